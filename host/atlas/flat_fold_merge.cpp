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
  // The edges where two different charts meet across a manifold edge, per pair of charts.
  struct Border {
    double length = 0.0;
    std::vector<std::pair<int, int>> edges;  // vertex pairs
  };

  [[nodiscard]] int chart_of(int face) const { return segmentation_.chart_of_face[static_cast<std::size_t>(face)]; }
  [[nodiscard]] int seed_rank(int chart) const {
    return geometry_.rank[static_cast<std::size_t>(segmentation_.seed_of_chart[static_cast<std::size_t>(chart)])];
  }

  // One round: every pair of neighbouring charts, longest border first, joined where allowed;
  // a chart joins at most once per round (its figures change). Returns whether any joined.
  bool merge_round() {
    std::map<std::pair<int, int>, Border> borders;
    perimeter_.assign(static_cast<std::size_t>(segmentation_.chart_count), 0.0);
    area_.assign(static_cast<std::size_t>(segmentation_.chart_count), 0.0);
    for (int f = 0; f < geometry_.face_count(); ++f) {
      const int chart = chart_of(f);
      if (chart < 0) continue;
      area_[static_cast<std::size_t>(chart)] += geometry_.area[static_cast<std::size_t>(f)];
      for (int k = 0; k < 3; ++k) {
        const int g = geometry_.across[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
        if (g < 0 || chart_of(g) != chart)
          perimeter_[static_cast<std::size_t>(chart)] += geometry_.edge_length[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
        if (g < f) continue;  // each edge once (g = -1: no neighbour)
        const int other = chart_of(g);
        if (other < 0 || other == chart) continue;
        Border& border = borders[std::pair<int, int>(std::min(chart, other), std::max(chart, other))];
        border.length += geometry_.edge_length[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
        border.edges.emplace_back(mesh_.faces(f, k), mesh_.faces(f, (k + 1) % 3));
      }
    }
    if (borders.empty()) return false;
    std::vector<const std::pair<const std::pair<int, int>, Border>*> order;
    for (const auto& entry : borders) order.push_back(&entry);
    std::sort(order.begin(), order.end(), [&](const auto* x, const auto* y) {
      if (x->second.length != y->second.length) return x->second.length > y->second.length;
      const auto ranks = [&](const std::pair<int, int>& pair) {
        const int first = seed_rank(pair.first), second = seed_rank(pair.second);
        return std::pair<int, int>(std::min(first, second), std::max(first, second));  // by value
      };
      return ranks(x->first) < ranks(y->first);
    });
    std::vector<std::vector<int>> faces(static_cast<std::size_t>(segmentation_.chart_count));
    for (int f = 0; f < geometry_.face_count(); ++f)
      if (chart_of(f) >= 0) faces[static_cast<std::size_t>(chart_of(f))].push_back(f);
    std::vector<char> changed(static_cast<std::size_t>(segmentation_.chart_count), 0);
    bool any = false;
    for (const auto* entry : order) {
      const auto [a, b] = entry->first;
      if (changed[static_cast<std::size_t>(a)] || changed[static_cast<std::size_t>(b)]) continue;
      if (!joinable(a, b, entry->second, faces)) continue;
      const int kept = seed_rank(a) <= seed_rank(b) ? a : b, joined = kept == a ? b : a;
      for (const int f : faces[static_cast<std::size_t>(joined)]) segmentation_.chart_of_face[static_cast<std::size_t>(f)] = kept;
      changed[static_cast<std::size_t>(a)] = changed[static_cast<std::size_t>(b)] = 1;
      any = true;
    }
    return any;
  }

  [[nodiscard]] bool joinable(int a, int b, const Border& border, const std::vector<std::vector<int>>& faces) const {
    // A border too short for its seam to matter: joining at it would only hinge two charts
    // at a corner, an awkward shape to pack for little seam saved.
    const double shorter_perimeter =
        std::min(perimeter_[static_cast<std::size_t>(a)], perimeter_[static_cast<std::size_t>(b)]);
    if (border.length < kLeastBorderShare * shorter_perimeter) return false;
    // The union about as compact as its parts were, area for area (isoperimetric ratio
    // 4 pi area / perimeter^2, 1 for a disk): an L or a hook packs worse than its parts did.
    const auto compactness = [this](int chart) {
      const double area = area_[static_cast<std::size_t>(chart)], perimeter = perimeter_[static_cast<std::size_t>(chart)];
      return perimeter > 0.0 ? 4.0 * std::numbers::pi * area / (perimeter * perimeter) : 0.0;
    };
    const double area_a = area_[static_cast<std::size_t>(a)], area_b = area_[static_cast<std::size_t>(b)];
    const double union_perimeter =
        perimeter_[static_cast<std::size_t>(a)] + perimeter_[static_cast<std::size_t>(b)] - 2.0 * border.length;
    const double union_compactness =
        union_perimeter > 0.0 ? 4.0 * std::numbers::pi * (area_a + area_b) / (union_perimeter * union_perimeter) : 0.0;
    const double parts_compactness = (area_a * compactness(a) + area_b * compactness(b)) / (area_a + area_b);
    if (!(union_compactness >= kCompactnessKept * parts_compactness)) return false;
    if (!one_path(border)) return false;
    // A single face hinged to the other chart by one edge unfolds about it without stretch at any
    // angle (a flap a scan left at a hole's rim, folded back): the flattening checks it against
    // lapping over the chart as it checks every layout.
    if (border.edges.size() == 1 && (faces[static_cast<std::size_t>(a)].size() == 1 || faces[static_cast<std::size_t>(b)].size() == 1))
      return true;
    // The union's normals within the cone of its mean normal.
    Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
    for (const int chart : {a, b})
      for (const int f : faces[static_cast<std::size_t>(chart)])
        normal_sum += geometry_.area[static_cast<std::size_t>(f)] * geometry_.normal[static_cast<std::size_t>(f)];
    if (!(normal_sum.norm() > 0.0)) return false;
    const Eigen::Vector3d mean = normal_sum.normalized();
    for (const int chart : {a, b})
      for (const int f : faces[static_cast<std::size_t>(chart)])
        if (geometry_.normal[static_cast<std::size_t>(f)].dot(mean) < cone_cosine_) return false;
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

  // Whether the border's edges form one simple path (not a cycle, not several pieces).
  [[nodiscard]] static bool one_path(const Border& border) {
    std::map<int, std::vector<int>> neighbours;
    for (const auto& [v, w] : border.edges) {
      neighbours[v].push_back(w);
      neighbours[w].push_back(v);
    }
    int ends = 0;
    for (const auto& [v, around] : neighbours) {
      if (around.size() > 2) return false;
      if (around.size() == 1) ++ends;
    }
    if (ends != 2) return false;  // a cycle has none, several pieces have more
    // Connected: a walk from one end reaches every vertex.
    int previous = -1;
    int current = std::find_if(neighbours.begin(), neighbours.end(), [](const auto& entry) {
                    return entry.second.size() == 1;
                  })->first;
    std::size_t visited = 1;
    while (true) {
      const std::vector<int>& around = neighbours[current];
      const int next = around[0] != previous ? around[0] : (around.size() > 1 ? around[1] : -1);
      if (next < 0 || next == previous) break;
      previous = current;
      current = next;
      ++visited;
      if (neighbours[current].size() == 1) break;
    }
    return visited == neighbours.size();
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
  std::vector<double> perimeter_;  // per chart, this round
  std::vector<double> area_;       // per chart, this round
};

}  // namespace

void merge_across_flat_folds(const Mesh& mesh, const FaceGeometry& geometry, double cone,
                             Segmentation& segmentation) {
  FlatFoldMerger(mesh, geometry, cone, segmentation).run();
}

}  // namespace harmonia::detail
