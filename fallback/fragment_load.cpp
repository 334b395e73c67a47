// The Poisson load of a fragmented mesh on the CPU (fragment_load.h).

#include "fallback/fragment_load.h"

#include <future>

#include "harmonia/laplacian.h"
#include "mesh/helper_tasks.h"

namespace harmonia::detail {
namespace {

// Adds S_f F_f of the faces [begin, end) to `load`, in face order.
void add_fragment_loads(const Eigen::MatrixX3i& faces, const PairStiffness& stiffness,
                        const Eigen::MatrixXd& fragments, Eigen::Index begin, Eigen::Index end,
                        Eigen::MatrixXd& load) {
  for (Eigen::Index f = begin; f < end; ++f) {
    for (int a = 0; a < 3; ++a) {
      const int b = (a + 1) % 3;
      for (Eigen::Index column = 0; column < fragments.cols(); ++column) {
        const double term =
            stiffness(f, a) * (fragments(3 * f + b, column) - fragments(3 * f + a, column));
        load(faces(f, a), column) += term;
        load(faces(f, b), column) -= term;
      }
    }
  }
}

}  // namespace

PairStiffness cotangent_pair_stiffness(const Eigen::MatrixX3d& positions,
                                       const Eigen::MatrixX3i& faces) {
  PairStiffness stiffness(faces.rows(), 3);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d half_cotangents =
        cotangent_half_weights(positions.row(faces(f, 0)), positions.row(faces(f, 1)),
                               positions.row(faces(f, 2)));
    // The pair (a, a + 1) is the edge opposite corner a + 2.
    for (int a = 0; a < 3; ++a) stiffness(f, a) = -half_cotangents[(a + 2) % 3];
  }
  return stiffness;
}

Eigen::MatrixXd gather_fragment_load(const Eigen::MatrixX3i& faces, int vertex_count,
                                     const PairStiffness& stiffness,
                                     const Eigen::MatrixXd& fragments) {
  const Eigen::Index face_count = faces.rows(), middle = face_count / 2;
  Eigen::MatrixXd load = Eigen::MatrixXd::Zero(vertex_count, fragments.cols());
  Eigen::MatrixXd second_half = Eigen::MatrixXd::Zero(vertex_count, fragments.cols());
  std::future<void> second = start_beside([&] {
    add_fragment_loads(faces, stiffness, fragments, middle, face_count, second_half);
  });
  add_fragment_loads(faces, stiffness, fragments, 0, middle, load);
  second.get();
  return load + second_half;
}

}  // namespace harmonia::detail
