// Two halves of the elimination tree factorized side by side (subtree_parallel_cholesky.h).

#include "fallback/subtree_parallel_cholesky.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <functional>
#include <future>
#include <numeric>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "fallback/bordered_cholesky.h"
#include "fallback/elimination_tree.h"
#include "fallback/page_prefault.h"
#include "fallback/serial_openmp_regions.h"
#include "fallback/single_threaded_blas.h"
#include "mesh/helper_tasks.h"

#ifdef HARMONIA_HAVE_LAPACK
// BLAS and LAPACK (Fortran interface; the trailing arguments are the lengths of the character
// arguments).
extern "C" {
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* beta, double* c, const int* ldc,
            std::size_t uplo_length, std::size_t trans_length);
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info,
             std::size_t uplo_length);
}
#endif

namespace harmonia::detail {
namespace {

// Each half must hold at least this fraction of the rows below the separator: a smaller one
// leaves the other thread with nearly all the work.
constexpr double kSmallestHalf = 1.0 / 6.0;
// The separator's dense work (two symmetric products and a Cholesky factorization, about 2 s^3
// flops for s rows) may take at most half the time of the larger half's sparse factorization.
// Dense BLAS on the separator runs about 8 times faster per flop than the small supernodes of a
// mesh's sparse factor (40 against 5 Gflop/s on the 2-core machine), so its flops may be up to 4
// times the half's.
constexpr double kLargestSeparatorWork = 4.0;

// Dense LAPACK on the separator's block; absent without LAPACK, where no split is made.
#ifdef HARMONIA_HAVE_LAPACK
constexpr bool kHaveDenseLapack = true;

// product = R R^T for a square R (lower triangle written).
void lower_square(const Eigen::MatrixXd& r, Eigen::MatrixXd& product) {
  const auto n = static_cast<int>(r.rows());
  if (n == 0) return;
  const double one = 1.0, zero = 0.0;
  dsyrk_("L", "N", &n, &n, &one, r.data(), &n, &zero, product.data(), &n, 1, 1);
}

// The Cholesky factor of `matrix` (lower triangle read and overwritten); false when it is not
// positive definite.
bool dense_cholesky(Eigen::MatrixXd& matrix) {
  const auto n = static_cast<int>(matrix.rows());
  int info = 0;
  if (n > 0) dpotrf_("L", &n, matrix.data(), &n, &info, 1);
  return info == 0;
}

#else
constexpr bool kHaveDenseLapack = false;
void lower_square(const Eigen::MatrixXd&, Eigen::MatrixXd&) {}
bool dense_cholesky(Eigen::MatrixXd&) { return false; }
#endif

// Which half (0 or 1) each row below the separator belongs to, and where the separator begins;
// empty `half` when the tree has no such split.
struct TreeSplit {
  std::vector<signed char> half;  // Rows [0, separator_begin): 0 or 1.
  int separator_begin = 0;
  std::array<int, 2> half_rows = {0, 0};
};

TreeSplit split_tree(const std::vector<int>& parent) {
  TreeSplit split;
  const auto size = static_cast<int>(parent.size());
  std::vector<int> child_count(static_cast<std::size_t>(size), 0);
  std::vector<int> subtree_rows(static_cast<std::size_t>(size), 1);
  std::vector<int> roots;
  for (int node = 0; node < size; ++node) {
    const int up = parent[static_cast<std::size_t>(node)];
    if (up < 0) {
      roots.push_back(node);
    } else {
      ++child_count[static_cast<std::size_t>(up)];
      subtree_rows[static_cast<std::size_t>(up)] += subtree_rows[static_cast<std::size_t>(node)];
    }
  }
  // The top path: from the single root down while each node has one child (in a postorder, the
  // node just before it). A forest has no path; its roots are the subtrees.
  std::vector<int> subtrees;
  int separator_begin = size;
  if (roots.size() == 1) {
    int node = roots.front();
    while (child_count[static_cast<std::size_t>(node)] == 1) {
      if (node == 0 || parent[static_cast<std::size_t>(node) - 1] != node) return split;
      --node;
    }
    if (child_count[static_cast<std::size_t>(node)] == 0) return split;  // A path.
    separator_begin = node;
    for (int row = 0; row < node; ++row)
      if (parent[static_cast<std::size_t>(row)] == node) subtrees.push_back(row);
  } else {
    subtrees = roots;
  }
  // In a postorder each subtree is the range of rows ending at its root; together they must
  // cover the rows below the separator.
  int covered = 0;
  for (const int root : subtrees) {
    if (root - subtree_rows[static_cast<std::size_t>(root)] + 1 != covered) return split;
    covered = root + 1;
  }
  if (covered != separator_begin) return split;
  // The largest subtrees first, each to the lighter half.
  std::sort(subtrees.begin(), subtrees.end(), [&](int a, int b) {
    return subtree_rows[static_cast<std::size_t>(a)] > subtree_rows[static_cast<std::size_t>(b)];
  });
  split.half.assign(static_cast<std::size_t>(separator_begin), 0);
  for (const int root : subtrees) {
    const int half = split.half_rows[0] <= split.half_rows[1] ? 0 : 1;
    const int rows = subtree_rows[static_cast<std::size_t>(root)];
    std::fill(split.half.begin() + (root - rows + 1), split.half.begin() + root + 1,
              static_cast<signed char>(half));
    split.half_rows[static_cast<std::size_t>(half)] += rows;
  }
  split.separator_begin = separator_begin;
  if (std::min(split.half_rows[0], split.half_rows[1]) < kSmallestHalf * separator_begin)
    split.half.clear();
  return split;
}

}  // namespace

struct SubtreeParallelCholesky::Impl {
  int size = 0;
  // Row of the caller's matrix -> its place in the elimination order (empty: the identity).
  std::vector<int> elimination_position;
  std::vector<int> elimination_order;  // Its inverse: the caller's row eliminated k-th.
  int separator_begin = 0;
  int separator_rows = 0;
  // Per half: its rows of A (increasing), its bordered matrix B_i (upper triangle; rows of the
  // half, then the separator's) with the position in A's values of each stored entry, and its
  // factorization.
  struct Half {
    std::vector<int> rows;
    Eigen::SparseMatrix<double> matrix;
    std::vector<int> source;
    std::unique_ptr<BorderedCholesky> factor;
    Eigen::MatrixXd border;  // R_i.
  };
  std::array<Half, 2> halves;
  // A_SS's stored entries: (row, column) within the separator and position in A's values.
  std::vector<std::array<int, 3>> separator_entries;
  Eigen::MatrixXd separator_factor;  // L_S (lower triangle) after factorize().

