// SubtreeParallelCholesky: the two halves below the top separator factorized side by side give the
// same solutions as one factorization, for a connected tree, a forest and several right-hand
// sides; an indefinite matrix fails; matrices without a useful split are left to one thread; and
// OpenBLAS's thread count is restored (SingleThreadedBlas).
#include <chrono>
#include <future>
#include <memory>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "fallback/direct_solvers.h"
#include "fallback/separator_first_ordering.h"
#include "fallback/single_threaded_blas.h"
#include "fallback/subtree_parallel_cholesky.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"
#include "mesh/adjacency_pattern.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

using detail::SingleThreadedBlas;
using detail::SubtreeParallelCholesky;
using SparseMatrix = Eigen::SparseMatrix<double>;

// A mesh Laplacian with 2 x 2 blocks [2 1; 1 2] (as the reduced angle system has), shifted to be
// positive definite: full symmetric storage.
SparseMatrix block_system(const Mesh& mesh) {
  const SparseMatrix scalar = laplacian(mesh, WeightScheme::cotangent);
  std::vector<Eigen::Triplet<double>> entries;
  const double block[2][2] = {{2.0, 1.0}, {1.0, 2.0}};
  for (int column = 0; column < scalar.outerSize(); ++column)
    for (SparseMatrix::InnerIterator entry(scalar, column); entry; ++entry)
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          entries.emplace_back(2 * entry.row() + a, 2 * column + b,
                               block[a][b] * (entry.value() + (entry.row() == column ? 0.01 : 0.0)));
  SparseMatrix matrix(2 * scalar.rows(), 2 * scalar.cols());
  matrix.setFromTriplets(entries.begin(), entries.end());
  return matrix;
}

// Two systems side by side with no entry between them (a forest of two trees).
SparseMatrix block_diagonal(const SparseMatrix& first, const SparseMatrix& second) {
  std::vector<Eigen::Triplet<double>> entries;
  for (const auto* part : {&first, &second}) {
    const Eigen::Index offset = part == &first ? 0 : first.rows();
    for (int column = 0; column < part->outerSize(); ++column)
      for (SparseMatrix::InnerIterator entry(*part, column); entry; ++entry)
        entries.emplace_back(offset + entry.row(), offset + column, entry.value());
  }
  SparseMatrix matrix(first.rows() + second.rows(), first.cols() + second.cols());
  matrix.setFromTriplets(entries.begin(), entries.end());
  return matrix;
}

// A postordered nested-dissection order of the symmetric `matrix` (without CHOLMOD, which has no
// nested dissection to offer, the postorder of its own numbering).
std::vector<int> elimination_order(const SparseMatrix& matrix) {
  const SparseMatrix lower = matrix.triangularView<Eigen::Lower>();
  std::vector<int> order = detail::nested_dissection_ordering(lower);
  if (order.empty()) {
    order.resize(static_cast<std::size_t>(matrix.rows()));
    std::iota(order.begin(), order.end(), 0);
  }
  return detail::postordered_ordering(lower, order);
}

// `matrix` renumbered in a postordered nested-dissection order: the lower triangle.
SparseMatrix in_elimination_order(const SparseMatrix& matrix) {
  const std::vector<int> order = elimination_order(matrix);
  Eigen::PermutationMatrix<Eigen::Dynamic> old_to_new(matrix.rows());
  for (std::size_t k = 0; k < order.size(); ++k) old_to_new.indices()[order[k]] = static_cast<int>(k);
  SparseMatrix renumbered(matrix.rows(), matrix.cols());
  renumbered = matrix.selfadjointView<Eigen::Lower>().twistedBy(old_to_new);
  return renumbered.triangularView<Eigen::Lower>();
}

// The solution by one CHOLMOD factorization of the whole matrix.
Eigen::MatrixXd reference_solution(const SparseMatrix& lower, const Eigen::MatrixXd& rhs) {
  const std::unique_ptr<detail::SparseSystemSolver> solver = detail::make_cholesky_solver();
  solver->analyze(lower);
  EXPECT_EQ(solver->factorize(lower).status, Status::ok);
  Eigen::MatrixXd solution;
  EXPECT_EQ(solver->solve(rhs, solution).status, Status::ok);
  return solution;
}

