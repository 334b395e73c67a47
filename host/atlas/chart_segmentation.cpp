#include "atlas/chart_segmentation.h"

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <cmath>
#include <numeric>
#include <queue>
#include <tuple>

namespace harmonia::detail {
namespace {

// Eliminating charts whose neighbours can take their faces: rounds, each followed by a Lloyd
// round (the survivors re-seeded and regrown). On the real assets three rounds found all but a
// few of what eight did.
constexpr int kEliminationRounds = 3;
// Absorbing small charts: passes (each one merges a chart at most once, then the figures are
// measured again); they join within joining_cone().
constexpr int kMergePasses = 3;
constexpr double kMergeConeFactor = 1.5;
constexpr double kLargestMergeCone = 89.0 * M_PI / 180.0;
// A chart this many times smaller than the neighbour it shares most of its border with joins it
// even when it is not mostly surrounded by it (a sliver between three charts).
constexpr double kTinyAreaRatio = 16.0;
// The share of a chart's border that a neighbour must hold for the chart to count as its island
// (all of it, but for the rounding of the summed lengths).
constexpr double kIslandBorderShare = 1.0 - 1e-9;

// A face waiting to join a chart: cheapest first, then the lower rank.
struct Candidate {
  double cost = 0.0;
  int rank = 0;
  int face = 0;
  int chart = 0;
  double distance = 0.0;  // path length from the chart's seed over the face centroids
  bool operator>(const Candidate& other) const {
    return std::tie(cost, rank, chart) > std::tie(other.cost, other.rank, other.chart);
  }
};
using CandidateQueue = std::priority_queue<Candidate, std::vector<Candidate>, std::greater<>>;

// What a chart is while it grows, and what the next relaxation round starts from.
struct ChartProxy {
  Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();  // area-weighted
  Eigen::Vector3d centroid_sum = Eigen::Vector3d::Zero();
  double area = 0.0;
  int seed = -1;

  [[nodiscard]] Eigen::Vector3d normal() const {
    const double length = normal_sum.norm();
    return length > 0.0 ? Eigen::Vector3d(normal_sum / length) : Eigen::Vector3d::Zero();
  }
  [[nodiscard]] Eigen::Vector3d centroid() const {
    return area > 0.0 ? Eigen::Vector3d(centroid_sum / area) : Eigen::Vector3d::Zero();
  }
  void add(const FaceGeometry& geometry, int face) {
    const auto f = static_cast<std::size_t>(face);
    normal_sum += geometry.area[f] * geometry.normal[f];
    centroid_sum += geometry.area[f] * geometry.centroid[f];
    area += geometry.area[f];
  }
};

class Segmenter {
 public:
  Segmenter(const FaceGeometry& geometry, const SegmentationOptions& options)
      : geometry_(geometry),
        options_(options),
        cone_cosine_(std::cos(options.max_normal_deviation)),
        merge_cone_cosine_(std::cos(joining_cone(options))),
        chart_of_face_(static_cast<std::size_t>(geometry.face_count()), -1) {
    order_by_flatness();
  }

  Segmentation run() {
    const int passes = 1 + options_.relaxation_rounds + kEliminationRounds + kMergePasses;
    if (!keep_going(0, passes)) return cancelled();
    grow_greedily();
    for (int round = 0; round < options_.relaxation_rounds; ++round) {
      if (!keep_going(1 + round, passes)) return cancelled();
      relax();
    }
    for (int round = 0; options_.eliminate_charts && round < kEliminationRounds; ++round) {
      if (!keep_going(1 + options_.relaxation_rounds + round, passes)) return cancelled();
      if (!eliminate_charts()) break;
      relax();
    }
    for (int pass = 0; pass < kMergePasses; ++pass) {
      if (!keep_going(1 + options_.relaxation_rounds + kEliminationRounds + pass, passes)) return cancelled();
      if (!absorb_small_charts()) break;
    }
    std::vector<int> seeds(charts_.size());
    for (std::size_t c = 0; c < charts_.size(); ++c) seeds[c] = charts_[c].seed;
    return {chart_of_face_, static_cast<int>(charts_.size()), std::move(seeds)};
  }

 private:
  [[nodiscard]] bool keep_going(int pass, int passes) const {
    return !options_.progress || options_.progress(Progress{"segmentation", pass, passes});
  }
  [[nodiscard]] static Segmentation cancelled() {
    Segmentation stopped;
    stopped.cancelled = true;
    return stopped;
  }

