#include "fallback/separator_first_ordering.h"

#include <algorithm>
#include <exception>
#include <numeric>
#include <utility>

#include "fallback/direct_solvers.h"
#include "mesh/adjacency_pattern.h"

#ifdef HARMONIA_HAVE_METIS
#include <metis.h>
#endif

namespace harmonia::detail {
namespace {

// Below this many vertices the whole order takes milliseconds: no separator is computed first.
constexpr int kSmallestSplitGraph = 10000;

#ifdef HARMONIA_HAVE_METIS
// A graph in METIS's form: the neighbours of vertex v are adjacency[offsets[v] .. offsets[v+1]).
struct AdjacencyGraph {
  std::vector<idx_t> offsets;
  std::vector<idx_t> adjacency;
  [[nodiscard]] idx_t vertices() const { return static_cast<idx_t>(offsets.size()) - 1; }
};

// Both directions of every off-diagonal entry of the lower triangle of `pattern`.
AdjacencyGraph graph_of(const Eigen::SparseMatrix<double>& pattern) {
  const auto size = static_cast<int>(pattern.rows());
  const int* outer = pattern.outerIndexPtr();
  const int* inner = pattern.innerIndexPtr();
  const int* nonzeros = pattern.innerNonZeroPtr();
  const auto column_end = [&](int column) {
    return nonzeros != nullptr ? outer[column] + nonzeros[column] : outer[column + 1];
  };
  AdjacencyGraph graph;
  graph.offsets.assign(static_cast<std::size_t>(size) + 1, 0);
  for (int column = 0; column < size; ++column)
    for (int k = outer[column]; k < column_end(column); ++k)
      if (inner[k] > column) {
        ++graph.offsets[static_cast<std::size_t>(column) + 1];
        ++graph.offsets[static_cast<std::size_t>(inner[k]) + 1];
      }
  std::partial_sum(graph.offsets.begin(), graph.offsets.end(), graph.offsets.begin());
  graph.adjacency.resize(static_cast<std::size_t>(graph.offsets.back()));
  std::vector<idx_t> next(graph.offsets.begin(), graph.offsets.end() - 1);
  for (int column = 0; column < size; ++column)
    for (int k = outer[column]; k < column_end(column); ++k)
      if (inner[k] > column) {
        graph.adjacency[static_cast<std::size_t>(next[static_cast<std::size_t>(column)]++)] =
            inner[k];
        graph.adjacency[static_cast<std::size_t>(next[static_cast<std::size_t>(inner[k])]++)] =
            column;
      }
  return graph;
}

// The vertex graph of a triangle mesh: each face joins its three vertices pairwise. The directed
// edges are bucketed by their first vertex (a counting sort), then each bucket sorted and made
// unique (an interior edge comes from both of its faces).
AdjacencyGraph graph_of(const Eigen::MatrixX3i& faces, int vertex_count) {
  AdjacencyGraph graph;
  std::vector<idx_t> bucket(static_cast<std::size_t>(vertex_count) + 1, 0);
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) bucket[static_cast<std::size_t>(faces(f, k)) + 1] += 2;
  std::partial_sum(bucket.begin(), bucket.end(), bucket.begin());
  std::vector<idx_t> neighbours(static_cast<std::size_t>(bucket.back()));
  std::vector<idx_t> next(bucket.begin(), bucket.end() - 1);
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = faces(f, k);
      neighbours[static_cast<std::size_t>(next[static_cast<std::size_t>(v)]++)] = faces(f, (k + 1) % 3);
      neighbours[static_cast<std::size_t>(next[static_cast<std::size_t>(v)]++)] = faces(f, (k + 2) % 3);
    }
  graph.offsets.assign(static_cast<std::size_t>(vertex_count) + 1, 0);
  graph.adjacency.reserve(neighbours.size() / 2 + static_cast<std::size_t>(vertex_count));
  for (int v = 0; v < vertex_count; ++v) {
    const auto first = neighbours.begin() + bucket[static_cast<std::size_t>(v)];
    const auto last = neighbours.begin() + bucket[static_cast<std::size_t>(v) + 1];
    std::sort(first, last);
    const auto unique_end = std::unique(first, last);
    for (auto it = first; it != unique_end; ++it)
      if (*it != v) graph.adjacency.push_back(*it);
    graph.offsets[static_cast<std::size_t>(v) + 1] = static_cast<idx_t>(graph.adjacency.size());
  }
  return graph;
}