// Every split here needs the policy that lets harmonia hold OpenBLAS's thread count
// (harmonia/blas_threads.h); the library's default leaves it alone (test_blas_thread_policy.cpp).
class HoldBlasThreads : public ::testing::Environment {
 public:
  void SetUp() override {
    hold_.emplace(BlasThreadPolicy::hold_during_split_factorizations);
  }
  void TearDown() override { hold_.reset(); }

 private:
  std::optional<testing::ScopedBlasThreadPolicy> hold_;
};
[[maybe_unused]] ::testing::Environment* const kHoldBlasThreads =
    ::testing::AddGlobalTestEnvironment(new HoldBlasThreads);

bool can_split() {
  return std::thread::hardware_concurrency() >= 2 && SingleThreadedBlas::available();
}

TEST(SubtreeParallelCholesky, SolvesLikeOneFactorizationOfTheWhole) {
  if (!can_split()) GTEST_SKIP() << "one hardware thread or no OpenBLAS: no split is made";
  const SparseMatrix lower = in_elimination_order(block_system(planar_disk(20, 0.2)));
  const std::unique_ptr<SubtreeParallelCholesky> cholesky =
      SubtreeParallelCholesky::analyze(lower, {}, 100);
  ASSERT_NE(cholesky, nullptr);
  const SubtreeParallelCholesky::Shape shape = cholesky->shape();
  EXPECT_GT(shape.separator_rows, 0);
  const int below = shape.half_rows[0] + shape.half_rows[1];
  EXPECT_EQ(below + shape.separator_rows, lower.rows());
  EXPECT_GE(6 * std::min(shape.half_rows[0], shape.half_rows[1]), below);
  EXPECT_GT(shape.half_flops[0], 0.0);
  EXPECT_GT(shape.half_flops[1], 0.0);

  ASSERT_TRUE(cholesky->factorize(lower));
  const Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(lower.rows(), 3);
  const Eigen::MatrixXd solution = cholesky->solve(rhs);
  ASSERT_EQ(solution.rows(), lower.rows());
  const Eigen::MatrixXd reference = reference_solution(lower, rhs);
  EXPECT_LT((solution - reference).norm(), 1e-10 * reference.norm());
  const SparseMatrix full = lower.selfadjointView<Eigen::Lower>();
  EXPECT_LT((full * solution - rhs).norm(), 1e-10 * rhs.norm());

  // New values in the same pattern: a second factorization uses them.
  SparseMatrix scaled = lower;
  scaled *= 3.0;
  ASSERT_TRUE(cholesky->factorize(scaled));
  EXPECT_LT((cholesky->solve(rhs) - reference / 3.0).norm(), 1e-10 * reference.norm());
}

TEST(SubtreeParallelCholesky, AForestSplitsWithoutASeparator) {
  if (!can_split()) GTEST_SKIP() << "one hardware thread or no OpenBLAS: no split is made";
  const SparseMatrix lower = in_elimination_order(
      block_diagonal(block_system(planar_disk(12, 0.1)), block_system(hemisphere(10))));
  const std::unique_ptr<SubtreeParallelCholesky> cholesky =
      SubtreeParallelCholesky::analyze(lower, {}, 100);
  ASSERT_NE(cholesky, nullptr);
  EXPECT_EQ(cholesky->shape().separator_rows, 0);
  ASSERT_TRUE(cholesky->factorize(lower));
  const Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(lower.rows(), 2);
  const Eigen::MatrixXd reference = reference_solution(lower, rhs);
  EXPECT_LT((cholesky->solve(rhs) - reference).norm(), 1e-10 * reference.norm());
}

TEST(SubtreeParallelCholesky, AnIndefiniteMatrixFailsToFactorize) {
  if (!can_split()) GTEST_SKIP() << "one hardware thread or no OpenBLAS: no split is made";
  SparseMatrix lower = in_elimination_order(block_system(planar_disk(20, 0.2)));
  const std::unique_ptr<SubtreeParallelCholesky> cholesky =
      SubtreeParallelCholesky::analyze(lower, {}, 100);
  ASSERT_NE(cholesky, nullptr);
  // A negative pivot in the separator (last row) and, separately, in the first half.
  SparseMatrix last_negative = lower;
  last_negative.coeffRef(lower.rows() - 1, lower.rows() - 1) = -1.0;
  EXPECT_FALSE(cholesky->factorize(last_negative));
  SparseMatrix first_negative = lower;
  first_negative.coeffRef(0, 0) = -1.0;
  EXPECT_FALSE(cholesky->factorize(first_negative));
  EXPECT_TRUE(cholesky->factorize(lower));
}