  // Runs work(0) here and work(1) on a second thread, with OpenBLAS held to one thread per call
  // and each thread's OpenMP regions (CHOLMOD's) kept on that thread: the two threads already fill
  // both cores.
  // `meanwhile`, if any, runs here after work(0), while work(1) may still run.
  template <typename Work>
  static auto on_both_halves(const Work& work, const std::function<void()>& meanwhile = {}) {
    SingleThreadedBlas single_threaded_blas;
    const auto serial = [&work](int half) {
      const SerialOpenMpRegions serial_regions;
      return work(half);
    };
    auto second = start_beside([&serial] { return serial(1); });
    auto first = serial(0);
    if (meanwhile) meanwhile();
    // This thread is done: the other half's remaining BLAS calls (its largest supernodes come
    // last) may use OpenBLAS's threads again, on this thread's core.
    single_threaded_blas.release();
    return std::array<decltype(first), 2>{std::move(first), second.get()};
  }

  // The caller's rows of the split found in the elimination tree: each half's rows in
  // elimination order, then the separator's.
  bool build(const Eigen::SparseMatrix<double>& lower, const TreeSplit& split) {
    size = static_cast<int>(lower.rows());
    separator_begin = split.separator_begin;
    separator_rows = size - separator_begin;
    const auto original_row = [this](int position) {
      return elimination_position.empty() ? position
                                          : elimination_order[static_cast<std::size_t>(position)];
    };
    std::array<std::vector<int>, 2> members;
    for (int position = 0; position < separator_begin; ++position) {
      const auto h = static_cast<std::size_t>(split.half[static_cast<std::size_t>(position)]);
      halves[h].rows.push_back(position);
      members[h].push_back(original_row(position));
    }
    for (auto& member : members)
      for (int position = separator_begin; position < size; ++position)
        member.push_back(original_row(position));
    const auto built = on_both_halves([&](int h) {
      return build_half(lower, halves[static_cast<std::size_t>(h)],
                        members[static_cast<std::size_t>(h)]);
    });
    if (!built[0] || !built[1]) return false;
    collect_separator_entries(lower, {members[0].end() - separator_rows, members[0].end()});
    return true;
  }

