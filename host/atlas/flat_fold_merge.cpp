#include "atlas/flat_fold_merge.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

namespace harmonia::detail {
namespace {

// The faces around each vertex (compressed rows).
struct VertexStars {
  std::vector<int> first;  // faces of vertex v: face[first[v] .. first[v + 1])
  std::vector<int> face;

  explicit VertexStars(const Mesh& mesh) {
    const auto vertex_count = static_cast<std::size_t>(mesh.vertices.rows());
    first.assign(vertex_count + 1, 0);
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
      for (int k = 0; k < 3; ++k) ++first[static_cast<std::size_t>(mesh.faces(f, k)) + 1];
    std::partial_sum(first.begin(), first.end(), first.begin());
    face.resize(static_cast<std::size_t>(first.back()));
    std::vector<int> next(first.begin(), first.end() - 1);
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
      for (int k = 0; k < 3; ++k) face[static_cast<std::size_t>(next[static_cast<std::size_t>(mesh.faces(f, k))]++)] = static_cast<int>(f);
  }
};

// The 3D angle of face f at its corner k, from its edge lengths (edge k runs from corner k to k+1).
double corner_angle(const FaceGeometry& geometry, int f, int k) {
  const std::array<double, 3>& length = geometry.edge_length[static_cast<std::size_t>(f)];
  const double a = length[static_cast<std::size_t>(k)], b = length[static_cast<std::size_t>((k + 2) % 3)];
  const double opposite = length[static_cast<std::size_t>((k + 1) % 3)];
  if (!(a > 0.0 && b > 0.0)) return 0.0;
  return std::acos(std::clamp((a * a + b * b - opposite * opposite) / (2.0 * a * b), -1.0, 1.0));
}

class FlatFoldMerger {
 public:
  FlatFoldMerger(const Mesh& mesh, FaceGeometry& geometry, double cone, Segmentation& segmentation)
      : mesh_(mesh), geometry_(geometry), cone_cosine_(std::cos(cone)), segmentation_(segmentation),
        stars_(mesh) {}

  void run() {
    while (merge_round()) {
    }
    renumber();
  }

 private:
  [[nodiscard]] int chart_of(int face) const { return segmentation_.chart_of_face[static_cast<std::size_t>(face)]; }

  // One round: every pair of neighbouring charts, longest border first, joined where allowed;
  // a chart joins at most once per round (its figures change). Returns whether any joined.
  bool merge_round() {
    const ChartAdjacency adjacency =
        chart_adjacency(mesh_, geometry_, segmentation_.chart_of_face, segmentation_.chart_count);
    if (adjacency.borders.empty()) return false;
    std::vector<int> seed_rank(static_cast<std::size_t>(segmentation_.chart_count));
    for (int chart = 0; chart < segmentation_.chart_count; ++chart)
      seed_rank[static_cast<std::size_t>(chart)] =
          geometry_.rank[static_cast<std::size_t>(segmentation_.seed_of_chart[static_cast<std::size_t>(chart)])];
    std::vector<std::vector<int>> faces(static_cast<std::size_t>(segmentation_.chart_count));
    for (int f = 0; f < geometry_.face_count(); ++f)
      if (chart_of(f) >= 0) faces[static_cast<std::size_t>(chart_of(f))].push_back(f);
    std::vector<char> changed(static_cast<std::size_t>(segmentation_.chart_count), 0);
    bool any = false;
    for (const auto& [a, b] : pairs_longest_border_first(adjacency, seed_rank)) {
      if (changed[static_cast<std::size_t>(a)] || changed[static_cast<std::size_t>(b)]) continue;
      std::optional<std::vector<std::pair<int, int>>> cuts = join_plan(a, b, adjacency, faces);
      if (!cuts) continue;
      for (const auto& [v, w] : *cuts) sever(v, w, a, b);
      const int kept = seed_rank[static_cast<std::size_t>(a)] <= seed_rank[static_cast<std::size_t>(b)] ? a : b;
      const int joined = kept == a ? b : a;
      for (const int f : faces[static_cast<std::size_t>(joined)]) segmentation_.chart_of_face[static_cast<std::size_t>(f)] = kept;
      changed[static_cast<std::size_t>(a)] = changed[static_cast<std::size_t>(b)] = 1;
      developable_.erase(a);
      developable_.erase(b);
      any = true;
    }
    return any;
  }