TEST(SubtreeParallelCholesky, MatricesWithoutAUsefulSplitAreLeftToOneThread) {
  // Below the row threshold.
  const SparseMatrix small = in_elimination_order(block_system(planar_disk(20, 0.2)));
  EXPECT_EQ(SubtreeParallelCholesky::analyze(small), nullptr);
  // A tridiagonal matrix: its elimination tree is a path, with no two subtrees.
  const int size = 5000;
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < size; ++i) {
    entries.emplace_back(i, i, 4.0);
    if (i + 1 < size) entries.emplace_back(i + 1, i, -1.0);
  }
  SparseMatrix path(size, size);
  path.setFromTriplets(entries.begin(), entries.end());
  EXPECT_EQ(SubtreeParallelCholesky::analyze(path, {}, 100), nullptr);
}

// The matrix in its own numbering with the order given apart (as the reduced angle system hands
// it over): the same solutions.
TEST(SubtreeParallelCholesky, TakesTheOrderApartFromTheMatrix) {
  if (!can_split()) GTEST_SKIP() << "one hardware thread or no OpenBLAS: no split is made";
  const SparseMatrix full = block_system(planar_disk(20, 0.2));
  const SparseMatrix lower = full.triangularView<Eigen::Lower>();
  const std::unique_ptr<SubtreeParallelCholesky> cholesky =
      SubtreeParallelCholesky::analyze(lower, elimination_order(full), 100);
  ASSERT_NE(cholesky, nullptr);
  ASSERT_TRUE(cholesky->factorize(lower));
  const Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(lower.rows(), 2);
  const Eigen::MatrixXd reference = reference_solution(lower, rhs);
  EXPECT_LT((cholesky->solve(rhs) - reference).norm(), 1e-10 * reference.norm());
}

// The Cholesky solver given a postordered order: split on two threads above the threshold,
// renumbered and factorized in CHOLMOD's natural order below it; the same solutions either way.
TEST(SubtreeParallelCholesky, TheCholeskySolverSplitsLargeSystemsAndRenumbersSmallOnes) {
  for (const int rings : {60, 20}) {  // 2 x 10981 rows, then 2 x 1261.
    const SparseMatrix full = block_system(planar_disk(rings, 0.2));
    const SparseMatrix lower = full.triangularView<Eigen::Lower>();
    const bool large = lower.rows() >= SubtreeParallelCholesky::kDefaultMinimumRows;
    const std::unique_ptr<detail::SparseSystemSolver> solver = detail::make_cholesky_solver();
    solver->analyze_in_elimination_order(lower, elimination_order(full));
    if (can_split()) {
      EXPECT_EQ(solver->name().find("on two subtrees") != std::string::npos, large)
          << solver->name();
    }
    const int blas_threads = SingleThreadedBlas::threads_now();
    ASSERT_EQ(solver->factorize(lower).status, Status::ok);
    const Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(lower.rows(), 1);
    Eigen::MatrixXd solution;
    ASSERT_EQ(solver->solve(rhs, solution).status, Status::ok);
    EXPECT_EQ(SingleThreadedBlas::threads_now(), blas_threads);
    const Eigen::MatrixXd reference = reference_solution(lower, rhs);
    EXPECT_LT((solution - reference).norm(), 1e-10 * reference.norm()) << rings << " rings";
  }
}

// The halves of a separator-first ordering (rows 2v, 2v + 1 of each vertex v), the second half's
// order arriving late from another thread.
struct GivenHalves {
  std::vector<int> separator, first;
  std::vector<int> second;
};

GivenHalves halves_of(const Mesh& mesh) {
  detail::SeparatorFirstOrdering ordering;
  ordering.compute(detail::AdjacencyPattern(mesh.faces, mesh.vertex_count()).take_matrix());
  GivenHalves halves;
  const auto rows_of = [](const std::vector<int>& vertices) {
    std::vector<int> rows;
    for (const int v : vertices) rows.insert(rows.end(), {2 * v, 2 * v + 1});
    return rows;
  };
  halves.first = rows_of(ordering.side_order(0));
  halves.second = rows_of(ordering.side_order(1));
  std::vector<int> separator_vertices;
  for (std::size_t v = 0; v < ordering.parts().size(); ++v)
    if (ordering.parts()[v] == detail::SeparatorFirstOrdering::separator)
      separator_vertices.push_back(static_cast<int>(v));
  halves.separator = rows_of(separator_vertices);
  return halves;
}

