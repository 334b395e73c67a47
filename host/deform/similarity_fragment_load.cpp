#include "deform/similarity_fragment_load.h"

#include "harmonia/laplacian.h"

namespace harmonia::detail {

SimilarityFragmentLoad::SimilarityFragmentLoad(const Mesh& rest)
    : faces_(rest.faces), vertex_count_(rest.vertex_count()), corner_loads_(3, 3 * rest.face_count()) {
  for (Eigen::Index f = 0; f < faces_.rows(); ++f) {
    const Eigen::Vector3i corner = faces_.row(f);
    Eigen::Vector3d position[3];
    for (int k = 0; k < 3; ++k) position[k] = rest.vertices.row(corner[k]);
    // half_cot[k] weights the edge opposite corner k (harmonia::laplacian's cotangent scheme).
    const Eigen::Vector3d half_cot = cotangent_half_weights(position[0], position[1], position[2]);
    for (int k = 0; k < 3; ++k) {
      const int next = (k + 1) % 3, previous = (k + 2) % 3;
      corner_loads_.col(3 * f + k) = half_cot[previous] * (position[k] - position[next]) +
                                     half_cot[next] * (position[k] - position[previous]);
    }
  }
}

void SimilarityFragmentLoad::assemble(const TriangleSimilarities& similarities,
                                      Eigen::MatrixXd& load) const {
  gather(
      [&similarities](Eigen::Index f) {
        return Eigen::Matrix3d(similarities.scale[f] *
                               similarities.rotation[static_cast<std::size_t>(f)].toRotationMatrix());
      },
      load);
}

void SimilarityFragmentLoad::assemble(const std::vector<Eigen::Matrix3d>& linear,
                                      Eigen::MatrixXd& load) const {
  gather([&linear](Eigen::Index f) { return linear[static_cast<std::size_t>(f)]; }, load);
}

void SimilarityFragmentLoad::assemble(const GroupMix& mix, const std::vector<Eigen::Matrix3d>& group_linear,
                                      Eigen::MatrixXd& load) const {
  gather(
      [&](Eigen::Index f) {
        const int first = mix.start[static_cast<std::size_t>(f)], end = mix.start[static_cast<std::size_t>(f) + 1];
        // Most triangles lie inside one group: its linear part as it is.
        if (end - first == 1) return group_linear[static_cast<std::size_t>(mix.group[static_cast<std::size_t>(first)])];
        Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
        for (int i = first; i < end; ++i)
          sum += mix.weight[static_cast<std::size_t>(i)] *
                 group_linear[static_cast<std::size_t>(mix.group[static_cast<std::size_t>(i)])];
        return sum;
      },
      load);
}

}  // namespace harmonia::detail
