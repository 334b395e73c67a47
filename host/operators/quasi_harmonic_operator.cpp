// The quasi-harmonic operator div(C grad f) of thesis chapter 5: per-triangle metric tensors of a
// current map (5.1-5.7) and their two discretizations, the tensor-cotangent operator over the
// centroid dual (5.10) and the tensor mean-value operator over circles (section 5.4).

#include "harmonia/quasi_harmonic_operator.h"

#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Dense>

#include "harmonia/types.h"
#include "mesh/adjacency_pattern.h"
#include "operators/element_stiffness.h"
#include "mesh/power_of_two_scale.h"

namespace harmonia {
namespace {

Eigen::Matrix2d tensor_of(const TriangleTensors& tensors, Eigen::Index f) {
  Eigen::Matrix2d tensor;
  tensor << tensors(f, 0), tensors(f, 1), tensors(f, 2), tensors(f, 3);
  return tensor;
}

void store(TriangleTensors& tensors, Eigen::Index f, const Eigen::Matrix2d& tensor) {
  tensors.row(f) << tensor(0, 0), tensor(0, 1), tensor(1, 0), tensor(1, 1);
}

void check_operator_input(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& faces,
                          const TriangleTensors& tensors, const char* who) {
  if (tensors.rows() != faces.rows()) {
    throw Error(Status::invalid_input, std::string(who) + ": " + std::to_string(tensors.rows()) +
                                           " tensors given for " + std::to_string(faces.rows()) +
                                           " faces");
  }
  detail::check_face_indices(faces, uv.rows(), who);
}

// The vector rotated by +90 degrees: for an edge of a counter-clockwise triangle it points inward.
Eigen::Vector2d perpendicular(const Eigen::Vector2d& edge) { return {-edge.y(), edge.x()}; }

// Stiffness weight on the edge (u_j - u_i) .. (u_k - u_i) wedge for neighbour `near`, with `far` the
// other spoke (both relative to the centre), under tensor C: see tensor_mean_value_laplacian.
double tensor_mean_value_wedge(const Eigen::Vector2d& near, const Eigen::Vector2d& far,
                               const Eigen::Matrix2d& tensor) {
  const double near_length = near.norm(), far_length = far.norm();
  const Eigen::Vector2d along = far / far_length;  // e: the spoke where the integration starts
  Eigen::Vector2d across = near - near.dot(along) * along;  // f: toward `near`, perpendicular to e
  const double across_length = across.norm();
  if (across_length == 0.0) return 0.0;  // zero wedge angle: a degenerate triangle contributes 0
  across /= across_length;
  // Angle of the wedge, its sine and cosine, from the spokes themselves.
  const double sine = across_length / near_length;
  const double cosine = near.dot(along) / near_length;
  const double tan_half = sine / (1.0 + cosine);
  const double a = along.dot(tensor * along), b = across.dot(tensor * across);
  const double c = along.dot(tensor * across);
  return ((a + 2.0 * b) * tan_half + 2.0 * c * sine * sine + (a - b) * sine * cosine) /
         (3.0 * near_length);
}

}  // namespace

Eigen::Vector3d detail::tensor_cotangent_pair_stiffness(const Eigen::MatrixX2d& uv,
                                                        const Eigen::Vector3i& corner,
                                                        const Eigen::Matrix2d& raw_tensor) {
  Eigen::Vector2d rotated_edge[3];
  for (int k = 0; k < 3; ++k)
    rotated_edge[k] = perpendicular(uv.row(corner[(k + 2) % 3]) - uv.row(corner[(k + 1) % 3]));
  const double twice_area =
      std::abs(rotated_edge[2].x() * rotated_edge[1].y() - rotated_edge[2].y() * rotated_edge[1].x());
  if (twice_area == 0.0) return Eigen::Vector3d::Zero();
  const Eigen::Matrix2d tensor = 0.5 * (raw_tensor + raw_tensor.transpose());
  Eigen::Vector3d stiffness;
  for (int a = 0; a < 3; ++a)
    stiffness[a] = rotated_edge[a].dot(tensor * rotated_edge[(a + 1) % 3]) / (2.0 * twice_area);
  return stiffness;
}

Eigen::Matrix2d spd_sqrt(const Eigen::Matrix2d& m) {
  // For a 2x2 SPD matrix with root R: R^2 - trace(R) R + det(R) Id = 0 (Cayley-Hamilton), with
  // det(R) = sqrt(det M) and trace(R)^2 = trace M + 2 sqrt(det M). Hence
  // sqrt(M) = (M + sqrt(det M) Id) / sqrt(trace M + 2 sqrt(det M)). Non-SPD input gives NaN.
  const double root_det = std::sqrt(m.determinant());
  const double root_trace = std::sqrt(m.trace() + 2.0 * root_det);
  return (m + root_det * Eigen::Matrix2d::Identity()) / root_trace;
}

namespace {

// The first fundamental form of face f computed on its 3D and uv edges each scaled by a power of
// two into the safe range (power_of_two_scale.h), so that neither a model in units of 1e-100 nor
// one in units of 1e100 underflows or overflows on the way: the Jacobian comes out multiplied by
// 2^exponent (the 3D scale over the uv scale), and the form by 2^(2 exponent). Both scalings are
// exact, and inside the safe range nothing is scaled (the same bits as the plain formula).
struct ScaledForm {
  Eigen::Matrix2d form;  //!< I times 2^(2 exponent).
  int exponent = 0;
  bool zero_uv_area = false;
};

ScaledForm scaled_first_fundamental_form(const Mesh& mesh, const Eigen::MatrixX2d& uv, Eigen::Index f) {
  const int i = mesh.faces(f, 0), j = mesh.faces(f, 1), k = mesh.faces(f, 2);
  // dX = J dU (5.1): J maps the uv edges onto the 3D edges, J = E3 * E2^-1.
  Eigen::Matrix<double, 3, 2> edges3d;
  edges3d.col(0) = (mesh.vertices.row(j) - mesh.vertices.row(i)).transpose();
  edges3d.col(1) = (mesh.vertices.row(k) - mesh.vertices.row(i)).transpose();
  Eigen::Matrix2d edges_uv;
  edges_uv.col(0) = (uv.row(j) - uv.row(i)).transpose();
  edges_uv.col(1) = (uv.row(k) - uv.row(i)).transpose();
  const double scale_3d = detail::safe_range_scale_for(edges3d.cwiseAbs().maxCoeff());
  const double scale_uv = detail::safe_range_scale_for(edges_uv.cwiseAbs().maxCoeff());
  ScaledForm result;
  if (scale_3d != 1.0) edges3d *= scale_3d;
  if (scale_uv != 1.0) edges_uv *= scale_uv;
  result.exponent = std::ilogb(scale_3d) - std::ilogb(scale_uv);
  if (edges_uv.determinant() == 0.0) {
    result.zero_uv_area = true;
    return result;
  }
  const Eigen::Matrix<double, 3, 2> jacobian = edges3d * edges_uv.inverse();
  result.form = jacobian.transpose() * jacobian;  // I = J^T J (5.2)
  return result;
}

// `tensor` times 2^exponent, exactly.
Eigen::Matrix2d times_power_of_two(const Eigen::Matrix2d& tensor, int exponent) {
  if (exponent == 0) return tensor;
  return tensor.unaryExpr([exponent](double value) { return std::ldexp(value, exponent); });
}

void check_form_input(const Mesh& mesh, const Eigen::MatrixX2d& uv, const char* who) {
  if (uv.rows() != mesh.vertices.rows()) {
    throw Error(Status::invalid_input, std::string(who) + ": " + std::to_string(uv.rows()) +
                                           " uv rows for " + std::to_string(mesh.vertices.rows()) +
                                           " vertices");
  }
  detail::check_face_indices(mesh.faces, mesh.vertices.rows(), who);
}

}  // namespace

TriangleTensors first_fundamental_forms(const Mesh& mesh, const Eigen::MatrixX2d& uv) {
  check_form_input(mesh, uv, "first_fundamental_forms");
  TriangleTensors forms(mesh.faces.rows(), 4);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const ScaledForm scaled = scaled_first_fundamental_form(mesh, uv, f);
    if (scaled.zero_uv_area) {
      forms.row(f).setConstant(std::numeric_limits<double>::infinity());
      continue;
    }
    store(forms, f, times_power_of_two(scaled.form, -2 * scaled.exponent));
  }
  return forms;
}

