// The saddle-point solve of the angle methods with the triangle rows eliminated face by face
// (ABF++'s algebraic step; the equations are written out in reduced_angle_system.h).
//
// Notation: J = [T; R], T the triangle rows (one per face, ones on the face's three corners), R the
// remaining rows (vertex, wheel, active boundary); lambda = [mu; nu]. Eliminating mu leaves
//     (R P R^T) nu = R y - s_R,   y_f = P_f r_f + W_f 1 s_f / sigma_f,   sigma_f = 1^T W_f 1,
// then mu_f = (1^T W_f (r_f - z_f) - s_f) / sigma_f with z = R^T nu, and dx = W (r - T^T mu - z).
//
// CPU: R P R^T is assembled face by face (each face adds the 2-column block B'_f = R_f Q_f times
// its transpose, a dense block over the few rows touching the face, like a finite element
// stiffness matrix) into a fixed lower-triangular pattern, and factorized by CHOLMOD with a
// fill-reducing ordering of the mesh's vertices expanded to their rows, postordered on the block
// graph: the solver takes the order as it is (SparseSystemSolver::analyze_in_elimination_order),
// splits a large system on two threads, and otherwise renumbers it once so that CHOLMOD factorizes
// it as stored instead of permuting and transposing it on every factorization. Devices: B' = R Q is
// assembled on the host and the product B' B'^T formed by the backend (the Vulkan B D B^T
// kernel), then solved by the backend's PCG, warm-started from the previous solution.

#include "abf/reduced_angle_system.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <future>
#include <numeric>
#include <span>
#include <thread>
#include <utility>

#include <Eigen/SparseCore>

#include "fallback/direct_solvers.h"
#include "fallback/separator_first_ordering.h"
#include "solve/backend_selection.h"
#include "mesh/helper_tasks.h"

namespace harmonia::detail {

namespace {

constexpr double kNegligibleRightHandSide = 1e-14;
// Below this many faces the per-face loops of a solve take a millisecond: one thread runs them.
constexpr int kSmallestSplitFaceCount = 50000;

// Q_f = W_f^{1/2} N_f, N_f an orthonormal basis (3 x 2) of the plane orthogonal to
// u = W_f^{1/2} 1: the last two columns of the Householder reflection that maps e_1 to -u/|u|
// (stable because every entry of u is positive). Then Q_f Q_f^T = W_f - W_f 1 1^T W_f / sigma_f.
Eigen::Matrix<double, 3, 2> complement_basis(const Eigen::Vector3d& weights) {
  const Eigen::Vector3d root = weights.cwiseSqrt();
  Eigen::Vector3d v = root / root.norm();
  v[0] += 1.0;
  const double scale = 2.0 / v.squaredNorm();
  Eigen::Matrix<double, 3, 2> basis;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 3; ++i)
      basis(i, j) = (i == j + 1 ? 1.0 : 0.0) - scale * v[i] * v[j + 1];
  return root.asDiagonal() * basis;
}

// Lists by block (CSR), each increasing: a block's rows, or its neighbours in the block graph
// (itself included).
struct BlockLists {
  std::vector<int> offsets, items;
  [[nodiscard]] std::span<const int> of(int block) const {
    const auto begin = static_cast<std::size_t>(offsets[static_cast<std::size_t>(block)]);
    const auto end = static_cast<std::size_t>(offsets[static_cast<std::size_t>(block) + 1]);
    return {items.data() + begin, end - begin};
  }
};

// The size x size lower-triangular pattern whose column c holds the rows that
// for_each_row(c, visit) visits (each once, any order), its values `value`: counted, then filled
// and sorted column by column, so that it costs only its own arrays.
template <typename ForEachRow>
Eigen::SparseMatrix<double> lower_pattern(int size, const ForEachRow& for_each_row, double value) {
  Eigen::SparseMatrix<double> pattern(size, size);
  int* outer = pattern.outerIndexPtr();
  outer[0] = 0;
  for (int column = 0; column < size; ++column) {
    int count = 0;
    for_each_row(column, [&count](int) { ++count; });
    outer[column + 1] = outer[column] + count;
  }
  pattern.resizeNonZeros(outer[size]);
  int* inner = pattern.innerIndexPtr();
  for (int column = 0; column < size; ++column) {
    int* slot = inner + outer[column];
    for_each_row(column, [&slot](int row) { *slot++ = row; });
    std::sort(inner + outer[column], slot);
  }
  std::fill(pattern.valuePtr(), pattern.valuePtr() + pattern.nonZeros(), value);
  return pattern;
}

}  // namespace