  // Half `half`'s bordered matrix B_i, stored as its upper triangle (which CHOLMOD factorizes
  // without a transpose): `members` lists the caller's rows of the half in elimination order,
  // then the separator's. The entry of bordered rows a < b goes to column b, row a: a counting
  // pass, a filling pass, then each (short) column sorted by row. False when an entry joins the
  // half to a row outside it and the separator.
  static bool build_half(const Eigen::SparseMatrix<double>& lower, Half& half,
                         const std::vector<int>& members) {
    const int* outer = lower.outerIndexPtr();
    const int* inner = lower.innerIndexPtr();
    const auto bordered_rows = static_cast<int>(members.size());
    const auto own_rows = static_cast<int>(half.rows.size());
    std::vector<int> local(static_cast<std::size_t>(lower.rows()), -1);
    for (int m = 0; m < bordered_rows; ++m)
      local[static_cast<std::size_t>(members[static_cast<std::size_t>(m)])] = m;
    // Calls visit(upper column, upper row, source) for the half's entries.
    const auto for_each_entry = [&](auto&& visit) {
      for (int m = 0; m < bordered_rows; ++m) {
        const int column = members[static_cast<std::size_t>(m)];
        for (int k = outer[column]; k < outer[column + 1]; ++k) {
          if (inner[k] < column) continue;  // The lower triangle only.
          const int target = local[static_cast<std::size_t>(inner[k])];
          if (target < 0) {
            if (m >= own_rows) continue;  // A separator column's entry in the other half.
            return false;
          }
          visit(std::max(target, m), std::min(target, m), k);
        }
      }
      return true;
    };
    half.matrix.resize(bordered_rows, bordered_rows);
    int* half_outer = half.matrix.outerIndexPtr();
    std::fill(half_outer, half_outer + bordered_rows + 1, 0);
    if (!for_each_entry([&](int c, int, int) { ++half_outer[c + 1]; })) return false;
    for (int c = 0; c < bordered_rows; ++c) half_outer[c + 1] += half_outer[c];
    half.matrix.resizeNonZeros(half_outer[bordered_rows]);
    int* half_inner = half.matrix.innerIndexPtr();
    half.source.assign(static_cast<std::size_t>(half_outer[bordered_rows]), 0);
    std::vector<int> next(half_outer, half_outer + bordered_rows);
    (void)for_each_entry([&](int c, int r, int k) {
      const int slot = next[static_cast<std::size_t>(c)]++;
      half_inner[slot] = r;
      half.source[static_cast<std::size_t>(slot)] = k;
    });
    for (int c = 0; c < bordered_rows; ++c)  // Insertion sort: a few entries per column.
      for (int slot = half_outer[c] + 1; slot < half_outer[c + 1]; ++slot)
        for (int j = slot; j > half_outer[c] && half_inner[j - 1] > half_inner[j]; --j) {
          std::swap(half_inner[j - 1], half_inner[j]);
          std::swap(half.source[static_cast<std::size_t>(j) - 1],
                    half.source[static_cast<std::size_t>(j)]);
        }
    gather(lower, half);
    return true;
  }