std::shared_future<std::vector<int>> arriving_late(std::vector<int> rows) {
  return std::async(std::launch::async, [rows = std::move(rows)] {
           std::this_thread::sleep_for(std::chrono::milliseconds(50));
           return rows;
         }).share();
}

TEST(SubtreeParallelCholesky, FactorizesGivenHalvesWhileTheSecondIsStillOrdered) {
  if (!can_split()) GTEST_SKIP() << "one hardware thread or no OpenBLAS: no split is made";
  const Mesh mesh = planar_disk(60, 0.2);  // 2 x 10981 rows.
  const SparseMatrix lower = SparseMatrix(block_system(mesh).triangularView<Eigen::Lower>());
  const GivenHalves halves = halves_of(mesh);
  ASSERT_FALSE(halves.separator.empty());
  int meanwhile_runs = 0;
  const std::unique_ptr<SubtreeParallelCholesky> cholesky = SubtreeParallelCholesky::factorize_halves(
      lower, halves.separator, halves.first, arriving_late(halves.second),
      [&meanwhile_runs] { ++meanwhile_runs; });
  ASSERT_NE(cholesky, nullptr);
  EXPECT_EQ(meanwhile_runs, 1);
  const SubtreeParallelCholesky::Shape shape = cholesky->shape();
  EXPECT_EQ(shape.half_rows[0], static_cast<int>(halves.first.size()));
  EXPECT_EQ(shape.half_rows[1], static_cast<int>(halves.second.size()));
  EXPECT_EQ(shape.separator_rows, static_cast<int>(halves.separator.size()));

  const Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(lower.rows(), 2);
  const Eigen::MatrixXd reference = reference_solution(lower, rhs);
  EXPECT_LT((cholesky->solve(rhs) - reference).norm(), 1e-10 * reference.norm());
  // A refactorization with new values reuses the halves' analyses.
  SparseMatrix scaled = lower;
  scaled *= 2.0;
  ASSERT_TRUE(cholesky->factorize(scaled));
  EXPECT_LT((cholesky->solve(rhs) - reference / 2.0).norm(), 1e-10 * reference.norm());
}

// The caller's `meanwhile` runs while OpenBLAS is held to one thread; when it throws, the second
// half is waited for, the exception reaches the caller, and the count is restored.
TEST(SubtreeParallelCholesky, AThrowingMeanwhileLeavesTheThreadCountRestored) {
  if (!can_split()) GTEST_SKIP() << "one hardware thread or no OpenBLAS: no split is made";
  const Mesh mesh = planar_disk(60, 0.2);
  const SparseMatrix lower = SparseMatrix(block_system(mesh).triangularView<Eigen::Lower>());
  const GivenHalves halves = halves_of(mesh);
  ASSERT_FALSE(halves.separator.empty());
  const int blas_threads = SingleThreadedBlas::threads_now();
  int held_meanwhile = 0;
  EXPECT_THROW((void)SubtreeParallelCholesky::factorize_halves(
                   lower, halves.separator, halves.first, arriving_late(halves.second),
                   [&held_meanwhile] {
                     held_meanwhile = SingleThreadedBlas::threads_now();
                     throw std::runtime_error("the caller's work failed");
                   }),
               std::runtime_error);
  EXPECT_EQ(held_meanwhile, 1);
  EXPECT_EQ(SingleThreadedBlas::threads_now(), blas_threads);
}

TEST(SubtreeParallelCholesky, GivenHalvesJoinedByAnEntryAreRefused) {
  if (!can_split()) GTEST_SKIP() << "one hardware thread or no OpenBLAS: no split is made";
  const Mesh mesh = planar_disk(60, 0.2);
  const SparseMatrix lower = SparseMatrix(block_system(mesh).triangularView<Eigen::Lower>());
  GivenHalves halves = halves_of(mesh);
  // A separator vertex moved into the second half joins it to the first.
  halves.second.insert(halves.second.end(), halves.separator.end() - 2, halves.separator.end());
  halves.separator.resize(halves.separator.size() - 2);
  EXPECT_EQ(SubtreeParallelCholesky::factorize_halves(lower, halves.separator, halves.first,
                                                      arriving_late(halves.second)),
            nullptr);
}