struct ReducedAngleSystem::Impl {
  Backend& backend;
  IterativeSettings settings;
  ProgressCallback progress;
  int face_count = 0;
  int vertex_count = 0;
  std::vector<int> corner_vertex;  // Corner -> vertex, for the row ordering.
  bool direct = false;

  // The pattern of J the structures below were built for.
  std::vector<int> pattern_outer, pattern_inner;
  int reduced_rows = 0;
  std::vector<int> row_vertex;  // Reduced row -> its vertex (vertex, wheel, boundary rows).
  // Vertex -> block (the vertices owning rows) or -1, row -> block, and the block graph's lower
  // pattern (build_blocks, build_block_graph).
  std::vector<int> vertex_block, row_block;
  BlockLists block_rows, block_neighbours;
  Eigen::SparseMatrix<double> blocks_graph;

  // J^T restricted to the reduced rows: per corner, (reduced row, position in J's values).
  std::vector<int> corner_offsets, corner_rows, corner_value_index;
  // Reduced rows per face (CPU path).
  std::vector<int> face_row_offsets, face_row_list;

  // The current problem.
  const RowMajorSparse* jacobian = nullptr;
  Eigen::VectorXd weights;
  std::vector<Eigen::Matrix<double, 3, 2>> bases;  // Q_f per face.

  // CPU: lower triangle of R P R^T in a fixed column-major pattern, and its factorization.
  Eigen::SparseMatrix<double> reduced;
  std::unique_ptr<SparseSystemSolver> factorization;
  bool analyzed = false;
  bool factorized = false;

  // Devices: B' = R Q (rows x 2F) and its normal product.
  RowMajorSparse reduced_jacobian;
  std::unique_ptr<DeviceNormalProduct> product;
  std::unique_ptr<DeviceVectors> device_rhs, device_solution;
  Eigen::VectorXd warm_start;
  // A fill-reducing ordering of all the mesh's vertices from the caller (may be empty), or one
  // still being computed.
  std::vector<int> vertex_ordering;
  const SeparatorFirstOrdering* staged_ordering = nullptr;

  Impl(Backend& backend_in, const AngleTopology& topology, const IterativeSettings& settings_in,
       const ProgressCallback& progress_in)
      : backend(backend_in), settings(settings_in), progress(progress_in) {
    face_count = topology.face_count;
    vertex_count = topology.vertex_count;
    direct = backend.supports(Feature::direct_factorization);
    corner_vertex.assign(static_cast<std::size_t>(topology.corner_count()), -1);
    for (int v = 0; v < topology.vertex_count; ++v)
      for (int k = topology.vertex_corner_offsets[v]; k < topology.vertex_corner_offsets[v + 1]; ++k)
        corner_vertex[static_cast<std::size_t>(topology.vertex_corners[k])] = v;
  }

  bool same_pattern(const RowMajorSparse& j) const {
    return static_cast<std::size_t>(j.outerSize()) + 1 == pattern_outer.size() &&
           std::equal(pattern_outer.begin(), pattern_outer.end(), j.outerIndexPtr()) &&
           static_cast<std::size_t>(j.nonZeros()) == pattern_inner.size() &&
           std::equal(pattern_inner.begin(), pattern_inner.end(), j.innerIndexPtr());
  }