TriangleTensors quasi_harmonic_tensors(const Mesh& mesh, const Eigen::MatrixX2d& uv) {
  check_form_input(mesh, uv, "quasi_harmonic_tensors");
  TriangleTensors tensors(mesh.faces.rows(), 4);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const ScaledForm scaled = scaled_first_fundamental_form(mesh, uv, f);
    if (scaled.zero_uv_area) {  // the non-finite marker of a zero-area uv face
      tensors.row(f).setConstant(std::numeric_limits<double>::infinity());
      continue;
    }
    // K = sqrt(I) is the planar Jacobian with K^T K = I (5.5); C = K^-1 (5.7), computed on the
    // scaled form, whose root is K times 2^exponent.
    store(tensors, f, times_power_of_two(spd_sqrt(scaled.form).inverse(), scaled.exponent));
  }
  return tensors;
}

TriangleTensors scalar_tensors(const Eigen::VectorXd& kappa) {
  TriangleTensors tensors = TriangleTensors::Zero(kappa.size(), 4);
  tensors.col(0) = kappa;
  tensors.col(3) = kappa;
  return tensors;
}

Eigen::SparseMatrix<double> tensor_cotangent_laplacian(const Eigen::MatrixX2d& uv,
                                                       const Eigen::MatrixX3i& faces,
                                                       const TriangleTensors& tensors) {
  check_operator_input(uv, faces, tensors, "tensor_cotangent_laplacian");
  detail::AdjacencyPattern pattern(faces, static_cast<int>(uv.rows()));
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3i corner = faces.row(f);
    const Eigen::Vector3d stiffness = detail::tensor_cotangent_pair_stiffness(uv, corner, tensor_of(tensors, f));
    for (int a = 0; a < 3; ++a) {
      const int b = (a + 1) % 3;
      pattern.add(corner[a], corner[b], stiffness[a]);  // stiffness = -w_ab (PSD convention)
      pattern.add(corner[b], corner[a], stiffness[a]);
    }
  }
  pattern.set_diagonal_from_rows();
  return pattern.take_matrix();
}

