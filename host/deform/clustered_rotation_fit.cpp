#include "deform/clustered_rotation_fit.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>

#include "deform/triangle_transforms.h"

namespace harmonia::detail {
namespace {

// Columns solved together at set-up: enough for the solver's blocked back-substitution, few enough
// that the dense load and solution stay small at 400K faces (2 x 24 x 8 bytes a vertex).
constexpr Eigen::Index kColumnsPerSolve = 24;
// Newton's method on the rotations: at most this many steps ...
constexpr int kMostNewtonSteps = 60;
// ... ending when a step turns no cluster by more than this (radians; the energy is then at its
// maximum to rounding, since the step is quadratically small)...
constexpr double kSmallestTurn = 1e-9;
// ... or when the energy gains, or would gain, less than this fraction of itself.
constexpr double kSmallestRelativeGain = 1e-15;

// [e_a]_x, the cross-product matrix of the a-th unit vector: the derivative of exp([w]_x) along w_a.
Eigen::Matrix3d cross_matrix(int a) {
  Eigen::Matrix3d cross = Eigen::Matrix3d::Zero();
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  cross(c, b) = 1.0;
  cross(b, c) = -1.0;
  return cross;
}

double frobenius(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) { return a.cwiseProduct(b).sum(); }

}  // namespace

ClusteredRotationFit::ClusteredRotationFit(const Mesh& mesh, VertexClusters clusters,
                                           const SimilarityFragmentLoad& load)
    : clusters_(std::move(clusters)) {
  // G: the covariance of a scalar field u with cluster c's cells is sum_v u_v G(v, 3c + k). Each
  // corner of a triangle holds the triangle's edges in its cell with its weight for c, and the
  // triangle's weighted edges, summed at a corner, are the corner load c_fk
  // (similarity_fragment_load.h): so G gathers c_fk times the sum of the corners' weights for c.
  const Eigen::Matrix3Xd& corner_loads = load.corner_loads();
  const Eigen::Index columns = 3 * static_cast<Eigen::Index>(clusters_.count);
  const auto& start = clusters_.weight_start;
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(12 * mesh.faces.size()));
  rest_inertia_ = Eigen::MatrixXd::Zero(columns, columns);
  std::vector<std::pair<int, double>> weight_sum;  // the triangle's clusters, with their corners' weights summed
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    weight_sum.clear();
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces(f, k);
      for (int i = start[v]; i < start[v + 1]; ++i) {
        const int c = clusters_.weight_cluster[i];
        auto found = std::find_if(weight_sum.begin(), weight_sum.end(), [c](const auto& e) { return e.first == c; });
        if (found == weight_sum.end())
          weight_sum.emplace_back(c, clusters_.weight_value[i]);
        else
          found->second += clusters_.weight_value[i];
      }
    }
    for (const auto& [c, w] : weight_sum) {
      triangle_mix_.group.push_back(c);
      triangle_mix_.weight.push_back(w / 3.0);
    }
    triangle_mix_.start.push_back(static_cast<int>(triangle_mix_.group.size()));
    for (const auto& [c, w] : weight_sum)
      for (int m = 0; m < 3; ++m)
        for (int j = 0; j < 3; ++j) entries.emplace_back(mesh.faces(f, m), 3 * c + j, w * corner_loads(j, 3 * f + m));
    // The triangle's rest inertia C_f[a][j] = sum_m p_m[a] c_fm[j] (its weighted edges' e e^T).
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
    for (int m = 0; m < 3; ++m)
      inertia += mesh.vertices.row(mesh.faces(f, m)).transpose() * corner_loads.col(3 * f + m).transpose();
    inertia = (0.5 * (inertia + inertia.transpose())).eval();
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces(f, k);
      for (int i = start[v]; i < start[v + 1]; ++i)
        for (int i2 = start[v]; i2 < start[v + 1]; ++i2)
          rest_inertia_.block<3, 3>(3 * clusters_.weight_cluster[i], 3 * clusters_.weight_cluster[i2]) +=
              clusters_.weight_value[i] * clusters_.weight_value[i2] * inertia;
    }
  }
  covariance_map_.resize(mesh.vertex_count(), columns);
  covariance_map_.setFromTriplets(entries.begin(), entries.end());
}

