#pragma once
//! \file solver_options.h
//! \brief Options shared by every map: which backend does the linear algebra, tolerances, progress.

#include <memory>
#include <optional>
#include <string>

#include "harmonia/types.h"

namespace harmonia {

namespace vulkan {
class Context;  // harmonia/vulkan_context.h (builds with the Vulkan backend).
}  // namespace vulkan

enum class BackendChoice {
  automatic,  //!< Vulkan where a device exists, else the CPU (with one message in the report).
  cpu,        //!< Eigen on the CPU (direct sparse factorization; CHOLMOD when built with it).
  vulkan,     //!< Vulkan compute; Status::unsupported in a build or on a machine without it.
};

//! Arithmetic on devices (the CPU backend always computes in double).
enum class DevicePrecision {
  //! fp32 kernels; linear solves refined in double on the host (the default: every device has it).
  float32,
  //! fp64 kernels; needs shaderFloat64 on the device, else the method returns Status::unsupported.
  float64,
};

//! How the conjugate gradients of iterative solves (the Vulkan backend's) are preconditioned.
enum class IterativePreconditioner {
  //! Smoothed-aggregation algebraic multigrid, one V-cycle per iteration (the default): the
  //! iteration count hardly grows with the mesh's size or the length of its limbs.
  multilevel,
  //! The diagonal: no set-up, cheap iterations, but their count grows with the square root of
  //! the condition number (hundreds to thousands on corpus meshes).
  jacobi,
};

struct SolverOptions {
  BackendChoice backend = BackendChoice::automatic;  //!< Where the linear algebra runs.
  double tolerance = 1e-10;     //!< Relative residual target for iterative solvers.
  int max_iterations = 20000;   //!< Iteration cap for iterative solvers.
  //! Preconditioner of iterative SPD solves (devices; the CPU factorizes directly).
  IterativePreconditioner preconditioner = IterativePreconditioner::multilevel;
  ProgressCallback progress;    //!< Optional; return false from it to cancel.
  DevicePrecision device_precision = DevicePrecision::float32;  //!< Vulkan arithmetic.
  //! Run every backend operation on the CPU fallback as well and put the largest difference
  //! (relative to the result's magnitude) in SolveReport::cross_check_error. For tests and
  //! debugging: it costs a CPU run on top of the device run.
  bool cross_check = false;
  //! Optional: the Vulkan device to compute on (an application's own, e.g. Context::wrap of its
  //! engine's device). Used by BackendChoice::vulkan and automatic; without it they create a
  //! context for the call. Ignored by BackendChoice::cpu and in builds without Vulkan.
  std::shared_ptr<vulkan::Context> vulkan_context;
};

//! How UVs are normalized after a map is computed (docs/cli.md, "Output conventions").
enum class UvNormalization {
  //! Area-weighted centroid at the origin, principal axis of the layout along u, faces
  //! counter-clockwise (no mirror image), total UV area equal to the 3D surface area.
  match_surface_area,
  //! As above, then scaled uniformly so the layout fits the unit square [0,1]^2 (texture atlases).
  unit_square,
  //! No normalization: the solver's raw output (e.g. the boundary circle of radius 1).
  none,
};

}  // namespace harmonia
