#pragma once
// Internal: the pieces every planar map shares — input validation, phase timing with progress and
// cancellation, the Dirichlet system (solve/dirichlet_system.h), and the finishing of a result
// (finite check, normalization, validity counts).

#include <chrono>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "backend/backend.h"
#include "harmonia/boundary.h"
#include "harmonia/map_result.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"
#include "solve/dirichlet_system.h"

namespace harmonia::detail {

//! Checks that `mesh` is a disk (indices, finite coordinates, manifold, one boundary loop, genus 0)
//! and returns its boundary loop (mesh to the left, starting at its smallest vertex). On failure
//! sets report.status/message (pointing at `harmonia cut` for non-disks) and returns an empty loop.
//! The same as validate_mesh_arrays followed by validate_disk_topology.
[[nodiscard]] std::vector<int> validate_disk_input(const Mesh& mesh, SolveReport& report);

//! The first half of validate_disk_input: face indices in range and finite coordinates, all that
//! assembling an operator needs (so assembly may start while the topology is being checked).
[[nodiscard]] bool validate_mesh_arrays(const Mesh& mesh, SolveReport& report);

//! The second half: the disk topology of a mesh with valid arrays; returns the boundary loop.
[[nodiscard]] std::vector<int> validate_disk_topology(const Mesh& mesh, SolveReport& report);

//! Checks the boundary options against the mesh: for `given`, at least 2 distinct vertices in
//! range, one finite uv row per vertex. Sets invalid_input and returns false otherwise.
[[nodiscard]] bool validate_boundary_options(const Mesh& mesh, const BoundaryOptions& options,
                                             SolveReport& report);

//! The backend for the options; on failure sets report.status = unsupported and returns nullptr.
[[nodiscard]] std::unique_ptr<Backend> choose_backend(const SolverOptions& options,
                                                      SolveReport& report);

//! The mesh's operator pattern (detail::AdjacencyPattern: diagonal and face-sharing pairs, zero
//! values) and a fill-reducing ordering of its vertices (empty without CHOLMOD). Needs only the
//! faces, so a mapper computes it on a second thread while it validates and assembles.
struct OperatorPattern {
  Eigen::SparseMatrix<double> pattern;
  std::vector<int> vertex_ordering;
};
//! `nested_dissection`: order with nested_dissection_ordering instead of AMD.
[[nodiscard]] OperatorPattern operator_pattern(const Mesh& mesh, bool nested_dissection = false);

//! Times named phases into report.timings and reports them to the progress callback.
class PhaseClock {
 public:
  PhaseClock(SolveReport& report, const ProgressCallback& progress)
      : report_(report), progress_(progress) {}
  //! Ends the running phase (if any) and starts `phase`. Returns false, with report.status set to
  //! cancelled, when the progress callback asks to stop.
  [[nodiscard]] bool start(std::string_view phase, int step = 0, int total = 0);
  //! Ends the running phase.
  void stop();
  ~PhaseClock() { stop(); }

 private:
  SolveReport& report_;
  ProgressCallback progress_;
  std::string phase_;
  std::chrono::steady_clock::time_point started_;
  bool running_ = false;
};

//! Start of every mapper's update_geometry: clears the setup report and checks that `vertices`
//! has one finite row per vertex of `mesh`. Returns false (invalid_input in `setup`) otherwise.
[[nodiscard]] bool accept_new_geometry(const Mesh& mesh, const Eigen::MatrixX3d& vertices,
                                       SolveReport& setup);

//! Brings a layout computed on a unit-scaled mesh (mesh/power_of_two_scale.h: the input's
//! vertices times `scale`) back to the input's units: divided by the scale (exactly, a power of
//! two) when its size is the model's, that is normalized to the surface area, or raw with
//! `raw_in_model_units` (a free-boundary map whose pins sit at their 3D distance); left as it is
//! when fitted to the unit square, or raw on a boundary of the caller's (a circle of radius 1).
void to_model_units(Eigen::MatrixX2d& uv, double scale, UvNormalization normalization,
                    bool raw_in_model_units);

//! Finishes a map: non-finite UVs -> numerical_failure with an empty uv; otherwise normalizes,
//! counts flipped/zero-area triangles and the self-intersections of the boundary `loop` (the
//! mesh's one boundary loop, known to every mapper), and sets flipped_triangles when there are
//! flipped or zero-area triangles (the UVs are kept).
void finish_map(const Mesh& mesh, const std::vector<int>& loop, UvNormalization normalization,
                Eigen::MatrixX2d& uv, SolveReport& report, PhaseClock& clock);

}  // namespace harmonia::detail
