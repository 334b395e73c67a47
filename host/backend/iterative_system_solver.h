#pragma once
// Internal: a SparseSystemSolver built on a backend's Krylov methods, for backends without a
// direct factorization. SPD -> Jacobi-PCG, symmetric indefinite -> MINRES, general -> PCG on the
// normal equations A^T A x = A^T b (no LU on devices). The solution passed in is the warm start.

#include <memory>

#include "backend/backend.h"

namespace harmonia::detail {

[[nodiscard]] std::unique_ptr<SparseSystemSolver> make_iterative_solver(
    Backend& backend, MatrixKind kind, const IterativeSettings& settings,
    const ProgressCallback& progress);

}  // namespace harmonia::detail