  [[nodiscard]] bool usable(int face) const {
    return !geometry_.degenerate[static_cast<std::size_t>(face)];
  }
  [[nodiscard]] double normal_cost(int face, const Eigen::Vector3d& proxy) const {
    return 1.0 - geometry_.normal[static_cast<std::size_t>(face)].dot(proxy);
  }
  [[nodiscard]] bool within_cone(int face, const Eigen::Vector3d& proxy) const {
    return geometry_.normal[static_cast<std::size_t>(face)].dot(proxy) >= cone_cosine_;
  }

  // Seeds are tried flattest first: the sum over a face's neighbours of (1 - n_f . n_g).
  void order_by_flatness() {
    const int count = geometry_.face_count();
    std::vector<double> bending(static_cast<std::size_t>(count), 0.0);
    for (int f = 0; f < count; ++f)
      for (const int g : geometry_.across[static_cast<std::size_t>(f)])
        if (g >= 0) bending[static_cast<std::size_t>(f)] += normal_cost(g, geometry_.normal[static_cast<std::size_t>(f)]);
    seed_order_.resize(static_cast<std::size_t>(count));
    std::iota(seed_order_.begin(), seed_order_.end(), 0);
    std::sort(seed_order_.begin(), seed_order_.end(), [&](int a, int b) {
      const double x = bending[static_cast<std::size_t>(a)], y = bending[static_cast<std::size_t>(b)];
      return x != y ? x < y : geometry_.rank[static_cast<std::size_t>(a)] < geometry_.rank[static_cast<std::size_t>(b)];
    });
  }

  // The first pass (and the faces a relaxation round leaves): one chart at a time, from the
  // flattest free face, taking the cheapest faces across its border that lie within the cone of
  // its current mean normal.
  void grow_greedily() {
    for (const int seed : seed_order_) {
      if (!usable(seed) || chart_of_face_[static_cast<std::size_t>(seed)] >= 0) continue;
      const int chart = static_cast<int>(charts_.size());
      charts_.emplace_back();
      charts_.back().seed = seed;
      CandidateQueue queue;
      queue.push({0.0, geometry_.rank[static_cast<std::size_t>(seed)], seed, chart, 0.0});
      while (!queue.empty()) {
        const Candidate next = queue.top();
        queue.pop();
        if (chart_of_face_[static_cast<std::size_t>(next.face)] >= 0) continue;
        ChartProxy& proxy = charts_[static_cast<std::size_t>(chart)];
        if (next.face != seed && !within_cone(next.face, proxy.normal())) continue;
        chart_of_face_[static_cast<std::size_t>(next.face)] = chart;
        proxy.add(geometry_, next.face);
        const Eigen::Vector3d normal = proxy.normal();
        for (const int g : geometry_.across[static_cast<std::size_t>(next.face)])
          if (g >= 0 && chart_of_face_[static_cast<std::size_t>(g)] < 0 && within_cone(g, normal))
            queue.push({normal_cost(g, normal), geometry_.rank[static_cast<std::size_t>(g)], g, chart, 0.0});
      }
    }
  }

