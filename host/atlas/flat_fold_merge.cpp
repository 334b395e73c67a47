#include "atlas/flat_fold_merge.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
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
  FlatFoldMerger(const Mesh& mesh, const FaceGeometry& geometry, double cone, Segmentation& segmentation)
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
      if (!joinable(a, b, adjacency, faces)) continue;
      const int kept = seed_rank[static_cast<std::size_t>(a)] <= seed_rank[static_cast<std::size_t>(b)] ? a : b;
      const int joined = kept == a ? b : a;
      for (const int f : faces[static_cast<std::size_t>(joined)]) segmentation_.chart_of_face[static_cast<std::size_t>(f)] = kept;
      changed[static_cast<std::size_t>(a)] = changed[static_cast<std::size_t>(b)] = 1;
      any = true;
    }
    return any;
  }

  [[nodiscard]] bool joinable(int a, int b, const ChartAdjacency& adjacency,
                              const std::vector<std::vector<int>>& faces) const {
    const ChartBorder& border = adjacency.borders.at({a, b});
    if (!border_worth_joining(adjacency, a, b) || !is_one_path(border)) return false;
    // A single face hinged to the other chart by one edge unfolds about it without stretch at any
    // angle (a flap a scan left at a hole's rim, folded back): the flattening checks it against
    // lapping over the chart as it checks every layout.
    if (border.edges.size() == 1 && (faces[static_cast<std::size_t>(a)].size() == 1 || faces[static_cast<std::size_t>(b)].size() == 1))
      return true;
    std::vector<int> both = faces[static_cast<std::size_t>(a)];
    both.insert(both.end(), faces[static_cast<std::size_t>(b)].begin(), faces[static_cast<std::size_t>(b)].end());
    if (!normals_within_cone(geometry_, both, cone_cosine_)) return false;
    // The curvature the union brings inside: the defects of the border's vertices that become
    // interior.
    std::vector<int> vertices;
    for (const auto& [v, w] : border.edges) {
      vertices.push_back(v);
      vertices.push_back(w);
    }
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    double defect = 0.0;
    for (const int v : vertices) {
      double angle_sum = 0.0;
      if (!interior_of_union(v, a, b, angle_sum)) continue;
      defect += std::abs(2.0 * std::numbers::pi - angle_sum);
      if (defect > kFlatFoldDefect) return false;
    }
    return true;
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
  const FaceGeometry& geometry_;
  const double cone_cosine_;
  Segmentation& segmentation_;
  VertexStars stars_;
};

}  // namespace

void merge_across_flat_folds(const Mesh& mesh, const FaceGeometry& geometry, double cone,
                             Segmentation& segmentation) {
  FlatFoldMerger(mesh, geometry, cone, segmentation).run();
}

}  // namespace harmonia::detail