  // A_SS's stored entries (lower triangle, rows within the separator), for its Schur complement;
  // `separator`: the caller's rows of the separator in elimination order.
  void collect_separator_entries(const Eigen::SparseMatrix<double>& lower,
                                 const std::vector<int>& separator) {
    const int* outer = lower.outerIndexPtr();
    const int* inner = lower.innerIndexPtr();
    std::vector<int> local(static_cast<std::size_t>(lower.rows()), -1);
    for (std::size_t s = 0; s < separator.size(); ++s)
      local[static_cast<std::size_t>(separator[s])] = static_cast<int>(s);
    separator_entries.clear();
    for (std::size_t s = 0; s < separator.size(); ++s) {
      const int column = separator[s];
      for (int k = outer[column]; k < outer[column + 1]; ++k) {
        const int row = local[static_cast<std::size_t>(inner[k])];
        if (inner[k] < column || row < 0) continue;
        separator_entries.push_back(
            {std::max(row, static_cast<int>(s)), std::min(row, static_cast<int>(s)), k});
      }
    }
  }

  static void gather(const Eigen::SparseMatrix<double>& lower, Half& half) {
    const double* values = lower.valuePtr();
    double* target = half.matrix.valuePtr();
    for (std::size_t k = 0; k < half.source.size(); ++k) target[k] = values[half.source[k]];
  }

  // Half `half`'s symbolic analysis (CHOLMOD, natural order: the rows come postordered).
  bool analyze_half(Half& half) const {
    half.factor = make_bordered_cholesky();
    return half.factor != nullptr &&
           half.factor->analyze_in_elimination_order(half.matrix, separator_rows,
                                                     StoredTriangle::upper);
  }

  // Whether the separator's dense work is small next to the larger half's sparse work.
  [[nodiscard]] bool separator_pays(double larger_half_flops) const {
    return 2.0 * std::pow(static_cast<double>(separator_rows), 3) <=
           kLargestSeparatorWork * larger_half_flops;
  }

  bool analyze_halves() {
    const auto analyzed = on_both_halves(
        [this](int h) { return analyze_half(halves[static_cast<std::size_t>(h)]); });
    if (!analyzed[0] || !analyzed[1]) return false;
    return separator_pays(std::max(halves[0].factor->factorization_flops(),
                                   halves[1].factor->factorization_flops()));
  }

  // Half `half`'s values, its factorization, and R_i R_i^T (lower triangle); none when the
  // factorization failed.
  std::optional<Eigen::MatrixXd> factorize_half(const Eigen::SparseMatrix<double>& lower,
                                                Half& half) const {
    gather(lower, half);
    std::optional<Eigen::MatrixXd> product;
    if (!half.factor->factorize(half.matrix)) return product;
    half.border = half.factor->border_factor();
    product.emplace(Eigen::MatrixXd::Zero(separator_rows, separator_rows));
    lower_square(half.border, *product);
    return product;
  }

  bool factorize(const Eigen::SparseMatrix<double>& lower) {
    const auto products = on_both_halves(
        [&](int h) { return factorize_half(lower, halves[static_cast<std::size_t>(h)]); });
    return factorize_separator(lower, products);
  }