// The subgraph induced by the vertices of `part`, numbered in increasing order; `members` gets
// its vertices (original numbers).
AdjacencyGraph induced_subgraph(const AdjacencyGraph& graph,
                                const std::vector<SeparatorFirstOrdering::Part>& parts,
                                SeparatorFirstOrdering::Part part, std::vector<int>& members) {
  const idx_t size = graph.vertices();
  std::vector<idx_t> local(static_cast<std::size_t>(size), -1);
  members.clear();
  for (idx_t v = 0; v < size; ++v)
    if (parts[static_cast<std::size_t>(v)] == part) {
      local[static_cast<std::size_t>(v)] = static_cast<idx_t>(members.size());
      members.push_back(static_cast<int>(v));
    }
  AdjacencyGraph subgraph;
  subgraph.offsets.reserve(members.size() + 1);
  subgraph.offsets.push_back(0);
  for (const int v : members) {
    for (idx_t k = graph.offsets[static_cast<std::size_t>(v)];
         k < graph.offsets[static_cast<std::size_t>(v) + 1]; ++k) {
      const idx_t neighbour = local[static_cast<std::size_t>(graph.adjacency[static_cast<std::size_t>(k)])];
      if (neighbour >= 0) subgraph.adjacency.push_back(neighbour);
    }
    subgraph.offsets.push_back(static_cast<idx_t>(subgraph.adjacency.size()));
  }
  return subgraph;
}

// METIS's nested dissection of `graph` (order[k]: the vertex eliminated k-th); empty on failure.
std::vector<int> nested_dissection(AdjacencyGraph& graph) {
  idx_t size = graph.vertices();
  if (size == 0) return {};
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  std::vector<idx_t> order(static_cast<std::size_t>(size)), position(static_cast<std::size_t>(size));
  const auto lock = metis_lock();
  if (METIS_NodeND(&size, graph.offsets.data(), graph.adjacency.data(), nullptr, options,
                   order.data(), position.data()) != METIS_OK)
    return {};
  return {order.begin(), order.end()};
}

// METIS's top vertex separator of `graph` (the one its nested dissection would begin with);
// empty on failure.
std::vector<SeparatorFirstOrdering::Part> top_separator(AdjacencyGraph& graph) {
  idx_t size = graph.vertices();
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  idx_t separator_size = 0;
  std::vector<idx_t> part(static_cast<std::size_t>(size));
  {
    const auto lock = metis_lock();
    if (METIS_ComputeVertexSeparator(&size, graph.offsets.data(), graph.adjacency.data(), nullptr,
                                     options, &separator_size, part.data()) != METIS_OK)
      return {};
  }
  std::vector<SeparatorFirstOrdering::Part> parts(part.size());
  for (std::size_t v = 0; v < part.size(); ++v)
    parts[v] = static_cast<SeparatorFirstOrdering::Part>(part[v]);
  return parts;
}
#endif

}  // namespace

SeparatorFirstOrdering::SeparatorFirstOrdering()
    : parts_(parts_promise_.get_future().share()),
      sides_{side_promises_[0].get_future().share(), side_promises_[1].get_future().share()} {}