bool ClusteredRotationFit::couple(const Mesh& mesh, const EditRoles& roles,
                                  const Eigen::SparseMatrix<double>& operator_matrix,
                                  const Eigen::MatrixXd& fields, DirichletSystem& system,
                                  SolveReport& report) {
  handle_count_ = roles.handle_count;
  const Eigen::Index vertex_count = mesh.vertex_count();
  const Eigen::Index columns = covariance_map_.cols();
  // Each handle's mean field over each cluster.
  cluster_fields_ = Eigen::MatrixXd::Zero(clusters_.count, handle_count_);
  Eigen::VectorXd members = Eigen::VectorXd::Zero(clusters_.count);
  for (Eigen::Index v = 0; v < vertex_count; ++v) {
    const int c = clusters_.cluster_of[static_cast<std::size_t>(v)];
    cluster_fields_.row(c) += fields.row(v);
    members[c] += 1.0;
  }
  for (int c = 0; c < clusters_.count; ++c)
    if (members[c] > 0.0) cluster_fields_.row(c) /= members[c];

  // The fields that make x0 on the constrained vertices (0 on the free ones): per handle its rest
  // coordinates and 1; the fixed vertices' rest coordinates.
  const Eigen::Index target_columns = 4 * handle_count_ + 3;
  Eigen::MatrixXd boundary = Eigen::MatrixXd::Zero(vertex_count, target_columns);
  for (Eigen::Index k = 0; k < roles.constrained.size(); ++k) {
    const int v = roles.constrained[k];
    const int role = roles.role[static_cast<std::size_t>(v)];
    const Eigen::Vector3d rest = mesh.vertices.row(v);
    if (role >= 0) {
      boundary.block(v, 4 * role, 1, 3) = rest.transpose();
      boundary(v, 4 * role + 3) = 1.0;
    } else {
      boundary.block(v, 4 * handle_count_, 1, 3) = rest.transpose();
    }
  }
  // Their harmonic extensions need no solve of their own: with U = L_II^-1 G_I / 3 (the solutions
  // for P), the extension's free part is -L_II^-1 L_IB x_B, so its covariance is
  // G_B^T x_B - 3 U^T (L x_B), x_B zero at the free vertices.
  const Eigen::MatrixXd boundary_load = operator_matrix * boundary;
  target_covariance_ = covariance_map_.transpose() * boundary;

  // P = G^T U, U solved from the loads G / 3 (a triangle's linear part is the mean of its corners'
  // blends, so cluster c's unit M_c[d][j] loads corner k of f by the corners' summed weight for c,
  // over 3, times c_fk[j]).
  const Eigen::Index constrained = roles.constrained.size();
  coupling_.resize(columns, columns);
  Eigen::MatrixXd solution;
  for (Eigen::Index first = 0; first < columns; first += kColumnsPerSolve) {
    const Eigen::Index count = std::min(kColumnsPerSolve, columns - first);
    const Eigen::MatrixXd cluster_load = Eigen::MatrixXd(covariance_map_.middleCols(first, count)) / 3.0;
    if (!system.solve_columns(Eigen::MatrixXd::Zero(constrained, count), cluster_load, solution, report))
      return false;
    coupling_.middleCols(first, count).noalias() = covariance_map_.transpose() * solution;
    target_covariance_.middleRows(first, count).noalias() -= 3.0 * solution.transpose() * boundary_load;
  }
  // Symmetric up to the solve's rounding: take the symmetric part, whose gradient the Newton steps use.
  coupling_ = (0.5 * (coupling_ + coupling_.transpose())).eval();
  coupling_ -= rest_inertia_;
  return true;
}