  // One Lloyd round: proxies and seeds from the current charts, then all charts regrown together.
  void relax() {
    std::vector<ChartProxy> proxies(charts_.size());
    for (int f = 0; f < geometry_.face_count(); ++f)
      if (const int chart = chart_of_face_[static_cast<std::size_t>(f)]; chart >= 0)
        proxies[static_cast<std::size_t>(chart)].add(geometry_, f);
    std::vector<double> best_seed_cost(charts_.size(), std::numeric_limits<double>::infinity());
    for (int f = 0; f < geometry_.face_count(); ++f) {
      const int chart = chart_of_face_[static_cast<std::size_t>(f)];
      if (chart < 0) continue;
      ChartProxy& proxy = proxies[static_cast<std::size_t>(chart)];
      const double cost = seed_cost(f, proxy);
      double& best = best_seed_cost[static_cast<std::size_t>(chart)];
      if (proxy.seed < 0 || cost < best ||
          (cost == best && geometry_.rank[static_cast<std::size_t>(f)] <
                               geometry_.rank[static_cast<std::size_t>(proxy.seed)])) {
        best = cost;
        proxy.seed = f;
      }
    }
    std::fill(chart_of_face_.begin(), chart_of_face_.end(), -1);
    CandidateQueue queue;
    std::vector<Eigen::Vector3d> normals(proxies.size());
    std::vector<double> radii(proxies.size());
    for (std::size_t c = 0; c < proxies.size(); ++c) {
      normals[c] = proxies[c].normal();
      radii[c] = std::sqrt(proxies[c].area / M_PI);
      const int seed = proxies[c].seed;
      queue.push({0.0, geometry_.rank[static_cast<std::size_t>(seed)], seed, static_cast<int>(c), 0.0});
    }
    while (!queue.empty()) {
      const Candidate next = queue.top();
      queue.pop();
      if (chart_of_face_[static_cast<std::size_t>(next.face)] >= 0) continue;
      chart_of_face_[static_cast<std::size_t>(next.face)] = next.chart;
      const auto c = static_cast<std::size_t>(next.chart);
      for (const int g : geometry_.across[static_cast<std::size_t>(next.face)]) {
        if (g < 0 || chart_of_face_[static_cast<std::size_t>(g)] >= 0 || !within_cone(g, normals[c])) continue;
        const double distance = next.distance + (geometry_.centroid[static_cast<std::size_t>(g)] -
                                                 geometry_.centroid[static_cast<std::size_t>(next.face)]).norm();
        const double reach = radii[c] > 0.0 ? distance / radii[c] : 0.0;
        queue.push({normal_cost(g, normals[c]) + options_.compactness * reach * reach,
                    geometry_.rank[static_cast<std::size_t>(g)], g, next.chart, distance});
      }
    }
    // Each chart keeps the seed it regrew from: the tie-breaks of absorb_small_charts rank charts
    // by their seeds, so a chart without one would have no place in the face-order-free order.
    charts_.assign(proxies.size(), ChartProxy{});
    for (std::size_t c = 0; c < proxies.size(); ++c) charts_[c].seed = proxies[c].seed;
    for (int f = 0; f < geometry_.face_count(); ++f)
      if (const int chart = chart_of_face_[static_cast<std::size_t>(f)]; chart >= 0)
        charts_[static_cast<std::size_t>(chart)].add(geometry_, f);
    grow_greedily();  // what no chart could take within its cone
  }

  // Lloyd rounds keep the number of charts the greedy pass started with, and on a smooth surface
  // that pass leaves more than the cone needs (a sphere: ten caps and crescents where six
  // cube-like charts stay within 60 degrees). So, smallest first, a chart whose faces its
  // neighbours can share out among themselves disappears: its faces go, cheapest first from its
  // border, each to a neighbour within whose cone it lies, and the removal stands only if every
  // face found a neighbour and every grown neighbour still holds all its faces within the cone
  // around its new mean normal. Returns whether any chart disappeared.
  bool eliminate_charts() {
    const auto chart_count = charts_.size();
    std::vector<std::vector<int>> faces(chart_count);
    for (int f = 0; f < geometry_.face_count(); ++f)
      if (const int chart = chart_of_face_[static_cast<std::size_t>(f)]; chart >= 0)
        faces[static_cast<std::size_t>(chart)].push_back(f);
    std::vector<int> order(chart_count);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      const double x = charts_[static_cast<std::size_t>(a)].area, y = charts_[static_cast<std::size_t>(b)].area;
      return x != y ? x < y : seed_rank(a) < seed_rank(b);
    });
    std::vector<char> gone(chart_count, 0);
    std::vector<int> taker(static_cast<std::size_t>(geometry_.face_count()), -1);  // per face, during a trial
    bool any = false;
    for (const int chart : order) {
      const auto c = static_cast<std::size_t>(chart);
      if (faces[c].empty()) continue;
      // Each face of the chart goes to the neighbour that reaches it cheapest, within its cone.
      CandidateQueue queue;
      for (const int f : faces[c])
        for (const int g : geometry_.across[static_cast<std::size_t>(f)]) {
          const int other = g >= 0 ? chart_of_face_[static_cast<std::size_t>(g)] : -1;
          if (other < 0 || other == chart) continue;
          const Eigen::Vector3d normal = charts_[static_cast<std::size_t>(other)].normal();
          if (within_cone(f, normal))
            queue.push({normal_cost(f, normal), geometry_.rank[static_cast<std::size_t>(f)], f, other, 0.0});
        }
      // The neighbours grow as they take faces: each face is tested against the mean normal of
      // its taker at the moment it is taken, as in the greedy pass.
      std::size_t taken = 0;
      std::vector<int> grown;                 // the neighbours that took a face
      std::vector<ChartProxy> grown_proxies;  // their figures with what they took
      const auto trial_proxy = [&](int other) -> ChartProxy& {
        const auto at = std::find(grown.begin(), grown.end(), other);
        if (at != grown.end()) return grown_proxies[static_cast<std::size_t>(at - grown.begin())];
        grown.push_back(other);
        grown_proxies.push_back(charts_[static_cast<std::size_t>(other)]);
        return grown_proxies.back();
      };
      while (!queue.empty()) {
        const Candidate next = queue.top();
        queue.pop();
        if (taker[static_cast<std::size_t>(next.face)] >= 0) continue;
        ChartProxy& proxy = trial_proxy(next.chart);
        if (!within_cone(next.face, proxy.normal())) continue;
        taker[static_cast<std::size_t>(next.face)] = next.chart;
        ++taken;
        proxy.add(geometry_, next.face);
        const Eigen::Vector3d normal = proxy.normal();
        for (const int g : geometry_.across[static_cast<std::size_t>(next.face)])
          if (g >= 0 && chart_of_face_[static_cast<std::size_t>(g)] == chart &&
              taker[static_cast<std::size_t>(g)] < 0 && within_cone(g, normal))
            queue.push({normal_cost(g, normal), geometry_.rank[static_cast<std::size_t>(g)], g, next.chart, 0.0});
      }
      bool removable = taken == faces[c].size();
      // Every grown neighbour keeps all its faces, old and new, within the cone of its new normal.
      for (std::size_t k = 0; removable && k < grown.size(); ++k) {
        const Eigen::Vector3d normal = grown_proxies[k].normal();
        for (const int f : faces[static_cast<std::size_t>(grown[k])])
          if (!within_cone(f, normal)) removable = false;
        for (const int f : faces[c])
          if (taker[static_cast<std::size_t>(f)] == grown[k] && !within_cone(f, normal)) removable = false;
      }
      if (removable) {
        for (std::size_t k = 0; k < grown.size(); ++k) charts_[static_cast<std::size_t>(grown[k])] = grown_proxies[k];
        for (const int f : faces[c]) {
          const int target = taker[static_cast<std::size_t>(f)];
          chart_of_face_[static_cast<std::size_t>(f)] = target;
          faces[static_cast<std::size_t>(target)].push_back(f);
        }
        faces[c].clear();
        gone[c] = 1;
        any = true;
      }
      // Clear the trial's marks (a removed chart's faces now belong to the neighbours).
      for (const int f : faces[c]) taker[static_cast<std::size_t>(f)] = -1;
      for (const int g : grown)
        for (const int f : faces[static_cast<std::size_t>(g)]) taker[static_cast<std::size_t>(f)] = -1;
    }
    if (!any) return false;
    renumber_emptied(gone);
    return true;
  }

