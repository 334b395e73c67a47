#pragma once
// Internal: a nested-dissection ordering computed top separator first, each side's order handed
// out as soon as it is ready.
//
// Why: METIS orders a 400K-vertex mesh graph in about 2 s on one core, and a map waits for the
// whole order before it can factorize. Nested dissection begins with one vertex separator S that
// splits the graph into two sides with no edge between them; each side is then ordered on its own
// and S comes last. Computing S first (0.2 s) and then the sides one after the other gives the
// same kind of order (its fill and flops within METIS's run-to-run spread, measured over seeds on
// the 827K-face mesh), but a factorization can start on side 0 while METIS still orders side 1
// (subtree_parallel_cholesky.h, SubtreeParallelCholesky::factorize_halves).
//
// The METIS calls run one after the other on the thread that calls compute(): METIS draws from
// the C library's process-wide random numbers, so two of its calls at the same time would make
// the order depend on timing (direct_solvers.h, metis_lock()). Without METIS, or for a graph that
// no separator splits, compute() hands out the whole nested_dissection_ordering() as side 0's
// order, with no separator and an empty side 1.
#include <array>
#include <future>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace harmonia::detail {

class SeparatorFirstOrdering {
 public:
  //! Which part a vertex belongs to.
  enum Part : signed char { side0 = 0, side1 = 1, separator = 2 };

  SeparatorFirstOrdering();

  //! Orders the symmetric `pattern` (#V by #V; its lower triangle is read, the diagonal ignored),
  //! publishing the parts, then side 0's order, then side 1's. Call once, typically on a
  //! background thread; an exception thrown meanwhile is handed to every waiting reader.
  void compute(const Eigen::SparseMatrix<double>& pattern);
  //! The same for the vertex graph of a triangle mesh (vertices joined when they share a face),
  //! built straight from its faces (rows of vertex indices in [0, vertex_count)).
  void compute(const Eigen::MatrixX3i& faces, int vertex_count);

  //! Each vertex's part (side 0 the larger side); waits for the separator. Empty when no split
  //! was made (see above).
  [[nodiscard]] const std::vector<Part>& parts() const;
  //! The vertices of side `side` (0 or 1) in elimination order; waits for that side.
  [[nodiscard]] const std::vector<int>& side_order(int side) const;
  //! A shared handle on side `side`'s order, for a thread that waits for it.
  [[nodiscard]] std::shared_future<std::vector<int>> side_future(int side) const;
  //! The whole elimination order: side 0's vertices, side 1's, then the separator's (increasing);
  //! waits for everything.
  [[nodiscard]] std::vector<int> vertex_ordering() const;

 private:
  // The stages, for a graph of `vertex_count` vertices built by build_graph() (METIS's form),
  // with whole_order() where no split is made.
  template <typename BuildGraph, typename WholeOrder>
  void compute_stages(int vertex_count, const BuildGraph& build_graph,
                      const WholeOrder& whole_order);

  std::promise<std::vector<Part>> parts_promise_;
  std::array<std::promise<std::vector<int>>, 2> side_promises_;
  std::shared_future<std::vector<Part>> parts_;
  std::array<std::shared_future<std::vector<int>>, 2> sides_;
};

}  // namespace harmonia::detail