template <typename BuildGraph, typename WholeOrder>
void SeparatorFirstOrdering::compute_stages(int vertex_count, const BuildGraph& build_graph,
                                            const WholeOrder& whole_order) {
  int published = 0;  // Promises kept so far: parts, side 0, side 1.
  try {
    const auto whole = [&] {
      parts_promise_.set_value({});
      ++published;
      side_promises_[0].set_value(whole_order());
      ++published;
      side_promises_[1].set_value({});
      ++published;
    };
#ifdef HARMONIA_HAVE_METIS
    if (vertex_count < kSmallestSplitGraph) return whole();
    AdjacencyGraph graph = build_graph();
    std::vector<Part> parts = top_separator(graph);
    const auto side_size = [&parts](Part side) {
      return std::count(parts.begin(), parts.end(), side);
    };
    if (parts.empty() || side_size(side0) == 0 || side_size(side1) == 0) return whole();
    // The larger side first: the side ordered last is factorized last, so it had better be the
    // smaller one.
    if (side_size(side1) > side_size(side0))
      for (Part& part : parts)
        if (part != separator) part = part == side0 ? side1 : side0;
    std::array<std::vector<int>, 2> members;
    std::array<AdjacencyGraph, 2> subgraphs;
    for (int side = 0; side < 2; ++side)
      subgraphs[static_cast<std::size_t>(side)] = induced_subgraph(
          graph, parts, static_cast<Part>(side), members[static_cast<std::size_t>(side)]);
    graph = AdjacencyGraph();
    parts_promise_.set_value(std::move(parts));
    ++published;
    for (int side = 0; side < 2; ++side) {
      std::vector<int> order = nested_dissection(subgraphs[static_cast<std::size_t>(side)]);
      subgraphs[static_cast<std::size_t>(side)] = AdjacencyGraph();
      const std::vector<int>& member = members[static_cast<std::size_t>(side)];
      if (order.size() != member.size()) {  // METIS failed: its own order of the side, kept.
        order.resize(member.size());
        std::iota(order.begin(), order.end(), 0);
      }
      for (int& vertex : order) vertex = member[static_cast<std::size_t>(vertex)];
      side_promises_[static_cast<std::size_t>(side)].set_value(std::move(order));
      ++published;
    }
#else
    (void)build_graph;
    whole();
#endif
  } catch (...) {
    const std::exception_ptr error = std::current_exception();
    if (published < 1) parts_promise_.set_exception(error);
    if (published < 2) side_promises_[0].set_exception(error);
    if (published < 3) side_promises_[1].set_exception(error);
  }
}

void SeparatorFirstOrdering::compute(const Eigen::SparseMatrix<double>& pattern) {
  compute_stages(static_cast<int>(pattern.rows()), [&pattern] {
#ifdef HARMONIA_HAVE_METIS
    return graph_of(pattern);
#endif
  }, [&pattern] { return nested_dissection_ordering(pattern); });
}

void SeparatorFirstOrdering::compute(const Eigen::MatrixX3i& faces, int vertex_count) {
  compute_stages(vertex_count, [&] {
#ifdef HARMONIA_HAVE_METIS
    return graph_of(faces, vertex_count);
#endif
  }, [&] { return nested_dissection_ordering(AdjacencyPattern(faces, vertex_count).take_matrix()); });
}

const std::vector<SeparatorFirstOrdering::Part>& SeparatorFirstOrdering::parts() const {
  return parts_.get();
}

const std::vector<int>& SeparatorFirstOrdering::side_order(int side) const {
  return sides_[static_cast<std::size_t>(side)].get();
}

std::shared_future<std::vector<int>> SeparatorFirstOrdering::side_future(int side) const {
  return sides_[static_cast<std::size_t>(side)];
}

std::vector<int> SeparatorFirstOrdering::vertex_ordering() const {
  std::vector<int> order = side_order(0);
  const std::vector<int>& second = side_order(1);
  order.insert(order.end(), second.begin(), second.end());
  const std::vector<Part>& part = parts();
  for (std::size_t v = 0; v < part.size(); ++v)
    if (part[v] == separator) order.push_back(static_cast<int>(v));
  return order;
}

}  // namespace harmonia::detail
