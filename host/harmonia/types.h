#pragma once
//! \file types.h
//! \brief Status codes, the error type, solve reports and progress callbacks shared by every method.
//!
//! Convention (see docs/cpp-api.md, "Errors"): outcomes that depend on the mesh or on the numbers
//! (bad input, not a disk, no convergence, flipped triangles) are returned as a Status inside a
//! report; only failures of the environment (a file that cannot be opened or written, a malformed
//! file, a device that is lost or out of memory) are thrown as harmonia::Error.

#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace harmonia {

//! What happened. `to_string` names every value (a switch without default, built with -Werror=switch).
enum class Status {
  ok,                  //!< Success.
  invalid_input,       //!< Bad numbers or indices in the input (the message names the vertex/face).
  parse_error,         //!< A mesh file could not be parsed (the message names file and line or byte).
  io_error,            //!< A file could not be opened, read or written.
  not_a_disk,          //!< The method needs a disk (one boundary loop, genus 0); see `harmonia cut`.
  not_a_sphere,        //!< The method needs a closed genus-0 surface (spherical maps).
  non_manifold,        //!< Non-manifold edge or vertex, or inconsistent orientation.
  not_converged,       //!< An iterative solver stopped at its iteration cap above tolerance.
  numerical_failure,   //!< A factorization failed, or a result was not finite.
  flipped_triangles,   //!< The map is computed but has flipped (or zero-area) triangles.
  cancelled,           //!< The progress callback asked to stop.
  unsupported,         //!< An option or feature is not available on this backend or build.
  device_failure,      //!< The compute device failed (device lost, out of device memory, ...).
};

//! Short lowercase name of a status, e.g. "not_a_disk".
[[nodiscard]] std::string_view to_string(Status status);

//! Exception for environment failures (files, devices). Carries the Status for programmatic use.
class Error : public std::runtime_error {
 public:
  Error(Status status, const std::string& message) : std::runtime_error(message), status_(status) {}
  [[nodiscard]] Status status() const noexcept { return status_; }

 private:
  Status status_;
};

//! Which implementation of the linear algebra ran.
enum class BackendKind { cpu, vulkan };
[[nodiscard]] std::string_view to_string(BackendKind kind);

//! Wall-clock time of one named phase of a method (e.g. "assembly", "factorization", "solve").
struct PhaseTiming {
  std::string phase;
  double seconds = 0.0;
};

//! Report that comes with every result.
struct SolveReport {
  Status status = Status::ok;        //!< Overall outcome.
  std::string message;               //!< Human-readable detail; empty when status is ok.
  BackendKind backend = BackendKind::cpu;  //!< Backend that did the linear algebra.
  std::string solver;                //!< e.g. "cholmod-supernodal", "eigen-simplicial-ldlt", "pcg".
  std::string device;                //!< The backend's own description, e.g. the GPU's name.
  //! One line on how the backend was chosen when that matters, e.g. why `automatic` ran on the CPU
  //! ("no hardware Vulkan GPU: ..."); empty otherwise. Not an error: status stays ok.
  std::string backend_notice;
  std::string precision = "double";  //!< "double", or "float (refined in double)" on Vulkan.
  int iterations = 0;                //!< Solver iterations (0 for direct solvers); summed over solves.
  int rounds = 0;                    //!< Outer rounds (quasi-harmonic iterations, Newton steps).
  double residual = 0.0;             //!< Largest relative residual ||Ax-b||/||b|| over all solves.
  //! Angle-based methods: the largest violation of the angle constraints (triangle, vertex,
  //! wheel, active boundary) by the final angles, in radians (wheel: in log-sine units).
  double constraint_residual = 0.0;
  int flipped_triangles = 0;         //!< Triangles with negative signed area in the result.
  //! Triangles with zero area in the result: exactly, or within the rounding of their corners.
  int degenerate_triangles = 0;
  int boundary_self_intersections = 0;  //!< Pairs of crossing boundary edges in the result.
  double cross_check_error = 0.0;    //!< Worst backend-vs-fallback difference when cross-checking.
  std::vector<PhaseTiming> timings;  //!< Per-phase wall-clock times, in order.
  //! What the method did instead of its default because the default would have failed, in order,
  //! one line each (e.g. a shortened step of a free-boundary map and why); empty when nothing.
  std::vector<std::string> fallbacks;

  [[nodiscard]] bool ok() const noexcept { return status == Status::ok; }
  //! Total of all recorded phases, in seconds.
  [[nodiscard]] double total_seconds() const noexcept;
};

//! Progress information passed to a ProgressCallback.
struct Progress {
  std::string_view stage;  //!< e.g. "assembly", "factorization", "round 2/5".
  int step = 0;            //!< Current step, starting at 0.
  int total = 0;           //!< Number of steps (0 when unknown).
};

//! Called during long work. Return false to cancel; the method then returns Status::cancelled.
using ProgressCallback = std::function<bool(const Progress&)>;

}  // namespace harmonia