  // Everything that depends on J's pattern only: the transposed index, the row vertices, and the
  // pattern of the reduced matrix (CPU) or of B' (devices).
  void build_pattern(const RowMajorSparse& j) {
    pattern_outer.assign(j.outerIndexPtr(), j.outerIndexPtr() + j.outerSize() + 1);
    pattern_inner.assign(j.innerIndexPtr(), j.innerIndexPtr() + j.nonZeros());
    reduced_rows = static_cast<int>(j.rows()) - face_count;
    const int corners = static_cast<int>(j.cols());

    // Counting sort of the reduced rows' entries by corner.
    corner_offsets.assign(static_cast<std::size_t>(corners) + 1, 0);
    const int first = j.outerIndexPtr()[face_count], last = j.outerIndexPtr()[j.rows()];
    for (int e = first; e < last; ++e) ++corner_offsets[j.innerIndexPtr()[e] + 1];
    std::partial_sum(corner_offsets.begin(), corner_offsets.end(), corner_offsets.begin());
    corner_rows.resize(static_cast<std::size_t>(last - first));
    corner_value_index.resize(corner_rows.size());
    std::vector<int> fill(corner_offsets.begin(), corner_offsets.end() - 1);
    row_vertex.assign(static_cast<std::size_t>(reduced_rows), 0);
    for (int row = 0; row < reduced_rows; ++row) {
      const int begin = j.outerIndexPtr()[face_count + row];
      const int end = j.outerIndexPtr()[face_count + row + 1];
      // A vertex or boundary row's corners sit at its vertex; a wheel row has the two other
      // corners of each face around its vertex, so its vertex is the first face's third corner.
      if (begin < end) {
        const int* columns = j.innerIndexPtr();
        int central = columns[begin];
        if (begin + 1 < end && columns[begin + 1] / 3 == columns[begin] / 3)
          central = 3 * (columns[begin] / 3) + 3 - columns[begin] % 3 - columns[begin + 1] % 3;
        row_vertex[static_cast<std::size_t>(row)] = corner_vertex[static_cast<std::size_t>(central)];
      }
      for (int e = begin; e < end; ++e) {
        const int slot = fill[j.innerIndexPtr()[e]]++;
        corner_rows[static_cast<std::size_t>(slot)] = row;
        corner_value_index[static_cast<std::size_t>(slot)] = e;
      }
    }
    if (direct) {
      build_face_rows();
      build_blocks();
      block_neighbours = neighbouring_blocks();
      build_reduced_pattern(block_neighbours);
      build_block_graph(block_neighbours);
    } else {
      product.reset();
    }
    analyzed = false;
    factorized = false;
    warm_start = Eigen::VectorXd::Zero(reduced_rows);
  }

  // Sorted, distinct reduced rows touching each face (CSR by face), gathered once per pattern:
  // the pattern build and every assembly walk them.
  void build_face_rows() {
    face_row_offsets.assign(static_cast<std::size_t>(face_count) + 1, 0);
    face_row_list.clear();
    face_row_list.reserve(corner_rows.size());
    std::vector<int> rows;
    for (int f = 0; f < face_count; ++f) {
      rows.clear();
      for (int c = 3 * f; c < 3 * f + 3; ++c)
        for (int k = corner_offsets[c]; k < corner_offsets[c + 1]; ++k)
          rows.push_back(corner_rows[static_cast<std::size_t>(k)]);
      std::sort(rows.begin(), rows.end());
      rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
      face_row_list.insert(face_row_list.end(), rows.begin(), rows.end());
      face_row_offsets[static_cast<std::size_t>(f) + 1] = static_cast<int>(face_row_list.size());
    }
    face_row_list.shrink_to_fit();
  }

  [[nodiscard]] std::span<const int> face_rows(int f) const {
    const auto begin = static_cast<std::size_t>(face_row_offsets[static_cast<std::size_t>(f)]);
    const auto end = static_cast<std::size_t>(face_row_offsets[static_cast<std::size_t>(f) + 1]);
    return {face_row_list.data() + begin, end - begin};
  }

  // The blocks of the rows touching each face are neighbours. Every row of a block touches the
  // faces around its vertex (a vertex or boundary row has its corners there, a wheel row the two
  // other corners of each face), so two rows touch a common face exactly when their blocks are
  // neighbours; were a row to touch fewer, the block pattern would only hold a few more zeros.
  // The directed pairs are bucketed by their first block (a counting sort), then each bucket
  // sorted and made unique.
  [[nodiscard]] BlockLists neighbouring_blocks() const {
    const auto blocks = static_cast<int>(block_rows.offsets.size()) - 1;
    // Calls visit(a, b) for the blocks a != b of each face's rows (a face's rows are sorted, and
    // a block's rows are consecutive among them only by chance: duplicates are removed later).
    const auto for_each_pair = [&](auto&& visit) {
      std::array<int, 8> face_blocks{};
      for (int f = 0; f < face_count; ++f) {
        int count = 0;
        for (const int row : face_rows(f)) {
          const int block = row_block[static_cast<std::size_t>(row)];
          if (std::find(face_blocks.begin(), face_blocks.begin() + count, block) !=
              face_blocks.begin() + count)
            continue;
          if (count == static_cast<int>(face_blocks.size())) break;  // Not for a triangle.
          face_blocks[static_cast<std::size_t>(count++)] = block;
        }
        for (int a = 0; a < count; ++a)
          for (int b = 0; b < count; ++b)
            if (a != b) visit(face_blocks[static_cast<std::size_t>(a)], face_blocks[static_cast<std::size_t>(b)]);
      }
    };
    BlockLists neighbours;
    std::vector<int> bucket(static_cast<std::size_t>(blocks) + 1, 0);
    for_each_pair([&](int a, int) { ++bucket[static_cast<std::size_t>(a) + 1]; });
    for (int b = 0; b < blocks; ++b) ++bucket[static_cast<std::size_t>(b) + 1];  // Itself.
    std::partial_sum(bucket.begin(), bucket.end(), bucket.begin());
    std::vector<int> pairs(static_cast<std::size_t>(bucket.back()));
    std::vector<int> next(bucket.begin(), bucket.end() - 1);
    for (int b = 0; b < blocks; ++b) pairs[static_cast<std::size_t>(next[static_cast<std::size_t>(b)]++)] = b;
    for_each_pair([&](int a, int b) { pairs[static_cast<std::size_t>(next[static_cast<std::size_t>(a)]++)] = b; });
    neighbours.offsets.reserve(static_cast<std::size_t>(blocks) + 1);
    neighbours.offsets.push_back(0);
    neighbours.items.reserve(pairs.size() / 2 + static_cast<std::size_t>(blocks));
    for (int b = 0; b < blocks; ++b) {
      const auto first = pairs.begin() + bucket[static_cast<std::size_t>(b)];
      const auto last = pairs.begin() + bucket[static_cast<std::size_t>(b) + 1];
      std::sort(first, last);
      neighbours.items.insert(neighbours.items.end(), first, std::unique(first, last));
      neighbours.offsets.push_back(static_cast<int>(neighbours.items.size()));
    }
    return neighbours;
  }

