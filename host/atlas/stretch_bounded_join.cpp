#include "atlas/stretch_bounded_join.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "atlas/chart_borders.h"
#include "atlas/chart_mesh.h"
#include "fallback/single_threaded_blas.h"
#include "mesh/for_each_index.h"

namespace harmonia::detail {
namespace {

// A chart by its first face and its face count, which a join changes: a pair whose union did not
// flatten within the limit is not tried again while both charts stay as they are.
using ChartIdentity = std::pair<int, std::size_t>;

ChartIdentity identity(const FinishedChart& chart) {
  return {chart.mesh.surface_face.front(), chart.mesh.surface_face.size()};
}

std::pair<ChartIdentity, ChartIdentity> pair_identity(const FinishedChart& a, const FinishedChart& b) {
  const ChartIdentity first = identity(a), second = identity(b);
  return first < second ? std::pair(first, second) : std::pair(second, first);
}

// A join to try: charts a and b, their union as a chart mesh, and its layout once flattened.
struct JoinTry {
  int a = 0;
  int b = 0;
  ChartMesh joined;
  std::optional<FlattenedChart> layout;
};

}  // namespace

bool join_within_stretch(const Mesh& surface, const FaceGeometry& geometry, double cone, double max_stretch,
                         const SolverOptions& solver, int threads, std::vector<FinishedChart>& charts) {
  // The tries' own solves run side by side and do not call back (the rounds do).
  SolverOptions try_solver = solver;
  try_solver.progress = nullptr;
  const double cone_cosine = std::cos(cone);
  std::set<std::pair<ChartIdentity, ChartIdentity>> failed;
  for (int round = 0;; ++round) {
    if (solver.progress && !solver.progress(Progress{"joining", round, 0})) return false;
    const int count = static_cast<int>(charts.size());
    std::vector<int> chart_of_face(static_cast<std::size_t>(geometry.face_count()), -1);
    std::vector<int> rank(static_cast<std::size_t>(count), std::numeric_limits<int>::max());
    for (int c = 0; c < count; ++c) {
      for (const int f : charts[static_cast<std::size_t>(c)].mesh.surface_face) {
        chart_of_face[static_cast<std::size_t>(f)] = c;
        rank[static_cast<std::size_t>(c)] = std::min(rank[static_cast<std::size_t>(c)], geometry.rank[static_cast<std::size_t>(f)]);
      }
    }
    const ChartAdjacency adjacency = chart_adjacency(surface, geometry, chart_of_face, count);
    // This round's tries: in order, each pair that passes the tests and whose charts no earlier
    // try of the round takes, so that the tries are independent.
    std::vector<JoinTry> tries;
    std::vector<char> taken(static_cast<std::size_t>(count), 0);
    for (const auto& [a, b] : pairs_longest_border_first(adjacency, rank)) {
      const FinishedChart& first = charts[static_cast<std::size_t>(a)];
      const FinishedChart& second = charts[static_cast<std::size_t>(b)];
      if (taken[static_cast<std::size_t>(a)] || taken[static_cast<std::size_t>(b)]) continue;
      if (failed.count(pair_identity(first, second)) != 0) continue;
      if (!border_worth_joining(adjacency, a, b) || !is_one_path(adjacency.borders.at({a, b}))) continue;
      std::vector<int> faces = first.mesh.surface_face;
      faces.insert(faces.end(), second.mesh.surface_face.begin(), second.mesh.surface_face.end());
      if (!normals_within_cone(geometry, faces, cone_cosine)) continue;
      std::sort(faces.begin(), faces.end());
      ChartMesh joined = chart_mesh(surface, geometry, faces);
      if (!is_disk(joined)) continue;
      taken[static_cast<std::size_t>(a)] = taken[static_cast<std::size_t>(b)] = 1;
      tries.push_back(JoinTry{a, b, std::move(joined), std::nullopt});
    }
    if (tries.empty()) break;
    // Flattened side by side, the largest first (so that no thread is left with one at the end).
    std::vector<std::size_t> largest_first(tries.size());
    std::iota(largest_first.begin(), largest_first.end(), std::size_t{0});
    std::stable_sort(largest_first.begin(), largest_first.end(), [&](std::size_t x, std::size_t y) {
      return tries[x].joined.surface_face.size() > tries[y].joined.surface_face.size();
    });
    {
      // Charts factorized side by side would queue for OpenBLAS's one pool and spin
      // (harmonia/blas_threads.h).
      std::optional<SingleThreadedBlas> single_threaded_blas;
      if (threads > 1 && tries.size() > 1 && SingleThreadedBlas::allowed()) single_threaded_blas.emplace();
      for_each_index(tries.size(), threads, [&](std::size_t k) {
        JoinTry& attempt = tries[largest_first[k]];
        attempt.layout = flatten_chart(attempt.joined, max_stretch, try_solver).chart;
      });
    }
    std::vector<char> removed(static_cast<std::size_t>(count), 0);
    for (JoinTry& attempt : tries) {
      FinishedChart& first = charts[static_cast<std::size_t>(attempt.a)];
      if (!attempt.layout) {
        failed.insert(pair_identity(first, charts[static_cast<std::size_t>(attempt.b)]));
        continue;
      }
      first = FinishedChart{std::move(attempt.joined), std::move(*attempt.layout)};
      removed[static_cast<std::size_t>(attempt.b)] = 1;
    }
    std::vector<FinishedChart> kept;
    kept.reserve(charts.size());
    for (int c = 0; c < count; ++c)
      if (!removed[static_cast<std::size_t>(c)]) kept.push_back(std::move(charts[static_cast<std::size_t>(c)]));
    charts = std::move(kept);
  }
  std::sort(charts.begin(), charts.end(), [](const FinishedChart& x, const FinishedChart& y) {
    return x.mesh.surface_face.front() < y.mesh.surface_face.front();
  });
  return true;
}

}  // namespace harmonia::detail