  // How charts a and b may join: nothing when they may not, else the edges of their common
  // border to cut (none: they join along all of it).
  [[nodiscard]] std::optional<std::vector<std::pair<int, int>>> join_plan(
      int a, int b, const ChartAdjacency& adjacency, const std::vector<std::vector<int>>& faces) {
    const ChartBorder& border = adjacency.borders.at({a, b});
    if (!is_one_path(border)) return std::nullopt;
    const std::vector<int> path = border_path(border);
    std::vector<double> length(path.size() - 1), defect(path.size(), 0.0);
    for (std::size_t i = 0; i + 1 < path.size(); ++i) length[i] = edge_length(path[i], path[i + 1], a, b);
    // The curvature joining along all of the border would bring inside: the defects of its
    // vertices that become interior (its two ends touch a third chart or the surface's boundary).
    double whole_defect = 0.0;
    for (std::size_t i = 1; i + 1 < path.size(); ++i) {
      double angle_sum = 0.0;
      if (interior_of_union(path[i], a, b, angle_sum)) defect[i] = std::abs(2.0 * std::numbers::pi - angle_sum);
      whole_defect += defect[i];
    }
    std::vector<int> both = faces[static_cast<std::size_t>(a)];
    both.insert(both.end(), faces[static_cast<std::size_t>(b)].begin(), faces[static_cast<std::size_t>(b)].end());
    if (whole_defect <= kFlatFoldDefect) {
      if (!border_worth_joining(adjacency, a, b)) return std::nullopt;
      // A single face hinged to the other chart by one edge unfolds about it without stretch at
      // any angle (a flap a scan left at a hole's rim, folded back): the flattening checks it
      // against lapping over the chart as it checks every layout.
      const bool single_face_flap = border.edges.size() == 1 && (faces[static_cast<std::size_t>(a)].size() == 1 ||
                                                                 faces[static_cast<std::size_t>(b)].size() == 1);
      if (!single_face_flap && !normals_within_cone(geometry_, both, cone_cosine_)) return std::nullopt;
      return std::vector<std::pair<int, int>>{};
    }
    // Two developable charts whose border holds curvature (three sides of a box around their
    // corner) join along the longest stretch of it that brings none inside; the rest of the border
    // is cut, so its curvature stays on the union's boundary and the union still unfolds exactly.
    if (!developable(a, faces) || !developable(b, faces)) return std::nullopt;
    std::size_t best_first = 0, best_last = 0;  // the joined edges: first .. last - 1
    double best_length = 0.0, window_length = 0.0, window_defect = 0.0;
    for (std::size_t first = 0, last = 0; first + 1 < path.size(); ++first) {
      if (last <= first) last = first, window_length = window_defect = 0.0;
      // Grow while the vertex the next edge makes interior (the window's current end) adds
      // no more than the budget allows.
      while (last + 1 < path.size() && (last == first || window_defect + defect[last] <= kFlatFoldDefect)) {
        if (last > first) window_defect += defect[last];
        window_length += length[last];
        ++last;
      }
      if (window_length > best_length) best_length = window_length, best_first = first, best_last = last;
      window_length -= length[first];
      if (first + 1 < last) window_defect -= defect[first + 1];
    }
    if (!border_worth_joining(adjacency, a, b, best_length) || !normals_within_cone(geometry_, both, cone_cosine_))
      return std::nullopt;
    std::vector<std::pair<int, int>> cuts;
    for (std::size_t i = 0; i + 1 < path.size(); ++i)
      if (i < best_first || i >= best_last) cuts.emplace_back(path[i], path[i + 1]);
    return cuts;
  }

  // The vertices of a border that is one path, from one end to the other.
  static std::vector<int> border_path(const ChartBorder& border) {
    std::map<int, std::vector<int>> neighbours;
    for (const auto& [v, w] : border.edges) {
      neighbours[v].push_back(w);
      neighbours[w].push_back(v);
    }
    int current = std::find_if(neighbours.begin(), neighbours.end(), [](const auto& entry) {
                    return entry.second.size() == 1;
                  })->first;
    std::vector<int> path{current};
    int previous = -1;
    while (path.size() < neighbours.size()) {
      const std::vector<int>& around = neighbours[current];
      const int next = around[0] != previous ? around[0] : around[1];
      previous = current;
      current = next;
      path.push_back(current);
    }
    return path;
  }