  // Lower-triangular pattern of R P R^T: rows i >= c that touch a common face with row c, i.e.
  // the rows of the blocks neighbouring c's.
  void build_reduced_pattern(const BlockLists& neighbours) {
    const auto for_each_row = [&](int column, auto&& visit) {
      for (const int block : neighbours.of(row_block[static_cast<std::size_t>(column)]))
        for (const int row : block_rows.of(block))
          if (row >= column) visit(row);
    };
    reduced = lower_pattern(reduced_rows, for_each_row, 0.0);
  }

  // A fill-reducing elimination order of the reduced rows: the vertices owning rows are ordered,
  // then expanded to their rows (a vertex's vertex and wheel rows have the same pattern, so they
  // are eliminated together). The vertices come in the order of the caller's vertex ordering when
  // there is one (restricted to the vertices owning rows: leaving vertices out of a graph never
  // adds fill to an elimination order), else in an AMD ordering of the block graph; either is
  // then postordered on the block graph, which makes the expanded order a postorder too.
  std::vector<int> elimination_order() const {
    const int blocks = static_cast<int>(blocks_graph.rows());
    const Eigen::SparseMatrix<double>& graph = blocks_graph;
    std::vector<int> block_order;
    if (vertex_ordering.size() == static_cast<std::size_t>(vertex_count)) {
      block_order.reserve(static_cast<std::size_t>(blocks));
      for (const int v : vertex_ordering)
        if (vertex_block[static_cast<std::size_t>(v)] >= 0)
          block_order.push_back(vertex_block[static_cast<std::size_t>(v)]);
    } else {
      block_order = fill_reducing_ordering(graph);
    }
    if (block_order.size() != static_cast<std::size_t>(blocks)) return {};
    return rows_of_blocks(postordered_ordering(graph, block_order));
  }

  // The rows of `block_order`'s blocks, block after block.
  std::vector<int> rows_of_blocks(const std::vector<int>& block_order) const {
    std::vector<int> rows;
    rows.reserve(static_cast<std::size_t>(reduced_rows));
    for (const int block : block_order) {
      const std::span<const int> own = block_rows.of(block);
      rows.insert(rows.end(), own.begin(), own.end());
    }
    return rows;
  }

  // The rows of one side of a separator-first ordering, in its vertices' order postordered on the
  // side's own block graph (the side's elimination forest, which the separator's rows then top).
  std::vector<int> side_rows(const std::vector<int>& side_vertices) const {
    std::vector<int> side_blocks;
    side_blocks.reserve(side_vertices.size());
    for (const int v : side_vertices)
      if (vertex_block[static_cast<std::size_t>(v)] >= 0)
        side_blocks.push_back(vertex_block[static_cast<std::size_t>(v)]);
    const auto count = static_cast<int>(side_blocks.size());
    std::vector<int> local(static_cast<std::size_t>(blocks_graph.rows()), -1);
    for (int k = 0; k < count; ++k) local[static_cast<std::size_t>(side_blocks[static_cast<std::size_t>(k)])] = k;
    // The side's block graph numbered along the side's order (lower triangle).
    const auto for_each_lower = [&](int k, auto&& visit) {
      for (const int block : block_neighbours.of(side_blocks[static_cast<std::size_t>(k)])) {
        const int row = local[static_cast<std::size_t>(block)];
        if (row >= k) visit(row);
      }
    };
    const Eigen::SparseMatrix<double> side_graph = lower_pattern(count, for_each_lower, 1.0);
    std::vector<int> identity(static_cast<std::size_t>(count));
    std::iota(identity.begin(), identity.end(), 0);
    std::vector<int> block_order = postordered_ordering(side_graph, identity);
    for (int& block : block_order) block = side_blocks[static_cast<std::size_t>(block)];
    return rows_of_blocks(block_order);
  }