// The Cholesky solver's factorize_in_halves: split on two threads above the threshold, the whole
// order awaited below it; the same solutions, and the caller's work run once either way.
TEST(SubtreeParallelCholesky, TheCholeskySolverFactorizesInHalvesOrWaitsForTheWholeOrder) {
#ifndef HARMONIA_HAVE_METIS
  GTEST_SKIP() << "built without METIS: no halves are given";
#endif
  for (const int rings : {60, 20}) {
    const Mesh mesh = planar_disk(rings, 0.2);
    const SparseMatrix lower = SparseMatrix(block_system(mesh).triangularView<Eigen::Lower>());
    const GivenHalves halves = halves_of(mesh);
    if (halves.separator.empty() && halves.second.empty()) {  // A small graph: ordered whole.
      EXPECT_EQ(rings, 20);
    }
    const std::unique_ptr<detail::SparseSystemSolver> solver = detail::make_cholesky_solver();
    int meanwhile_runs = 0;
    ASSERT_EQ(solver
                  ->factorize_in_halves(lower, halves.separator, halves.first,
                                        arriving_late(halves.second),
                                        [&meanwhile_runs] { ++meanwhile_runs; })
                  .status,
              Status::ok);
    EXPECT_EQ(meanwhile_runs, 1);
    if (can_split()) {
      EXPECT_EQ(solver->name().find("on two subtrees") != std::string::npos, rings == 60)
          << solver->name();
    }
    const Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(lower.rows(), 1);
    Eigen::MatrixXd solution;
    ASSERT_EQ(solver->solve(rhs, solution).status, Status::ok);
    const Eigen::MatrixXd reference = reference_solution(lower, rhs);
    EXPECT_LT((solution - reference).norm(), 1e-10 * reference.norm()) << rings << " rings";
    ASSERT_EQ(solver->factorize(lower).status, Status::ok);  // Refactorized with the analysis.
    ASSERT_EQ(solver->solve(rhs, solution).status, Status::ok);
    EXPECT_LT((solution - reference).norm(), 1e-10 * reference.norm()) << rings << " rings";
  }
}

TEST(SingleThreadedBlas, HoldsOneThreadWhileAGuardLivesAndRestoresTheCount) {
  if (!SingleThreadedBlas::available()) GTEST_SKIP() << "the BLAS is not OpenBLAS";
  const int before = SingleThreadedBlas::threads_now();
  {
    const SingleThreadedBlas outer;
    EXPECT_EQ(SingleThreadedBlas::threads_now(), 1);
    std::thread other([] {
      const SingleThreadedBlas inner;  // A second guard on another thread: nested.
      EXPECT_EQ(SingleThreadedBlas::threads_now(), 1);
    });
    other.join();
    EXPECT_EQ(SingleThreadedBlas::threads_now(), 1);  // The outer guard still holds.
  }
  EXPECT_EQ(SingleThreadedBlas::threads_now(), before);
}

TEST(SingleThreadedBlas, AReleasedGuardGivesItsHoldUpOnce) {
  if (!SingleThreadedBlas::available()) GTEST_SKIP() << "the BLAS is not OpenBLAS";
  const int before = SingleThreadedBlas::threads_now();
  if (before == 1) GTEST_SKIP() << "OpenBLAS runs one thread here: a hold would not show";
  {
    SingleThreadedBlas guard;
    ASSERT_EQ(SingleThreadedBlas::threads_now(), 1);
    guard.release();
    EXPECT_EQ(SingleThreadedBlas::threads_now(), before);
    {
      SingleThreadedBlas outer;
      {
        SingleThreadedBlas inner;
        inner.release();
        inner.release();  // Once only: the outer guard still holds.
        EXPECT_EQ(SingleThreadedBlas::threads_now(), 1);
      }
      EXPECT_EQ(SingleThreadedBlas::threads_now(), 1);
    }
    EXPECT_EQ(SingleThreadedBlas::threads_now(), before);
  }  // The released guard's destructor leaves the count alone.
  EXPECT_EQ(SingleThreadedBlas::threads_now(), before);
}

}  // namespace
}  // namespace harmonia