void ClusteredRotationFit::covariances(const Eigen::Matrix3Xd& stacked, const Eigen::Matrix3Xd& t0,
                                       Eigen::Matrix3Xd& covariance, double& energy) const {
  covariance.noalias() = stacked * coupling_;
  covariance += t0;
  energy = 0.5 * stacked.cwiseProduct(covariance + t0).sum();
}

int ClusteredRotationFit::fit(const std::vector<SimilarityTransform>& transforms,
                              std::vector<Eigen::Quaterniond>& blended,
                              std::vector<Eigen::Quaterniond>& rotations, Eigen::VectorXd& scales) const {
  const int count = clusters_.count;
  const Eigen::Index columns = 3 * static_cast<Eigen::Index>(count);
  // The start: the thesis' blend at each cluster's mean fields.
  TriangleSimilarities start;
  blend_triangle_transforms(cluster_fields_, transforms, start);
  blended = std::move(start.rotation);
  rotations = blended;
  scales = std::move(start.scale);

  // t0 = sum over handles of [s_i R_i | a_i] times its fields' covariances, plus the fixed part;
  // a handle maps p to s_i R_i p + a_i with a_i = c_i + t_i - s_i R_i c_i.
  Eigen::Matrix3Xd t0 = target_covariance_.rightCols(3).transpose();
  for (int i = 0; i < handle_count_; ++i) {
    const SimilarityTransform& handle = transforms[static_cast<std::size_t>(i)];
    Eigen::Matrix<double, 3, 4> affine;
    affine.leftCols<3>() = handle.scale * handle.rotation.normalized().toRotationMatrix();
    affine.col(3) = handle.center + handle.translation - affine.leftCols<3>() * handle.center;
    t0.noalias() += affine * target_covariance_.middleCols(4 * i, 4).transpose();
  }

  std::vector<Eigen::Matrix3d> rotation(static_cast<std::size_t>(count));
  Eigen::Matrix3Xd stacked(3, columns);
  const auto stack = [&](const std::vector<Eigen::Matrix3d>& turned) {
    for (int c = 0; c < count; ++c) stacked.middleCols(3 * c, 3) = scales[c] * turned[static_cast<std::size_t>(c)];
  };
  for (int c = 0; c < count; ++c)
    rotation[static_cast<std::size_t>(c)] = rotations[static_cast<std::size_t>(c)].normalized().toRotationMatrix();
  stack(rotation);
  Eigen::Matrix3Xd covariance(3, columns);
  double energy = 0.0;
  covariances(stacked, t0, covariance, energy);

  const Eigen::Matrix3d cross[3] = {cross_matrix(0), cross_matrix(1), cross_matrix(2)};
  Eigen::VectorXd gradient(columns), step(columns);
  Eigen::MatrixXd hessian(columns, columns), coupled(columns, columns), damped(columns, columns);
  std::vector<Eigen::Matrix3d> candidate(static_cast<std::size_t>(count));
  Eigen::Matrix3Xd candidate_covariance(3, columns);
  double damping = 0.0;
  int steps = 0;
  bool converged = false;
  while (!converged && steps < kMostNewtonSteps) {
    // The gradient and Hessian of f in the turns d_c (R_c <- exp([d_c]) R_c):
    // df = sum_c s_c <S_c, [d_c] R_c>; the Hessian's coupling part sum_d J_d^T P J_d with
    // J_d(3c + j, 3c + a) = s_c ([e_a] R_c)(d, j), and its curvature part per cluster,
    // s_c <S_c, sym([e_a][e_b]) R_c>.
    hessian.setZero();
    for (int d = 0; d < 3; ++d) {
      for (int c = 0; c < count; ++c) {
        Eigen::Matrix3d jacobian;  // (j, a)
        for (int a = 0; a < 3; ++a)
          jacobian.col(a) = scales[c] * (cross[a] * rotation[static_cast<std::size_t>(c)]).row(d).transpose();
        coupled.middleCols(3 * c, 3).noalias() = coupling_.middleCols(3 * c, 3) * jacobian;
      }
      for (int c = 0; c < count; ++c) {
        Eigen::Matrix3d jacobian;
        for (int a = 0; a < 3; ++a)
          jacobian.col(a) = scales[c] * (cross[a] * rotation[static_cast<std::size_t>(c)]).row(d).transpose();
        hessian.middleRows(3 * c, 3).noalias() += jacobian.transpose() * coupled.middleRows(3 * c, 3);
      }
    }
    for (int c = 0; c < count; ++c) {
      const Eigen::Matrix3d cluster_covariance = covariance.middleCols(3 * c, 3);
      const Eigen::Matrix3d& r = rotation[static_cast<std::size_t>(c)];
      for (int a = 0; a < 3; ++a) {
        gradient[3 * c + a] = scales[c] * frobenius(cluster_covariance, cross[a] * r);
        for (int b = 0; b < 3; ++b)
          hessian(3 * c + a, 3 * c + b) +=
              scales[c] * frobenius(cluster_covariance, 0.5 * (cross[a] * cross[b] + cross[b] * cross[a]) * r);
      }
    }
    hessian = (0.5 * (hessian + hessian.transpose())).eval();
    const double diagonal_size = hessian.diagonal().cwiseAbs().maxCoeff();
    const double smallest_damping = 1e-9 * diagonal_size + 1e-300;
    // Levenberg-Marquardt: (damping I - H) step = gradient, damping raised until the system is
    // positive definite and the step gains energy.
    bool accepted = false;
    for (int attempt = 0; attempt < 64 && !accepted; ++attempt) {
      damped = -hessian;
      damped.diagonal().array() += damping;
      Eigen::LLT<Eigen::MatrixXd> factor(damped);
      if (factor.info() == Eigen::Success) {
        step = factor.solve(gradient);
        // The gain the quadratic model expects (half of g . step for an undamped step): below
        // rounding of the energy, the rotations are at the maximum.
        if (gradient.dot(step) <= kSmallestRelativeGain * std::abs(energy)) {
          converged = true;
          break;
        }
        for (int c = 0; c < count; ++c) {
          const Eigen::Vector3d turn = step.segment<3>(3 * c);
          const double angle = turn.norm();
          candidate[static_cast<std::size_t>(c)] =
              angle > 0.0 ? Eigen::Matrix3d(Eigen::AngleAxisd(angle, turn / angle).toRotationMatrix() *
                                            rotation[static_cast<std::size_t>(c)])
                          : rotation[static_cast<std::size_t>(c)];
        }
        Eigen::Matrix3Xd candidate_stacked(3, columns);
        for (int c = 0; c < count; ++c)
          candidate_stacked.middleCols(3 * c, 3) = scales[c] * candidate[static_cast<std::size_t>(c)];
        double candidate_energy = 0.0;
        covariances(candidate_stacked, t0, candidate_covariance, candidate_energy);
        if (candidate_energy >= energy) {
          const double gain = candidate_energy - energy;
          rotation.swap(candidate);
          stacked = candidate_stacked;
          covariance = candidate_covariance;
          energy = candidate_energy;
          accepted = true;
          damping *= 0.25;
          if (damping < smallest_damping) damping = 0.0;
          ++steps;
          converged = step.cwiseAbs().maxCoeff() < kSmallestTurn ||
                      gain <= kSmallestRelativeGain * std::abs(energy);
          break;
        }
      }
      damping = std::max(4.0 * damping, smallest_damping);
    }
    if (!accepted) break;  // converged, or no step gains: a maximum to rounding
  }
  for (int c = 0; c < count; ++c)
    rotations[static_cast<std::size_t>(c)] = Eigen::Quaterniond(rotation[static_cast<std::size_t>(c)]).normalized();
  return steps;
}

}  // namespace harmonia::detail