Eigen::MatrixXd tensor_fragment_poisson_rhs(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& faces,
                                            const TriangleTensors& tensors,
                                            const Eigen::MatrixXd& fragments) {
  check_operator_input(uv, faces, tensors, "tensor_fragment_poisson_rhs");
  if (fragments.rows() != 3 * faces.rows()) {
    throw Error(Status::invalid_input, "tensor_fragment_poisson_rhs: fragments has " +
                                           std::to_string(fragments.rows()) + " rows, expected 3 * " +
                                           std::to_string(faces.rows()) + " faces");
  }
  // Each triangle's stiffness S under its tensor applied to its own fragment corners and gathered
  // at the shared vertices: row a of S F is sum over b != a of S_ab (F_b - F_a), since the rows of
  // S sum to zero.
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(uv.rows(), fragments.cols());
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3i corner = faces.row(f);
    const Eigen::Vector3d stiffness = detail::tensor_cotangent_pair_stiffness(uv, corner, tensor_of(tensors, f));
    for (int a = 0; a < 3; ++a) {
      const int b = (a + 1) % 3;
      const Eigen::RowVectorXd difference = fragments.row(3 * f + b) - fragments.row(3 * f + a);
      rhs.row(corner[a]) += stiffness[a] * difference;
      rhs.row(corner[b]) -= stiffness[a] * difference;
    }
  }
  return rhs;
}

Eigen::SparseMatrix<double> tensor_mean_value_laplacian(const Eigen::MatrixX2d& uv,
                                                        const Eigen::MatrixX3i& faces,
                                                        const TriangleTensors& tensors) {
  // Section 5.4. Around vertex i, integrate the flux (C grad f) . n over a small circle (5.12). As
  // the thesis does, the gradient in the wedge of triangle T = (i, j, k) is taken along the radial
  // direction n(phi): the radial derivative of the linear interpolant at angle phi from spoke j is
  //   [sin(g - phi) (f_j - f_i) / r_j + sin(phi) (f_k - f_i) / r_k] / sin g   (g: angle at i),
  // and C grad f . n becomes that derivative times n^T C n. Hence the weight of neighbour j from T is
  //   w_ij^T = 1 / (r_j sin g) * integral_0^g sin(phi') (n^T C n) dphi',
  // with phi' measured from the far spoke k towards j. In the frame e (along spoke k), f (across,
  // towards j), with a = e^T C e, b = f^T C f, c = e^T C f, the integral is elementary:
  //   w_ij^T = [(a + 2b) tan(g/2) + 2c sin^2 g + (a - b) sin g cos g] / (3 r_j),
  // which is the per-edge term printed in the thesis (1/(3 r_{j+1}) [...]); for C = kappa Id it is
  // kappa tan(g/2) / r_j, the mean value weight (5.13), (4.25). The integrand is positive for an SPD
  // C and 0 < g < pi, so every weight is positive whatever the triangle shapes (the point of 5.4).
  check_operator_input(uv, faces, tensors, "tensor_mean_value_laplacian");
  detail::AdjacencyPattern pattern(faces, static_cast<int>(uv.rows()));
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Matrix2d raw = tensor_of(tensors, f);
    const Eigen::Matrix2d tensor = 0.5 * (raw + raw.transpose());  // n^T C n sees the symmetric part
    for (int k = 0; k < 3; ++k) {
      const int i = faces(f, k), j = faces(f, (k + 1) % 3), l = faces(f, (k + 2) % 3);
      const Eigen::Vector2d to_j = (uv.row(j) - uv.row(i)).transpose();
      const Eigen::Vector2d to_l = (uv.row(l) - uv.row(i)).transpose();
      if (to_j.x() * to_l.y() - to_j.y() * to_l.x() == 0.0) continue;  // zero-area uv triangle
      pattern.add(i, j, -tensor_mean_value_wedge(to_j, to_l, tensor));
      pattern.add(i, l, -tensor_mean_value_wedge(to_l, to_j, tensor));
    }
  }
  pattern.set_diagonal_from_rows();
  return pattern.take_matrix();
}

}  // namespace harmonia