  // The first analysis with a separator-first ordering: side 0's rows are factorized while side 1
  // is ordered. False, with nothing done, where the ordering made no split.
  bool factorize_in_halves(SolveStats& stats, const std::function<void()>& meanwhile) {
    const SeparatorFirstOrdering& staged = *staged_ordering;
    const std::vector<SeparatorFirstOrdering::Part>& parts = staged.parts();
    if (parts.size() != static_cast<std::size_t>(vertex_count)) return false;
    std::vector<int> separator_blocks;
    for (int v = 0; v < vertex_count; ++v)
      if (parts[static_cast<std::size_t>(v)] == SeparatorFirstOrdering::separator &&
          vertex_block[static_cast<std::size_t>(v)] >= 0)
        separator_blocks.push_back(vertex_block[static_cast<std::size_t>(v)]);
    const std::vector<int> first_half = side_rows(staged.side_order(0));
    // Mapped on the thread that waits for it (the second half's).
    const std::shared_future<std::vector<int>> second_half =
        std::async(std::launch::deferred, [this, &staged] { return side_rows(staged.side_order(1)); })
            .share();
    stats = factorization->factorize_in_halves(reduced, rows_of_blocks(separator_blocks),
                                               first_half, second_half, meanwhile);
    return true;
  }

  // The vertices owning rows (blocks, numbered in the order of their first row), each row's
  // block and each block's rows: they depend on the pattern alone, so they are built with it,
  // ahead of the vertex ordering.
  void build_blocks() {
    vertex_block.assign(static_cast<std::size_t>(vertex_count), -1);
    int blocks = 0;
    row_block.assign(static_cast<std::size_t>(reduced_rows), 0);
    for (int row = 0; row < reduced_rows; ++row) {
      int& block = vertex_block[static_cast<std::size_t>(row_vertex[static_cast<std::size_t>(row)])];
      if (block < 0) block = blocks++;
      row_block[static_cast<std::size_t>(row)] = block;
    }
    block_rows.offsets.assign(static_cast<std::size_t>(blocks) + 1, 0);
    for (int row = 0; row < reduced_rows; ++row)
      ++block_rows.offsets[static_cast<std::size_t>(row_block[static_cast<std::size_t>(row)]) + 1];
    std::partial_sum(block_rows.offsets.begin(), block_rows.offsets.end(),
                     block_rows.offsets.begin());
    block_rows.items.resize(static_cast<std::size_t>(reduced_rows));
    std::vector<int> next(block_rows.offsets.begin(), block_rows.offsets.end() - 1);
    for (int row = 0; row < reduced_rows; ++row) {
      const auto block = static_cast<std::size_t>(row_block[static_cast<std::size_t>(row)]);
      block_rows.items[static_cast<std::size_t>(next[block]++)] = row;
    }
  }

  // Lower pattern of the block graph (blocks a >= b that are neighbours, the diagonal included),
  // for the orderings.
  void build_block_graph(const BlockLists& neighbours) {
    const auto blocks = static_cast<int>(neighbours.offsets.size()) - 1;
    std::vector<int> graph_outer{0}, graph_inner;
    graph_inner.reserve(neighbours.items.size() / 2 + static_cast<std::size_t>(blocks));
    for (int b = 0; b < blocks; ++b) {
      for (const int a : neighbours.of(b))
        if (a >= b) graph_inner.push_back(a);
      graph_outer.push_back(static_cast<int>(graph_inner.size()));
    }
    blocks_graph.resize(blocks, blocks);
    blocks_graph.resizeNonZeros(static_cast<Eigen::Index>(graph_inner.size()));
    std::copy(graph_outer.begin(), graph_outer.end(), blocks_graph.outerIndexPtr());
    std::copy(graph_inner.begin(), graph_inner.end(), blocks_graph.innerIndexPtr());
    std::fill(blocks_graph.valuePtr(), blocks_graph.valuePtr() + blocks_graph.nonZeros(), 1.0);
  }