  // The halves given by the caller (a separator computed first, separator_first_ordering.h):
  // half 0 built, analyzed and factorized here while half 1's order may still be computed, half 1
  // on a second thread as soon as its order is ready.
  bool factorize_given_halves(const Eigen::SparseMatrix<double>& lower,
                              const std::vector<int>& separator,
                              const std::vector<int>& first_half,
                              const std::shared_future<std::vector<int>>& second_half,
                              const std::function<void()>& meanwhile) {
    size = static_cast<int>(lower.rows());
    separator_rows = static_cast<int>(separator.size());
    const auto first_rows = static_cast<int>(first_half.size());
    // Half 1's factor storage, handed to this thread once half 1 is analyzed: after its own half,
    // and before `meanwhile`, this thread maps in its pages while half 1 factorizes
    // (page_prefault.h).
    std::promise<std::pair<void*, std::size_t>> second_storage;
    std::future<std::pair<void*, std::size_t>> second_storage_ready = second_storage.get_future();
    std::atomic<bool> second_done = false;
    const auto prepare = [&](int h, const std::vector<int>& rows, int first_position) {
      Half& half = halves[static_cast<std::size_t>(h)];
      half.rows.resize(rows.size());
      std::iota(half.rows.begin(), half.rows.end(), first_position);
      std::vector<int> members = rows;
      members.insert(members.end(), separator.begin(), separator.end());
      std::optional<Eigen::MatrixXd> product;
      // Each half's analysis stands in for the other's in the separator's test (the halves of a
      // nested dissection are of similar work).
      if (!build_half(lower, half, members) || !analyze_half(half) ||
          !separator_pays(half.factor->factorization_flops()))
        return product;
      if (h == 1) second_storage.set_value(half.factor->allocate_factor_storage());
      return factorize_half(lower, half);
    };
    const auto second_half_work = [&] {
      // Whatever happens to half 1, the storage is handed over (empty at worst) and the
      // prefaulting stopped.
      struct Finish {
        std::promise<std::pair<void*, std::size_t>>& storage;
        std::atomic<bool>& done;
        ~Finish() {
          done = true;
          try {
            storage.set_value({nullptr, 0});
          } catch (const std::future_error&) {  // Handed over already.
          }
        }
      } finish{second_storage, second_done};
      return prepare(1, second_half.get(), first_rows);
    };
    const auto products = on_both_halves(
        [&](int h) { return h == 0 ? prepare(0, first_half, 0) : second_half_work(); }, [&] {
          // The pages first: the sooner they are mapped, the fewer half 1 stops for.
          const auto [storage, bytes] = second_storage_ready.get();
          if (storage != nullptr) prefault_backward(storage, bytes, second_done);
          if (meanwhile) meanwhile();
        });
    // The elimination order: half 0's rows, half 1's, the separator's; a permutation of the rows.
    elimination_order = first_half;
    const std::vector<int>& second = second_half.get();
    elimination_order.insert(elimination_order.end(), second.begin(), second.end());
    elimination_order.insert(elimination_order.end(), separator.begin(), separator.end());
    if (elimination_order.size() != static_cast<std::size_t>(size)) return false;
    elimination_position.assign(static_cast<std::size_t>(size), -1);
    for (int k = 0; k < size; ++k) {
      const int row = elimination_order[static_cast<std::size_t>(k)];
      if (row < 0 || row >= size || elimination_position[static_cast<std::size_t>(row)] >= 0)
        return false;
      elimination_position[static_cast<std::size_t>(row)] = k;
    }
    separator_begin = size - separator_rows;
    collect_separator_entries(lower, separator);
    return factorize_separator(lower, products);
  }

  // With both halves' products: the separator's Schur complement and its dense factor.
  bool factorize_separator(const Eigen::SparseMatrix<double>& lower,
                           const std::array<std::optional<Eigen::MatrixXd>, 2>& products) {
    if (!products[0] || !products[1]) return false;
    if (separator_rows == 0) return true;
    // The separator's Schur complement R_0 R_0^T + R_1 R_1^T - A_SS (lower triangle), factorized
    // in place (OpenBLAS's own threads are back).
    separator_factor = *products[0] + *products[1];
    const double* values = lower.valuePtr();
    for (const auto& [row, column, k] : separator_entries) separator_factor(row, column) -= values[k];
    return dense_cholesky(separator_factor);
  }

