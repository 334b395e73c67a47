#pragma once
// Internal: CHOLMOD's view of an Eigen sparse matrix (no copy), for the CPU direct solvers.
#ifdef HARMONIA_HAVE_CHOLMOD

#include <cstddef>

#include <Eigen/SparseCore>
#include <cholmod.h>

namespace harmonia::detail {

//! A symmetric matrix seen through its lower triangle (stype -1), or its upper one (stype 1) when
//! `upper`. CHOLMOD only reads it. The supernodal factorization works on the upper triangle: an
//! upper matrix in natural order is factorized as stored, a lower one is transposed first.
inline cholmod_sparse lower_triangle_view(const Eigen::SparseMatrix<double>& matrix,
                                          bool upper = false) {
  auto& data = const_cast<Eigen::SparseMatrix<double>&>(matrix);
  cholmod_sparse view{};
  view.nrow = static_cast<std::size_t>(matrix.rows());
  view.ncol = static_cast<std::size_t>(matrix.cols());
  view.nzmax = static_cast<std::size_t>(matrix.nonZeros());
  view.p = data.outerIndexPtr();
  view.i = data.innerIndexPtr();
  view.nz = data.isCompressed() ? nullptr : data.innerNonZeroPtr();
  view.x = data.valuePtr();
  view.stype = upper ? 1 : -1;
  view.itype = CHOLMOD_INT;
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  view.sorted = 1;
  view.packed = data.isCompressed() ? 1 : 0;
  return view;
}

//! A dense column-major matrix (no copy; CHOLMOD only reads it).
inline cholmod_dense dense_view(const Eigen::MatrixXd& matrix) {
  cholmod_dense view{};
  view.nrow = static_cast<std::size_t>(matrix.rows());
  view.ncol = static_cast<std::size_t>(matrix.cols());
  view.nzmax = view.nrow * view.ncol;
  view.d = view.nrow;
  view.x = const_cast<double*>(matrix.data());
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  return view;
}

}  // namespace harmonia::detail

#endif
