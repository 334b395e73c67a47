#pragma once
// Internal: direct sparse solvers of the CPU backend (SparseSystemSolver implementations).
//
// analyze() runs the symbolic factorization (fill-reducing ordering, elimination tree) once per
// pattern; factorize() only redoes the numeric part, so a map that re-assembles the same pattern
// (quasi-harmonic rounds, update_geometry) pays for the ordering once.

#include <memory>
#include <mutex>
#include <vector>

#include "backend/backend.h"

namespace harmonia::detail {

//! Sparse Cholesky for SPD matrices: CHOLMOD supernodal LLT when the build has CHOLMOD, else
//! Eigen's simplicial LDLT. factorize() reports numerical_failure when the matrix is not SPD.
[[nodiscard]] std::unique_ptr<SparseSystemSolver> make_cholesky_solver();

//! CHOLMOD factorizes a symmetric positive definite system of this many rows or more
//! supernodal; a smaller one as CHOLMOD itself chooses after its analysis (CHOLMOD_AUTO):
//! simplicial (column by column, no BLAS) unless the factor is dense enough for dense kernels to
//! pay (flops per factor entry at least 40, CHOLMOD's supernodal_switch). Small sparse systems'
//! supernodes are too small for BLAS, and a BLAS call from one of several threads factorizing
//! side by side (a texture atlas flattens its charts so) may wake OpenBLAS's pool: on the
//! systems of linear ABF on atlas charts (the reduced angle system and the reconstruction's
//! Laplacian) the simplicial factorization was faster up to about 3,000 rows and the supernodal
//! one from about 5,000 (one BLAS thread, CPU time of the whole map). But a chart of a CAD model
//! whose vertices lie mostly on its boundary couples u and v nearly everywhere: its 2,350-row
//! system had a factor 22 % dense (400 Mflop), 0.19 s simplicial against 0.02 s supernodal.
inline constexpr Eigen::Index kCholmodSimplicialBelowRows = 4000;

//! An approximate minimum degree ordering of the symmetric `pattern` (CHOLMOD's AMD, the ordering
//! its analysis would choose for such a matrix), for SparseSystemSolver::analyze_with_ordering.
//! Empty without CHOLMOD (the solvers then order the unknowns themselves).
[[nodiscard]] std::vector<int> fill_reducing_ordering(const Eigen::SparseMatrix<double>& pattern);

//! A nested dissection ordering of `pattern` (METIS through CHOLMOD; AMD where CHOLMOD lacks
//! METIS). Slower to compute than AMD (about 2 s against 0.3 s for a 400K-vertex mesh graph) but
//! a mesh's factor then needs about a third of the arithmetic: worth it for systems with blocks
//! of unknowns per vertex, or when the ordering is computed while other work runs. A pattern of
//! fewer than 5,000 rows is ordered by AMD, which is cheaper there and fills about as little.
[[nodiscard]] std::vector<int> nested_dissection_ordering(
    const Eigen::SparseMatrix<double>& pattern);

//! Held while METIS runs: METIS draws from the C library's process-wide random numbers, so two of
//! its calls at the same time would interleave their draws and give orders that change from run
//! to run. Every METIS call of the library takes it.
[[nodiscard]] std::unique_lock<std::mutex> metis_lock();

//! `ordering` (ordering[k]: the row eliminated k-th) of the symmetric `pattern` (its lower
//! triangle is read), rearranged into a postorder of its elimination tree (elimination_tree.h):
//! the same fill, with every supernode's columns contiguous, for
//! SparseSystemSolver::analyze_in_elimination_order. `ordering` itself when it is not a
//! permutation of the rows.
[[nodiscard]] std::vector<int> postordered_ordering(const Eigen::SparseMatrix<double>& pattern,
                                                    const std::vector<int>& ordering);

//! Sparse LU with COLAMD ordering for general (non-symmetric or indefinite) matrices.
[[nodiscard]] std::unique_ptr<SparseSystemSolver> make_lu_solver();

}  // namespace harmonia::detail