  // B'_f = R_f Q_f over `rows` (sorted): local[2 a + j] for row rows[a], column j.
  void face_block(int f, std::span<const int> rows, std::vector<double>& local) const {
    local.assign(2 * rows.size(), 0.0);
    const Eigen::Matrix<double, 3, 2>& basis = bases[static_cast<std::size_t>(f)];
    for (int k = 0; k < 3; ++k) {
      const int c = 3 * f + k;
      for (int e = corner_offsets[c]; e < corner_offsets[c + 1]; ++e) {
        const auto a = static_cast<std::size_t>(
            std::lower_bound(rows.begin(), rows.end(), corner_rows[static_cast<std::size_t>(e)]) -
            rows.begin());
        const double value = jacobian->valuePtr()[corner_value_index[static_cast<std::size_t>(e)]];
        local[2 * a] += value * basis(k, 0);
        local[2 * a + 1] += value * basis(k, 1);
      }
    }
  }

  void assemble(const RowMajorSparse& j, const Eigen::VectorXd& w) {
    if (!same_pattern(j)) build_pattern(j);
    jacobian = &j;
    weights = w;
    bases.resize(static_cast<std::size_t>(face_count));
    for (int f = 0; f < face_count; ++f)
      bases[static_cast<std::size_t>(f)] = complement_basis(w.segment<3>(3 * f));
    if (reduced_rows == 0) return;
    if (direct) {
      assemble_reduced_matrix();
    } else {
      assemble_reduced_jacobian();
    }
  }

  // Per face: the dense block B'_f B'_f^T added into the lower-triangular pattern.
  void assemble_reduced_matrix() {
    std::fill(reduced.valuePtr(), reduced.valuePtr() + reduced.nonZeros(), 0.0);
    std::vector<double> local;
    const int* outer = reduced.outerIndexPtr();
    const int* inner = reduced.innerIndexPtr();
    double* values = reduced.valuePtr();
    for (int f = 0; f < face_count; ++f) {
      const std::span<const int> rows = face_rows(f);
      face_block(f, rows, local);
      for (std::size_t a = 0; a < rows.size(); ++a) {
        const int column = rows[a];
        const int* slot = inner + outer[column];
        for (std::size_t b = a; b < rows.size(); ++b) {
          slot = std::lower_bound(slot, inner + outer[column + 1], rows[b]);
          values[slot - inner] += local[2 * a] * local[2 * b] + local[2 * a + 1] * local[2 * b + 1];
        }
      }
    }
  }

  // B' = R Q in CSR: row i has the columns 2f, 2f + 1 of every face it touches.
  void assemble_reduced_jacobian() {
    const RowMajorSparse& j = *jacobian;
    std::vector<int> outer{0}, inner;
    std::vector<double> values;
    inner.reserve(static_cast<std::size_t>(j.nonZeros() - j.outerIndexPtr()[face_count]));
    values.reserve(inner.capacity());
    for (int row = 0; row < reduced_rows; ++row) {
      const int begin = j.outerIndexPtr()[face_count + row];
      const int end = j.outerIndexPtr()[face_count + row + 1];
      for (int e = begin; e < end;) {
        const int f = j.innerIndexPtr()[e] / 3;
        const Eigen::Matrix<double, 3, 2>& basis = bases[static_cast<std::size_t>(f)];
        double first = 0.0, second = 0.0;
        for (; e < end && j.innerIndexPtr()[e] / 3 == f; ++e) {
          const int k = j.innerIndexPtr()[e] % 3;
          first += j.valuePtr()[e] * basis(k, 0);
          second += j.valuePtr()[e] * basis(k, 1);
        }
        inner.push_back(2 * f);
        values.push_back(first);
        inner.push_back(2 * f + 1);
        values.push_back(second);
      }
      outer.push_back(static_cast<int>(inner.size()));
    }
    reduced_jacobian.resize(reduced_rows, 2 * face_count);
    reduced_jacobian.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
    std::copy(outer.begin(), outer.end(), reduced_jacobian.outerIndexPtr());
    std::copy(inner.begin(), inner.end(), reduced_jacobian.innerIndexPtr());
    std::copy(values.begin(), values.end(), reduced_jacobian.valuePtr());
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(2 * face_count);
    if (!product) {
      product = backend.normal_product(reduced_jacobian, ones);
      device_rhs = backend.allocate(reduced_rows, 1);
      device_solution = backend.allocate(reduced_rows, 1);
    } else {
      product->update(Eigen::Map<const Eigen::VectorXd>(reduced_jacobian.valuePtr(),
                                                        reduced_jacobian.nonZeros()),
                      ones);
    }
  }

