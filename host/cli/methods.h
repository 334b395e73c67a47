#pragma once
//! \file methods.h
//! \brief The planar methods as the program runs them (shared by `unwrap` and `demo`): the
//! library's flatten_disk (harmonia/flattening.h) with the program's backend and device choice.

#include <string>

#include "harmonia/flattening.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"

namespace harmonia::cli {

//! The solver options of every command: the backend asked for, the progress callback, and the
//! Vulkan device $HARMONIA_VULKAN_DEVICE names (docs/vulkan.md, "Choosing the device").
[[nodiscard]] SolverOptions program_solver_options(BackendChoice backend,
                                                   const ProgressCallback& progress);

//! The backend a --backend value names: "cpu", "vulkan", anything else (the commands allow only
//! "auto" besides) automatic.
[[nodiscard]] BackendChoice backend_choice(const std::string& name);

using MethodKind = FlatteningMethod;

//! Everything that selects and configures one method run: the method and the backend.
struct MethodChoice : FlatteningChoice {
  BackendChoice backend = BackendChoice::automatic;
  IterativePreconditioner preconditioner = IterativePreconditioner::multilevel;
};

//! --preconditioner's value: multilevel (default) or jacobi.
[[nodiscard]] IterativePreconditioner preconditioner_choice(const std::string& name);
//! The help of --preconditioner, shared by the commands that take it.
extern const char* const preconditioner_help;

//! Runs the chosen method with the program's solver options (flatten_disk).
[[nodiscard]] MapResult run_method(const Mesh& mesh, const MethodChoice& choice,
                                   const ProgressCallback& progress,
                                   AngleFigures* angle_figures = nullptr);

}  // namespace harmonia::cli
