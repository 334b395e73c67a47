// Output normalization of a planar layout (UvNormalization): orientation, centring, principal
// axis, then scale. Every step is a similarity (or the mirror v -> -v), so angles are untouched.

#include "harmonia/normalize.h"

#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "mesh/power_of_two_scale.h"

namespace harmonia {
namespace {

double signed_area(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const Eigen::Vector2d e1 = b - a, e2 = c - a;
  return 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
}

double surface_area(const Mesh& mesh) {
  double total = 0.0;
  for (int f = 0; f < mesh.face_count(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
    total += 0.5 * (b - a).cross(c - a).norm();
  }
  return total;
}

// Per-face UV centroids and unsigned areas: the weights of every moment below.
struct FaceSamples {
  Eigen::MatrixX2d centroid;
  Eigen::VectorXd area;
  double signed_total = 0.0;
};

FaceSamples face_samples(const Eigen::MatrixX3i& uv_faces, const Eigen::MatrixX2d& uv) {
  FaceSamples samples;
  samples.centroid.resize(uv_faces.rows(), 2);
  samples.area.resize(uv_faces.rows());
  for (Eigen::Index f = 0; f < uv_faces.rows(); ++f) {
    const Eigen::Vector2d a = uv.row(uv_faces(f, 0)), b = uv.row(uv_faces(f, 1)),
                          c = uv.row(uv_faces(f, 2));
    const double area = signed_area(a, b, c);
    samples.signed_total += area;
    samples.area[f] = std::abs(area);
    samples.centroid.row(f) = (a + b + c) / 3.0;
  }
  return samples;
}

}  // namespace

void normalize_uv(const Mesh& mesh3d, const Eigen::MatrixX3i& uv_faces, Eigen::MatrixX2d& uv,
                  UvNormalization mode) {
  if (mode == UvNormalization::none || uv.rows() == 0 || uv_faces.rows() == 0) return;

  // Worked in the safe range: the layout and the surface each scaled by a power of two where
  // needed (exact, mesh/power_of_two_scale.h), so that areas and moments neither overflow nor
  // underflow; the surface's scale is taken out again at the end.
  uv = detail::scaled_into_safe_range(uv);
  const detail::ScaledMesh surface = detail::unit_scaled(mesh3d);

  // Orientation: counter-clockwise overall.
  if (face_samples(uv_faces, uv).signed_total < 0.0) uv.col(1) = -uv.col(1);

  FaceSamples samples = face_samples(uv_faces, uv);
  const double weight = samples.area.sum();
  if (!(weight > 0.0)) return;  // A collapsed layout has no centroid or axis to speak of.

  // Area-weighted centroid to the origin.
  const Eigen::RowVector2d centroid = (samples.area.transpose() * samples.centroid) / weight;
  uv.rowwise() -= centroid;
  samples.centroid.rowwise() -= centroid;

  // Principal axis of the area-weighted second moment becomes +u (a rotation, no mirror).
  const Eigen::Matrix2d moment =
      samples.centroid.transpose() * samples.area.asDiagonal() * samples.centroid;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(moment);
  Eigen::Vector2d axis = eigen.eigenvectors().col(1);  // Eigenvalues ascend: last is the largest.
  // Sign: the area-weighted third moment along the axis is >= 0.
  const Eigen::VectorXd along = samples.centroid * axis;
  if (samples.area.dot(along.cwiseProduct(along).cwiseProduct(along)) < 0.0) axis = -axis;
  Eigen::Matrix2d rotation;  // Rows: new u axis, new v axis (axis turned by +90 degrees).
  rotation << axis.x(), axis.y(), -axis.y(), axis.x();
  uv = (uv * rotation.transpose()).eval();

  // Scale: total UV area equal to the 3D surface area.
  const double uv_area = face_samples(uv_faces, uv).signed_total;
  const double area3d = surface_area(surface.mesh);
  if (uv_area > 0.0 && area3d > 0.0) uv *= std::sqrt(area3d / uv_area) / surface.scale;

  if (mode == UvNormalization::unit_square) {
    const Eigen::RowVector2d low = uv.colwise().minCoeff(), high = uv.colwise().maxCoeff();
    const double extent = (high - low).maxCoeff();
    uv.rowwise() -= low;
    if (extent > 0.0) uv /= extent;
  }
}

}  // namespace harmonia