  SolveStats factorize(const std::function<void()>& meanwhile) {
    SolveStats stats;
    bool meanwhile_done = false;
    const auto run_meanwhile = [&] {
      if (meanwhile && !meanwhile_done) meanwhile();
      meanwhile_done = true;
    };
    if (!direct || reduced_rows == 0) {
      run_meanwhile();
      return stats;
    }
    if (!factorization)
      factorization = make_system_solver(backend, MatrixKind::symmetric_positive_definite,
                                         settings, progress);
    if (!analyzed && staged_ordering != nullptr) {
      const bool split = factorize_in_halves(stats, run_meanwhile);
      // Kept for a later analysis (a changed pattern).
      vertex_ordering = staged_ordering->vertex_ordering();
      staged_ordering = nullptr;
      if (split) {
        analyzed = true;
        factorized = stats.status == Status::ok;
        return stats;
      }
    }
    run_meanwhile();
    if (!analyzed) {
      const std::vector<int> order = elimination_order();
      if (order.size() == static_cast<std::size_t>(reduced_rows))
        factorization->analyze_in_elimination_order(reduced, order);
      else  // No ordering of the blocks: CHOLMOD orders the matrix itself.
        factorization->analyze(reduced);
      analyzed = true;
    }
    stats = factorization->factorize(reduced);
    factorized = stats.status == Status::ok;
    return stats;
  }

  // work(begin, end) over the faces: on two threads for a large mesh (each face's rows are its
  // own, so the halves write apart and the result does not depend on the split).
  template <typename Work>
  void for_face_ranges(const Work& work) const {
    if (face_count < kSmallestSplitFaceCount || std::thread::hardware_concurrency() < 2) {
      work(0, face_count);
      return;
    }
    auto second = start_beside([&] { work(face_count / 2, face_count); });
    work(0, face_count / 2);
    second.get();
  }

  // R y - s_R with y_f = P_f r_f + W_f 1 s_f / sigma_f (the triangle rows' contribution moved to
  // the right), or zero when it is negligible.
  Eigen::VectorXd right_hand_side(const Eigen::VectorXd& r, const Eigen::VectorXd& s) const {
    if (reduced_rows == 0) return {};
    const RowMajorSparse& j = *jacobian;
    Eigen::VectorXd y(3 * face_count);
    for_face_ranges([&](int begin, int end) {
      for (int f = begin; f < end; ++f) {
        const Eigen::Matrix<double, 3, 2>& basis = bases[static_cast<std::size_t>(f)];
        const Eigen::Vector3d w = weights.segment<3>(3 * f);
        y.segment<3>(3 * f) =
            basis * (basis.transpose() * r.segment<3>(3 * f)) + w * (s[f] / w.sum());
      }
    });
    Eigen::VectorXd rhs = j.bottomRows(reduced_rows) * y - s.tail(reduced_rows);
    // A right-hand side at the rounding level of the constraint values (sums of a few angles up
    // to pi: rounding about 1e-14) has nu = 0 as an exact answer to that precision. Solving it
    // anyway asks a relative tolerance of noise, which fp32 device solvers cannot meet.
    if (rhs.lpNorm<Eigen::Infinity>() <= kNegligibleRightHandSide) rhs.setZero();
    return rhs;
  }

  // Back-substitution: z = R^T nu, mu per face, dx = W (r - T^T mu - z).
  void back_substitute(const Eigen::VectorXd& r, const Eigen::VectorXd& s,
                       const Eigen::VectorXd& nu, Eigen::VectorXd& dx,
                       Eigen::VectorXd& lambda) const {
    const RowMajorSparse& j = *jacobian;
    const Eigen::VectorXd z = j.bottomRows(reduced_rows).transpose() * nu;
    lambda.resize(j.rows());
    lambda.tail(reduced_rows) = nu;
    dx.resize(3 * face_count);
    for_face_ranges([&](int begin, int end) {
      for (int f = begin; f < end; ++f) {
        const Eigen::Vector3d w = weights.segment<3>(3 * f);
        const Eigen::Vector3d free_part = r.segment<3>(3 * f) - z.segment<3>(3 * f);
        const double mu = (w.dot(free_part) - s[f]) / w.sum();
        lambda[f] = mu;
        dx.segment<3>(3 * f) = w.cwiseProduct(free_part - Eigen::Vector3d::Constant(mu));
      }
    });
  }