  // A chart mostly surrounded by one neighbour (sharing at least half of its perimeter with it)
  // and smaller than it joins it when all its faces lie within the wider merge cone around the
  // neighbour's normal: the slivers and single faces that the relaxation leaves between charts,
  // and the islands inside a chart (which would make it an annulus). Returns whether any joined.
  bool absorb_small_charts() {
    const auto chart_count = charts_.size();
    std::vector<double> perimeter(chart_count, 0.0);
    std::vector<std::map<int, double>> shared(chart_count);  // neighbour chart -> shared length
    for (int f = 0; f < geometry_.face_count(); ++f) {
      const int chart = chart_of_face_[static_cast<std::size_t>(f)];
      if (chart < 0) continue;
      for (int k = 0; k < 3; ++k) {
        const int other = geometry_.across[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
        const int other_chart = other >= 0 ? chart_of_face_[static_cast<std::size_t>(other)] : -1;
        if (other_chart == chart) continue;
        const double length = geometry_.edge_length[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
        perimeter[static_cast<std::size_t>(chart)] += length;
        if (other_chart >= 0) shared[static_cast<std::size_t>(chart)][other_chart] += length;
      }
    }
    std::vector<int> order(chart_count);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      const double x = charts_[static_cast<std::size_t>(a)].area, y = charts_[static_cast<std::size_t>(b)].area;
      return x != y ? x < y : seed_rank(a) < seed_rank(b);
    });
    std::vector<std::vector<int>> faces(chart_count);
    for (int f = 0; f < geometry_.face_count(); ++f)
      if (const int chart = chart_of_face_[static_cast<std::size_t>(f)]; chart >= 0)
        faces[static_cast<std::size_t>(chart)].push_back(f);
    std::vector<int> merged_into(chart_count, -1);
    std::vector<char> grew(chart_count, 0);  // changed this pass: its neighbours' figures are stale
    bool any = false;
    for (const int chart : order) {
      const auto c = static_cast<std::size_t>(chart);
      if (grew[c]) continue;
      int best = -1;
      double best_length = 0.0;
      for (const auto& [other, length] : shared[c])
        if (length > best_length || (length == best_length && best >= 0 && seed_rank(other) < seed_rank(best))) {
          best = other;
          best_length = length;
        }
      if (best < 0 || merged_into[static_cast<std::size_t>(best)] >= 0 || grew[static_cast<std::size_t>(best)] ||
          charts_[static_cast<std::size_t>(best)].area < charts_[c].area)
        continue;
      const bool surrounded = best_length >= 0.5 * perimeter[c];
      const bool tiny = charts_[c].area * kTinyAreaRatio <= charts_[static_cast<std::size_t>(best)].area;
      if (!surrounded && !tiny) continue;
      // An island, all of whose border the neighbour holds, joins it whatever its normals: the
      // flattening works on lengths and angles, which a spike folded over its neighbours keeps,
      // and the neighbour would otherwise have a hole to cut open.
      const bool island = best_length >= kIslandBorderShare * perimeter[c];
      if (!island && !faces_within(faces[c], charts_[static_cast<std::size_t>(best)].normal(), merge_cone_cosine_))
        continue;
      merged_into[c] = best;
      grew[static_cast<std::size_t>(best)] = 1;
      grew[c] = 1;
      any = true;
    }
    if (!any) return false;
    renumber(merged_into);
    return true;
  }