  // The faces of charts a and b on the two sides of the edge (v, w), as (face, edge index) pairs.
  [[nodiscard]] std::vector<std::pair<int, int>> sides_of(int v, int w, int a, int b) const {
    std::vector<std::pair<int, int>> sides;
    const auto begin = static_cast<std::size_t>(stars_.first[static_cast<std::size_t>(v)]);
    const auto end = static_cast<std::size_t>(stars_.first[static_cast<std::size_t>(v) + 1]);
    for (std::size_t i = begin; i < end; ++i) {
      const int f = stars_.face[i];
      if (chart_of(f) != a && chart_of(f) != b) continue;
      for (int k = 0; k < 3; ++k) {
        const int g = geometry_.across[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
        const int from = mesh_.faces(f, k), to = mesh_.faces(f, (k + 1) % 3);
        if (g >= 0 && ((from == v && to == w) || (from == w && to == v))) sides.emplace_back(f, k);
      }
    }
    return sides;
  }

  [[nodiscard]] double edge_length(int v, int w, int a, int b) const {
    const std::vector<std::pair<int, int>> sides = sides_of(v, w, a, b);
    return sides.empty() ? 0.0
                         : geometry_.edge_length[static_cast<std::size_t>(sides.front().first)]
                                                [static_cast<std::size_t>(sides.front().second)];
  }

  // The edge (v, w) between charts a and b made a cut: no chart crosses it any more.
  void sever(int v, int w, int a, int b) {
    for (const auto& [f, k] : sides_of(v, w, a, b))
      geometry_.across[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)] = -1;
  }

  // Whether chart c flattens without stretch: every vertex inside it has a flat star (angle
  // defect within kFlatFoldDefect). Remembered until the chart changes.
  bool developable(int c, const std::vector<std::vector<int>>& faces) {
    auto known = developable_.find(c);
    if (known != developable_.end()) return known->second;
    bool flat = true;
    for (const int f : faces[static_cast<std::size_t>(c)]) {
      for (int k = 0; k < 3 && flat; ++k) {
        double angle_sum = 0.0;
        if (interior_of_union(mesh_.faces(f, k), c, c, angle_sum))
          flat = std::abs(2.0 * std::numbers::pi - angle_sum) <= kFlatFoldDefect;
      }
      if (!flat) break;
    }
    return developable_[c] = flat;
  }

  // Whether every face around v lies in chart a or b, v is no boundary vertex, and its faces form
  // one fan (a manifold vertex); with the sum of its faces' angles at v.
  bool interior_of_union(int v, int a, int b, double& angle_sum) const {
    const auto begin = static_cast<std::size_t>(stars_.first[static_cast<std::size_t>(v)]);
    const auto end = static_cast<std::size_t>(stars_.first[static_cast<std::size_t>(v) + 1]);
    for (std::size_t i = begin; i < end; ++i) {
      const int f = stars_.face[i];
      const int chart = chart_of(f);
      if (chart != a && chart != b) return false;
      const int k = corner_of(f, v);
      // Both edges at v must lead to a face (no boundary, no non-manifold edge).
      if (geometry_.across[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)] < 0 ||
          geometry_.across[static_cast<std::size_t>(f)][static_cast<std::size_t>((k + 2) % 3)] < 0)
        return false;
      angle_sum += corner_angle(geometry_, f, k);
    }
    // One fan: walking across the edges at v from the first face comes back after all of them.
    const int start = stars_.face[begin];
    int face = start, steps = 0;
    do {
      const int k = corner_of(face, v);
      face = geometry_.across[static_cast<std::size_t>(face)][static_cast<std::size_t>(k)];
      ++steps;
    } while (face != start && face >= 0 && steps <= static_cast<int>(end - begin));
    return face == start && steps == static_cast<int>(end - begin);
  }

  [[nodiscard]] int corner_of(int f, int v) const {
    for (int k = 0; k < 3; ++k)
      if (mesh_.faces(f, k) == v) return k;
    return 0;
  }

  // Charts left without faces disappear; the others keep their order and seeds.
  void renumber() {
    std::vector<int> number(static_cast<std::size_t>(segmentation_.chart_count), -1);
    for (const int chart : segmentation_.chart_of_face)
      if (chart >= 0) number[static_cast<std::size_t>(chart)] = 0;
    std::vector<int> seeds;
    for (std::size_t c = 0; c < number.size(); ++c) {
      if (number[c] < 0) continue;
      number[c] = static_cast<int>(seeds.size());
      seeds.push_back(segmentation_.seed_of_chart[c]);
    }
    for (int& chart : segmentation_.chart_of_face)
      if (chart >= 0) chart = number[static_cast<std::size_t>(chart)];
    segmentation_.chart_count = static_cast<int>(seeds.size());
    segmentation_.seed_of_chart = std::move(seeds);
  }

  const Mesh& mesh_;
  FaceGeometry& geometry_;
  const double cone_cosine_;
  Segmentation& segmentation_;
  VertexStars stars_;
  std::map<int, bool> developable_;  // per chart: whether it flattens without stretch
};

}  // namespace

void merge_across_flat_folds(const Mesh& mesh, FaceGeometry& geometry, double cone,
                             Segmentation& segmentation) {
  FlatFoldMerger(mesh, geometry, cone, segmentation).run();
}

}  // namespace harmonia::detail
