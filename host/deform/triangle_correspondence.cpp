#include "deform/triangle_correspondence.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <numeric>
#include <utility>

#include "deform/surface_folds.h"
#include "deform/two_way_split.h"

namespace harmonia::detail {

TriangleCorrespondence match_triangles(const Eigen::MatrixXd& source_fields,
                                       const Eigen::MatrixXd& target_fields,
                                       const Eigen::MatrixX3i& target_faces, int components,
                                       double max_distance) {
  const Eigen::Index marker_count = source_fields.cols();
  const int compared = static_cast<int>(std::min<Eigen::Index>(components, marker_count));
  // The source triangles by their largest component (the lowest index on a tie), each bucket
  // sorted by that component: the distance to a target triangle is at least the difference in
  // that one component, so a bucket is searched outward from the target's value and left as soon
  // as the difference alone exceeds the best distance so far. The result is the exhaustive
  // search's; the cost falls from the bucket's size to the triangles near the target's value.
  struct Candidate {
    double value = 0.0;  // the bucket marker's component
    int source = 0;
  };
  std::vector<std::vector<Candidate>> by_dominant(static_cast<std::size_t>(marker_count));
  for (Eigen::Index s = 0; s < source_fields.rows(); ++s) {
    Eigen::Index dominant = 0;
    const double value = source_fields.row(s).maxCoeff(&dominant);
    by_dominant[static_cast<std::size_t>(dominant)].push_back({value, static_cast<int>(s)});
  }
  for (std::vector<Candidate>& bucket : by_dominant)
    std::sort(bucket.begin(), bucket.end(), [](const Candidate& a, const Candidate& b) {
      return a.value != b.value ? a.value < b.value : a.source < b.source;
    });
  TriangleCorrespondence result;
  result.source_triangle.assign(static_cast<std::size_t>(target_fields.rows()), -1);
  split_two_ways(target_fields.rows(), [&](int, Eigen::Index begin, Eigen::Index end) {
    std::vector<int> order(static_cast<std::size_t>(marker_count));
    for (Eigen::Index t = begin; t < end; ++t) {
      // The target's largest components, largest first (ties to the lower index).
      std::iota(order.begin(), order.end(), 0);
      std::partial_sort(order.begin(), order.begin() + compared, order.end(), [&](int a, int b) {
        const double x = target_fields(t, a), y = target_fields(t, b);
        return x != y ? x > y : a < b;
      });
      double best = std::numeric_limits<double>::infinity();
      int best_source = -1;
      const auto consider = [&](int s) {
        double squared = 0.0;
        for (int i = 0; i < compared && squared <= best; ++i) {
          const int marker = order[static_cast<std::size_t>(i)];
          const double difference = target_fields(t, marker) - source_fields(s, marker);
          squared += difference * difference;
        }
        if (squared < best || (squared == best && s < best_source)) {
          best = squared;
          best_source = s;
        }
      };
      for (int c = 0; c < compared; ++c) {
        const int marker = order[static_cast<std::size_t>(c)];
        const std::vector<Candidate>& bucket = by_dominant[static_cast<std::size_t>(marker)];
        const double value = target_fields(t, marker);
        const auto start = std::lower_bound(bucket.begin(), bucket.end(), value,
                                             [](const Candidate& a, double v) { return a.value < v; });
        for (auto up = start; up != bucket.end(); ++up) {
          const double gap = up->value - value;
          if (gap * gap > best) break;
          consider(up->source);
        }
        for (auto down = start; down != bucket.begin();) {
          --down;
          const double gap = value - down->value;
          if (gap * gap > best) break;
          consider(down->source);
        }
      }
      if (best_source >= 0 && std::sqrt(best) <= max_distance)
        result.source_triangle[static_cast<std::size_t>(t)] = best_source;
    }
  });
  // The unmatched take their nearest matched neighbour's match (breadth first from all matched).
  std::deque<int> frontier;
  for (std::size_t t = 0; t < result.source_triangle.size(); ++t)
    if (result.source_triangle[t] >= 0) {
      frontier.push_back(static_cast<int>(t));
      ++result.matched;
    }
  result.unmatched = static_cast<int>(result.source_triangle.size()) - result.matched;
  if (result.unmatched > 0) {
    const std::vector<std::vector<int>> neighbours = edge_neighbours(target_faces);
    while (!frontier.empty()) {
      const int t = frontier.front();
      frontier.pop_front();
      for (const int g : neighbours[static_cast<std::size_t>(t)])
        if (result.source_triangle[static_cast<std::size_t>(g)] < 0) {
          result.source_triangle[static_cast<std::size_t>(g)] =
              result.source_triangle[static_cast<std::size_t>(t)];
          frontier.push_back(g);
        }
    }
  }
  return result;
}

}  // namespace harmonia::detail