  // Whether every one of `faces` has its normal within the cone of `cosine` around `normal`.
  [[nodiscard]] bool faces_within(const std::vector<int>& faces, const Eigen::Vector3d& normal,
                                  double cosine) const {
    for (const int f : faces)
      if (geometry_.normal[static_cast<std::size_t>(f)].dot(normal) < cosine) return false;
    return true;
  }

  [[nodiscard]] int seed_rank(int chart) const {
    return geometry_.rank[static_cast<std::size_t>(charts_[static_cast<std::size_t>(chart)].seed)];
  }

  // Charts merged into others disappear; the rest keep their order.
  void renumber(const std::vector<int>& merged_into) {
    std::vector<int> number(merged_into.size(), -1);
    std::vector<ChartProxy> kept;
    for (std::size_t c = 0; c < merged_into.size(); ++c)
      if (merged_into[c] < 0) {
        number[c] = static_cast<int>(kept.size());
        kept.push_back(charts_[c]);
      }
    for (int f = 0; f < geometry_.face_count(); ++f) {
      int& chart = chart_of_face_[static_cast<std::size_t>(f)];
      if (chart < 0) continue;
      const int target = merged_into[static_cast<std::size_t>(chart)] >= 0 ? merged_into[static_cast<std::size_t>(chart)] : chart;
      if (target != chart) kept[static_cast<std::size_t>(number[static_cast<std::size_t>(target)])].add(geometry_, f);
      chart = number[static_cast<std::size_t>(target)];
    }
    charts_ = std::move(kept);
  }

  // Charts emptied by eliminate_charts (their faces already moved) disappear; the rest keep
  // their order, their figures and their seeds.
  void renumber_emptied(const std::vector<char>& gone) {
    std::vector<int> number(gone.size(), -1);
    std::vector<ChartProxy> kept;
    for (std::size_t c = 0; c < gone.size(); ++c)
      if (!gone[c]) {
        number[c] = static_cast<int>(kept.size());
        kept.push_back(charts_[c]);
      }
    for (int& chart : chart_of_face_)
      if (chart >= 0) chart = number[static_cast<std::size_t>(chart)];
    charts_ = std::move(kept);
  }

  // How well a face would seed its chart: its normal against the chart's, and its distance from
  // the chart's centroid against the chart's radius.
  [[nodiscard]] double seed_cost(int face, const ChartProxy& proxy) const {
    const double radius_squared = proxy.area / M_PI;
    const double offset_squared = (geometry_.centroid[static_cast<std::size_t>(face)] - proxy.centroid()).squaredNorm();
    return normal_cost(face, proxy.normal()) +
           options_.compactness * (radius_squared > 0.0 ? offset_squared / radius_squared : 0.0);
  }

  const FaceGeometry& geometry_;
  const SegmentationOptions options_;
  const double cone_cosine_;
  const double merge_cone_cosine_;
  std::vector<int> chart_of_face_;
  std::vector<ChartProxy> charts_;
  std::vector<int> seed_order_;
};

}  // namespace

double joining_cone(const SegmentationOptions& options) {
  return std::min(kMergeConeFactor * options.max_normal_deviation, kLargestMergeCone);
}

Segmentation segment_into_charts(const FaceGeometry& geometry, const SegmentationOptions& options) {
  return Segmenter(geometry, options).run();
}

}  // namespace harmonia::detail
