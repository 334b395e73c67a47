#pragma once
// Batches of independent SPD systems for the block-diagonal PCG tests (tests/backend/
// test_block_pcg.cpp on the CPU, tests/kernels/test_vulkan_block_pcg.cpp on the device): diagonal
// blocks of very different sizes and conditioning put together into one block-diagonal matrix,
// with each block's spectrum so that a test derives its tolerance from the block it checks.

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "backend/backend.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"
#include "support/conditioning.h"

namespace harmonia::testing {

using Sparse = Eigen::SparseMatrix<double>;

struct BlockBatch {
  std::vector<Sparse> blocks;     // The diagonal blocks (SPD unless a test made one not).
  detail::RowMajorSparse matrix;  // All of them on the diagonal.
  detail::BlockRows rows;         // Where each block sits.
  Eigen::MatrixXd rhs;            // rows x columns; blocks with b_k = 0 included on purpose.

  [[nodiscard]] int count() const { return rows.count(); }
  [[nodiscard]] Eigen::MatrixXd segment(const Eigen::MatrixXd& v, int block) const {
    return v.middleRows(rows.begin(block), rows.size(block));
  }
};

//! The cotangent Laplacian (positive semi-definite, constants in its kernel) of an nu x nv grid of
//! unit squares, each cut into two triangles, plus shift I: eigenvalues in [shift, about 8 +
//! shift], so the shift sets the condition number.
inline Sparse shifted_grid_laplacian(int nu, int nv, double shift) {
  const Sparse l = laplacian(developable_strip(nu, nv, nu, nv, 1e3), WeightScheme::cotangent);
  Sparse identity(l.rows(), l.cols());
  identity.setIdentity();
  return l + shift * identity;
}

//! The blocks on the diagonal of one matrix, in order; rhs gives the right-hand sides.
inline BlockBatch assemble_batch(std::vector<Sparse> blocks, Eigen::MatrixXd rhs) {
  BlockBatch batch;
  batch.rows.offsets = {0};
  std::vector<Eigen::Triplet<double>> entries;
  for (const Sparse& block : blocks) {
    const int first = batch.rows.offsets.back();
    for (int column = 0; column < block.outerSize(); ++column)
      for (Sparse::InnerIterator entry(block, column); entry; ++entry)
        entries.emplace_back(first + static_cast<int>(entry.row()), first + column, entry.value());
    batch.rows.offsets.push_back(first + static_cast<int>(block.rows()));
  }
  const int rows = batch.rows.offsets.back();
  batch.matrix.resize(rows, rows);
  batch.matrix.setFromTriplets(entries.begin(), entries.end());
  batch.matrix.makeCompressed();
  batch.blocks = std::move(blocks);
  batch.rhs = std::move(rhs);
  return batch;
}

//! Seven blocks: 0 a well-conditioned 4 x 3 grid (condition about 9), 1 an ill-conditioned 11 x 9
//! grid (about 8e4), 2 a 1 x 1 block, 3 an empty block, 4 a 5 x 5 grid whose right-hand side is
//! zero, 5 a diagonal spanning four decades (Jacobi-PCG solves it in one step), 6 a 15 x 15 grid
//! (about 800). Right-hand sides uniform in [-1, 1] (fixed seed), `columns` of them.
inline BlockBatch mixed_batch(int columns) {
  std::vector<Sparse> blocks;
  blocks.push_back(shifted_grid_laplacian(4, 3, 1.0));
  blocks.push_back(shifted_grid_laplacian(11, 9, 1e-4));
  Sparse one(1, 1);
  one.insert(0, 0) = 2.5;
  blocks.push_back(one);
  blocks.emplace_back(0, 0);
  blocks.push_back(shifted_grid_laplacian(5, 5, 0.1));
  Sparse diagonal(17, 17);
  for (int k = 0; k < 17; ++k) diagonal.insert(k, k) = std::pow(10.0, k / 4.0);
  blocks.push_back(diagonal);
  blocks.push_back(shifted_grid_laplacian(15, 15, 1e-2));
  int rows = 0;
  for (const Sparse& block : blocks) rows += static_cast<int>(block.rows());
  std::mt19937 generator(20240611u);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Eigen::MatrixXd rhs(rows, columns);
  for (Eigen::Index k = 0; k < rhs.size(); ++k) rhs.data()[k] = value(generator);
  BlockBatch batch = assemble_batch(std::move(blocks), std::move(rhs));
  batch.rhs.middleRows(batch.rows.begin(4), batch.rows.size(4)).setZero();
  return batch;
}

//! `count` small grids (1 x 1 to 5 x 4 squares: 4 to 30 unknowns) with shifts from 1e-2 to 1
//! drawn at random (fixed seed): many independent charts' worth of systems.
inline BlockBatch many_small_blocks(int count, int columns, std::uint32_t seed) {
  std::mt19937 generator(seed);
  std::uniform_int_distribution<int> nu(1, 5), nv(1, 4);
  std::uniform_real_distribution<double> log_shift(-2.0, 0.0), value(-1.0, 1.0);
  std::vector<Sparse> blocks;
  int rows = 0;
  for (int k = 0; k < count; ++k) {
    const int u = nu(generator), v = nv(generator);
    blocks.push_back(shifted_grid_laplacian(u, v, std::pow(10.0, log_shift(generator))));
    rows += static_cast<int>(blocks.back().rows());
  }
  Eigen::MatrixXd rhs(rows, columns);
  for (Eigen::Index k = 0; k < rhs.size(); ++k) rhs.data()[k] = value(generator);
  return assemble_batch(std::move(blocks), std::move(rhs));
}

//! The condition number of an SPD block with the margin its smallest-eigenvalue estimate needs
//! (support/conditioning.h); 1 for blocks of size 0 or 1.
inline double condition_bound(const Sparse& block) {
  if (block.rows() <= 1) return 1.0;
  const SpdSpectrum spectrum = spd_spectrum(block);
  return SpdSpectrum::kEstimateMargin * spectrum.condition();
}

//! condition_bound of the Jacobi-preconditioned block D^-1/2 A D^-1/2 (D the diagonal of A): what
//! Jacobi-PCG's convergence and its sensitivity to rounding depend on.
inline double jacobi_condition_bound(const Sparse& block) {
  const Eigen::VectorXd scale = block.diagonal().cwiseSqrt().cwiseInverse();
  const Sparse scaled = scale.asDiagonal() * block * scale.asDiagonal();
  return condition_bound(scaled);
}

//! Each column of each block solved directly (Eigen's SimplicialLDLT), in the batch's layout.
inline Eigen::MatrixXd direct_solutions(const BlockBatch& batch) {
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(batch.rhs.rows(), batch.rhs.cols());
  for (int k = 0; k < batch.count(); ++k) {
    if (batch.rows.size(k) == 0) continue;
    const Eigen::SimplicialLDLT<Sparse> ldlt(batch.blocks[k]);
    x.middleRows(batch.rows.begin(k), batch.rows.size(k)) = ldlt.solve(batch.segment(batch.rhs, k));
  }
  return x;
}

}  // namespace harmonia::testing
