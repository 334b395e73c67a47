#pragma once
// Internal: the triangle correspondence of deformation transfer (thesis 8.4): each target
// triangle matched to the source triangle whose marker-field vector is closest on the target's n
// largest components (harmonia/deformation_transfer.h).

#include <vector>

#include <Eigen/Core>

namespace harmonia::detail {

struct TriangleCorrespondence {
  std::vector<int> source_triangle;  // per target triangle; -1 when nothing could be given
  int matched = 0;    // matched by their own fields
  int unmatched = 0;  // given the match of their nearest matched neighbour, or none
};

// `source_fields` (#F_s by k) and `target_fields` (#F_t by k): the triangles' field vectors;
// `target_faces` gives the target's edge adjacency for the unmatched ones. A target triangle's
// candidates are the source triangles whose largest component is one of its `components` largest;
// the best candidate is its match when its distance is at most `max_distance`. The others take the
// match of the nearest matched triangle across edges (breadth first; ties to the lower index).
[[nodiscard]] TriangleCorrespondence match_triangles(const Eigen::MatrixXd& source_fields,
                                                     const Eigen::MatrixXd& target_fields,
                                                     const Eigen::MatrixX3i& target_faces,
                                                     int components, double max_distance);

}  // namespace harmonia::detail