  // y = L^-1 b: each half's forward solve with a zero border gives its rows of y and z_i with
  // R_i z_i = -R_Si y_i; the separator's rows are then y_S = L_S^-1 (b_S + R_0 z_0 + R_1 z_1).
  Eigen::MatrixXd forward(const Eigen::MatrixXd& b) const {
    const Eigen::Index columns = b.cols();
    const auto parts = on_both_halves([&](int h) {
      const Half& half = halves[static_cast<std::size_t>(h)];
      const auto rows = static_cast<Eigen::Index>(half.rows.size());
      Eigen::MatrixXd bordered = Eigen::MatrixXd::Zero(rows + separator_rows, columns);
      for (Eigen::Index r = 0; r < rows; ++r)
        bordered.row(r) = b.row(half.rows[static_cast<std::size_t>(r)]);
      return half.factor->forward(bordered);
    });
    Eigen::MatrixXd y(size, columns);
    y.bottomRows(separator_rows) = b.bottomRows(separator_rows);
    for (int h = 0; h < 2; ++h) {
      const Half& half = halves[static_cast<std::size_t>(h)];
      const Eigen::MatrixXd& part = parts[static_cast<std::size_t>(h)];
      if (part.rows() != static_cast<Eigen::Index>(half.rows.size()) + separator_rows) return {};
      for (std::size_t r = 0; r < half.rows.size(); ++r)
        y.row(half.rows[r]) = part.row(static_cast<Eigen::Index>(r));
      if (separator_rows > 0)
        y.bottomRows(separator_rows) +=
            half.border.triangularView<Eigen::Lower>() * part.bottomRows(separator_rows);
    }
    if (separator_rows > 0)
      separator_factor.triangularView<Eigen::Lower>().solveInPlace(y.bottomRows(separator_rows));
    return y;
  }

