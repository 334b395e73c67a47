#pragma once
// Internal: the Poisson right-hand side of a fragmented mesh whose triangles are the rest triangles
// moved by per-triangle similarities (thesis 8.3): b = div(grad of the fragmented target).
//
// A similarity keeps angles, so a transformed triangle has the rest triangle's cotangent weights,
// and its stiffness applied to its own corners is the rest one's turned and scaled: the load of
// corner k of face f is M_f c_fk, with c_fk = sum over the corner's two edges (k, j) of
// cot(opposite angle)/2 (x_k - x_j) at rest. The c_fk are computed once; a frame costs one 3x3
// product per corner. With every M_f = I the loads sum to L x_rest (L: the cotangent Laplacian).

#include <vector>

#include <Eigen/Core>

#include "deform/triangle_transforms.h"
#include "deform/two_way_split.h"
#include "harmonia/mesh.h"

namespace harmonia::detail {

// Each triangle's share of some groups (CSR over the triangles, the weights of one summing to 1).
struct GroupMix {
  std::vector<int> start{0};  // #F + 1: triangle f's entries are [start[f], start[f + 1])
  std::vector<int> group;
  std::vector<double> weight;
};

class SimilarityFragmentLoad {
 public:
  explicit SimilarityFragmentLoad(const Mesh& rest);

  // load (#V by 3, its storage reused): the loads of the triangles turned and scaled by
  // `similarities`, summed at the shared vertices.
  void assemble(const TriangleSimilarities& similarities, Eigen::MatrixXd& load) const;
  // The same for any linear part per triangle (#F; e.g. a mean of rotations, arap_refinement.h).
  void assemble(const std::vector<Eigen::Matrix3d>& linear, Eigen::MatrixXd& load) const;
  // The same for linear parts given per group (a rotation cluster's s_c R_c,
  // deform/clustered_rotation_fit.h), each triangle's a weighted sum of its groups'.
  void assemble(const GroupMix& mix, const std::vector<Eigen::Matrix3d>& group_linear, Eigen::MatrixXd& load) const;
  // c_fk, column 3 f + k.
  [[nodiscard]] const Eigen::Matrix3Xd& corner_loads() const { return corner_loads_; }

 private:
  // Sums linear_part(f) * c_fk at the corners' vertices.
  // Two halves of the faces on two threads, each into its own sum (split_two_ways).
  template <typename LinearPart>
  void gather(const LinearPart& linear_part, Eigen::MatrixXd& load) const {
    Eigen::MatrixXd* sums[2] = {&load, &second_half_load_};
    const int parts = split_two_ways(faces_.rows(), [&](int part, Eigen::Index begin, Eigen::Index end) {
      Eigen::MatrixXd& sum = *sums[part];
      sum.resize(vertex_count_, 3);
      sum.setZero();
      for (Eigen::Index f = begin; f < end; ++f) {
        const Eigen::Matrix3d transform = linear_part(f);
        for (int k = 0; k < 3; ++k)
          sum.row(faces_(f, k)) += (transform * corner_loads_.col(3 * f + k)).transpose();
      }
    });
    if (parts == 2) load += second_half_load_;
  }

  Eigen::MatrixX3i faces_;
  int vertex_count_ = 0;
  Eigen::Matrix3Xd corner_loads_;  // column 3 f + k: c_fk
  mutable Eigen::MatrixXd second_half_load_;  // the second thread's sum, its storage reused
};

}  // namespace harmonia::detail