  SolveStats solve(const Eigen::VectorXd& r, const Eigen::VectorXd& s, Eigen::VectorXd& dx,
                   Eigen::VectorXd& lambda) {
    SolveStats stats;
    Eigen::VectorXd nu = Eigen::VectorXd::Zero(reduced_rows);
    const Eigen::VectorXd rhs = right_hand_side(r, s);
    if (reduced_rows > 0 && rhs.lpNorm<Eigen::Infinity>() > 0.0) {
      if (direct) {
        Eigen::MatrixXd solution;
        stats = factorization->solve(rhs, solution);
        if (stats.status != Status::ok) return stats;
        nu = solution.col(0);
        const Eigen::VectorXd residual =
            reduced.selfadjointView<Eigen::Lower>() * nu - rhs;
        const double norm = rhs.norm();
        stats.relative_residual = norm > 0.0 ? residual.norm() / norm : residual.norm();
      } else {
        device_rhs->upload(rhs);
        device_solution->upload(warm_start);
        stats = backend.pcg(product->matrix(), *device_rhs, *device_solution, settings, progress);
        if (stats.status != Status::ok && stats.status != Status::not_converged) return stats;
        nu = device_solution->download().col(0);
        warm_start = nu;
      }
    }
    back_substitute(r, s, nu, dx, lambda);
    return stats;
  }

  // R P R^T with both triangles.
  RowMajorSparse reduced_matrix() const {
    if (direct) return RowMajorSparse(reduced.selfadjointView<Eigen::Lower>());
    if (product) return product->download();
    return RowMajorSparse(reduced_rows, reduced_rows);
  }
};

ReducedAngleSystem::ReducedAngleSystem(Backend& backend, const AngleTopology& topology,
                                       const IterativeSettings& settings,
                                       const ProgressCallback& progress)
    : impl_(std::make_unique<Impl>(backend, topology, settings, progress)) {}

ReducedAngleSystem::~ReducedAngleSystem() = default;

void ReducedAngleSystem::assemble(const RowMajorSparse& jacobian, const Eigen::VectorXd& weights) {
  impl_->assemble(jacobian, weights);
}

void ReducedAngleSystem::use_vertex_ordering(std::vector<int> vertex_ordering) {
  if (impl_->vertex_ordering != vertex_ordering) impl_->analyzed = false;
  impl_->vertex_ordering = std::move(vertex_ordering);
  impl_->staged_ordering = nullptr;
}

void ReducedAngleSystem::use_vertex_ordering(const SeparatorFirstOrdering& staged_ordering) {
  impl_->vertex_ordering.clear();
  impl_->staged_ordering = &staged_ordering;
  impl_->analyzed = false;
}

SolveStats ReducedAngleSystem::factorize(const std::function<void()>& meanwhile) {
  return impl_->factorize(meanwhile);
}

SolveStats ReducedAngleSystem::solve_assembled(const Eigen::VectorXd& r, const Eigen::VectorXd& s,
                                               Eigen::VectorXd& dx, Eigen::VectorXd& lambda) {
  return impl_->solve(r, s, dx, lambda);
}

SolveStats ReducedAngleSystem::solve(const RowMajorSparse& jacobian,
                                     const Eigen::VectorXd& weights, const Eigen::VectorXd& r,
                                     const Eigen::VectorXd& s, Eigen::VectorXd& dx,
                                     Eigen::VectorXd& lambda) {
  assemble(jacobian, weights);
  const SolveStats stats = factorize();
  if (stats.status != Status::ok) return stats;
  return solve_assembled(r, s, dx, lambda);
}

RowMajorSparse ReducedAngleSystem::reduced_matrix() const { return impl_->reduced_matrix(); }

Eigen::VectorXd ReducedAngleSystem::reduced_right_hand_side(const Eigen::VectorXd& r,
                                                            const Eigen::VectorXd& s) const {
  return impl_->right_hand_side(r, s);
}

void ReducedAngleSystem::back_substitute(const Eigen::VectorXd& r, const Eigen::VectorXd& s,
                                         const Eigen::VectorXd& nu, Eigen::VectorXd& dx,
                                         Eigen::VectorXd& lambda) const {
  impl_->back_substitute(r, s, nu, dx, lambda);
}

std::string ReducedAngleSystem::solver_name() const {
  if (impl_->direct) {
    const std::string name =
        impl_->factorization ? impl_->factorization->name() : std::string("direct");
    return name + " (reduced, 2 per interior vertex)";
  }
  return "pcg-jacobi (reduced, 2 per interior vertex)";
}

}  // namespace harmonia::detail