  // x = L^-T y: x_S = L_S^-T y_S, then each half's backward solve with its border's rows set to
  // R_i^T x_S gives x_i = R_ii^-T (y_i - R_Si^T x_S).
  Eigen::MatrixXd backward(const Eigen::MatrixXd& y) const {
    const Eigen::Index columns = y.cols();
    Eigen::MatrixXd x(size, columns);
    x.bottomRows(separator_rows) = y.bottomRows(separator_rows);
    if (separator_rows > 0)
      separator_factor.triangularView<Eigen::Lower>().transpose().solveInPlace(
          x.bottomRows(separator_rows));
    const auto parts = on_both_halves([&](int h) {
      const Half& half = halves[static_cast<std::size_t>(h)];
      const auto rows = static_cast<Eigen::Index>(half.rows.size());
      Eigen::MatrixXd bordered(rows + separator_rows, columns);
      for (Eigen::Index r = 0; r < rows; ++r)
        bordered.row(r) = y.row(half.rows[static_cast<std::size_t>(r)]);
      if (separator_rows > 0)
        bordered.bottomRows(separator_rows) =
            half.border.triangularView<Eigen::Lower>().transpose() * x.bottomRows(separator_rows);
      return half.factor->backward(bordered);
    });
    for (int h = 0; h < 2; ++h) {
      const Half& half = halves[static_cast<std::size_t>(h)];
      const Eigen::MatrixXd& part = parts[static_cast<std::size_t>(h)];
      if (part.rows() != static_cast<Eigen::Index>(half.rows.size()) + separator_rows) return {};
      for (std::size_t r = 0; r < half.rows.size(); ++r)
        x.row(half.rows[r]) = part.row(static_cast<Eigen::Index>(r));
    }
    return x;
  }
};

namespace {

// Whether a split of `lower` can pay on this machine at all. Two halves side by side need
// OpenBLAS held to one thread per call, which the caller must have allowed (blas_threads.h).
bool split_possible(const Eigen::SparseMatrix<double>& lower, int minimum_rows) {
  return lower.rows() >= std::max(minimum_rows, 2) && lower.rows() == lower.cols() &&
         std::thread::hardware_concurrency() >= 2 && SingleThreadedBlas::allowed() &&
         kHaveDenseLapack;
}

}  // namespace

std::unique_ptr<SubtreeParallelCholesky> SubtreeParallelCholesky::analyze(
    const Eigen::SparseMatrix<double>& lower, const std::vector<int>& order, int minimum_rows,
    int border_rows) {
  if (!split_possible(lower, minimum_rows)) return nullptr;
  if (!order.empty() && order.size() != static_cast<std::size_t>(lower.rows())) return nullptr;
  auto impl = std::make_unique<Impl>();
  if (!order.empty()) {
    impl->elimination_position.assign(order.size(), -1);
    for (std::size_t k = 0; k < order.size(); ++k) {
      const int row = order[k];
      if (row < 0 || row >= lower.rows() || impl->elimination_position[static_cast<std::size_t>(row)] >= 0)
        return nullptr;  // Not a permutation.
      impl->elimination_position[static_cast<std::size_t>(row)] = static_cast<int>(k);
    }
    impl->elimination_order = order;
  }
  const TreeSplit split = split_tree(elimination_tree(lower, impl->elimination_position));
  if (split.half.empty() || split.separator_begin > lower.rows() - border_rows) return nullptr;
  if (!impl->build(lower, split) || !impl->analyze_halves()) return nullptr;
  return std::unique_ptr<SubtreeParallelCholesky>(new SubtreeParallelCholesky(std::move(impl)));
}

std::unique_ptr<SubtreeParallelCholesky> SubtreeParallelCholesky::factorize_halves(
    const Eigen::SparseMatrix<double>& lower, const std::vector<int>& separator,
    const std::vector<int>& first_half, const std::shared_future<std::vector<int>>& second_half,
    const std::function<void()>& meanwhile, int minimum_rows) {
  if (!split_possible(lower, minimum_rows) || first_half.empty()) return nullptr;
  auto impl = std::make_unique<Impl>();
  if (!impl->factorize_given_halves(lower, separator, first_half, second_half, meanwhile))
    return nullptr;
  return std::unique_ptr<SubtreeParallelCholesky>(new SubtreeParallelCholesky(std::move(impl)));
}

SubtreeParallelCholesky::SubtreeParallelCholesky(std::unique_ptr<Impl> impl)
    : impl_(std::move(impl)) {}

SubtreeParallelCholesky::~SubtreeParallelCholesky() = default;

bool SubtreeParallelCholesky::factorize(const Eigen::SparseMatrix<double>& lower) {
  return impl_->factorize(lower);
}

Eigen::MatrixXd SubtreeParallelCholesky::solve(const Eigen::MatrixXd& rhs) const {
  if (rhs.rows() != impl_->size) return {};
  const std::vector<int>& position = impl_->elimination_position;
  if (position.empty()) {
    const Eigen::MatrixXd y = impl_->forward(rhs);
    return y.rows() == impl_->size ? impl_->backward(y) : Eigen::MatrixXd();
  }
  Eigen::MatrixXd in_order(rhs.rows(), rhs.cols());
  for (int row = 0; row < impl_->size; ++row)
    in_order.row(position[static_cast<std::size_t>(row)]) = rhs.row(row);
  const Eigen::MatrixXd y = impl_->forward(in_order);
  if (y.rows() != impl_->size) return {};
  const Eigen::MatrixXd x = impl_->backward(y);
  if (x.rows() != impl_->size) return {};
  Eigen::MatrixXd solution(rhs.rows(), rhs.cols());
  for (int row = 0; row < impl_->size; ++row)
    solution.row(row) = x.row(position[static_cast<std::size_t>(row)]);
  return solution;
}

Eigen::MatrixXd SubtreeParallelCholesky::forward(const Eigen::MatrixXd& b) const {
  if (b.rows() != impl_->size) return {};
  return impl_->forward(b);
}

Eigen::MatrixXd SubtreeParallelCholesky::backward(const Eigen::MatrixXd& y) const {
  if (y.rows() != impl_->size) return {};
  return impl_->backward(y);
}

Eigen::MatrixXd SubtreeParallelCholesky::trailing_factor(int rows) const {
  const int first = impl_->separator_rows - rows;
  if (rows < 0 || first < 0) return {};
  return impl_->separator_factor.bottomRightCorner(rows, rows).triangularView<Eigen::Lower>();
}

SubtreeParallelCholesky::Shape SubtreeParallelCholesky::shape() const {
  Shape shape;
  for (int h = 0; h < 2; ++h) {
    const Impl::Half& half = impl_->halves[static_cast<std::size_t>(h)];
    shape.half_rows[h] = static_cast<int>(half.rows.size());
    shape.half_flops[h] = half.factor ? half.factor->factorization_flops() : 0.0;
  }
  shape.separator_rows = impl_->separator_rows;
  return shape;
}

}  // namespace harmonia::detail
