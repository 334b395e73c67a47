#pragma once
// Internal: the angle validity constraints shared by ABF (chapter 2) and linear ABF (chapter 3).
//
// Corner numbering: corner c = 3 f + k is the angle of face f at vertex faces(f, k); angle vectors
// have 3F entries in that order. Around an interior vertex v, each incident face contributes its
// angle at v (central), the angle at the next corner of the face (the wheel's "left" angle beta,
// (2.3)) and the one at the previous corner (the "right" angle gamma).
//
// Constraint rows, always in this order:
//   [0, F)                 triangle consistency (2.2): x_a + x_b + x_c - pi
//   [F, F + I)             vertex consistency (2.1): sum of central angles - 2 pi (interior v)
//   [F + I, F + 2 I)       wheel consistency, log-sine form (2.11):
//                          sum log sin beta - log sin gamma (interior v)
//   [F + 2 I, F + 2 I + K) the active boundary rows (2.6), if any: sum of angles at boundary
//                          vertex - t pi, for the K boundary vertices passed in.
// with I interior vertices numbered in increasing vertex order. The Jacobian of the wheel rows is
// cot beta / -cot gamma: exactly the linearized wheel condition (3.7) of linear ABF.

#include <vector>

#include <Eigen/Core>

#include "backend/backend.h"
#include "harmonia/mesh.h"

namespace harmonia::detail {

// Topology of the angle problem of a disk mesh (built once; the mesh must be a valid disk).
struct AngleTopology {
  int face_count = 0;
  int vertex_count = 0;
  std::vector<int> interior_vertices;  // Increasing.
  std::vector<int> interior_index;     // vertex -> index among interior_vertices, or -1.
  std::vector<int> boundary_vertices;  // The boundary loop's order.
  // Corners around each vertex: CSR by vertex (vertex_corner_offsets: V + 1).
  std::vector<int> vertex_corner_offsets, vertex_corners;

  [[nodiscard]] int corner_count() const { return 3 * face_count; }
  [[nodiscard]] int interior_count() const { return static_cast<int>(interior_vertices.size()); }
};

// `boundary_loop`: the mesh's one boundary loop (validate_disk_input's result).
[[nodiscard]] AngleTopology build_angle_topology(const Mesh& mesh,
                                                 const std::vector<int>& boundary_loop);

// The 3D corner angles (3F).
[[nodiscard]] Eigen::VectorXd corner_angles(const Mesh& mesh);

// The ABF target angles (2.8): corner angles rescaled to sum 2 pi around interior vertices.
[[nodiscard]] Eigen::VectorXd rescaled_angles(const AngleTopology& topology,
                                              const Eigen::VectorXd& angles);

// Constraint values h(x) and Jacobian J(x) at `angles` (rows as documented above). The Jacobian's
// pattern depends only on the topology and `active_boundary` (so it can be uploaded once and its
// values refreshed); its values are in CSR order of a RowMajorSparse.
struct AngleConstraints {
  Eigen::VectorXd values;  // h(x)
  RowMajorSparse jacobian;  // J(x), rows x 3F.
};
[[nodiscard]] AngleConstraints evaluate_angle_constraints(
    const AngleTopology& topology, const Eigen::VectorXd& angles,
    const std::vector<int>& active_boundary = {}, double boundary_t = 2.0);

// h(x) alone, for a residual check (no Jacobian built).
[[nodiscard]] Eigen::VectorXd angle_constraint_values(const AngleTopology& topology,
                                                      const Eigen::VectorXd& angles,
                                                      const std::vector<int>& active_boundary = {},
                                                      double boundary_t = 2.0);

// Largest |h| over the triangle, vertex and wheel rows (and the given active boundary rows).
[[nodiscard]] double constraint_violation(const AngleConstraints& constraints);

}  // namespace harmonia::detail
