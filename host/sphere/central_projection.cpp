// The spherical map of a coarse star-shaped mesh by central projection (central_projection.h).
#include "sphere/central_projection.h"

#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "sphere/sphere_orientation.h"

namespace harmonia::detail {
namespace {

// The centroid of the solid a closed, outward-oriented mesh bounds: the signed tetrahedra from the
// origin to each face, weighted by their volumes (divergence theorem). Nothing for no volume.
std::optional<Eigen::Vector3d> solid_centroid(const Mesh& mesh) {
  double volume = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  // Relative to the vertices' centroid, so that a model far from the origin keeps its digits.
  const Eigen::Vector3d origin = mesh.vertices.colwise().mean().transpose();
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0)).transpose() - origin;
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1)).transpose() - origin;
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2)).transpose() - origin;
    const double six_volume = a.dot(b.cross(c));
    volume += six_volume;
    moment += six_volume * (a + b + c) / 4.0;
  }
  if (!(volume > 0.0)) return std::nullopt;
  return origin + moment / volume;
}

// The points of `mesh` projected from `centre`, when every chord triangle faces outward.
std::optional<Eigen::MatrixX3d> projection_from(const Mesh& mesh, const Eigen::Vector3d& centre) {
  Eigen::MatrixX3d points(mesh.vertices.rows(), 3);
  for (Eigen::Index v = 0; v < points.rows(); ++v) {
    const Eigen::Vector3d offset = mesh.vertices.row(v).transpose() - centre;
    const double length = offset.norm();
    if (!(length > 0.0) || !std::isfinite(length)) return std::nullopt;
    points.row(v) = (offset / length).transpose();
  }
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    if (sphere_orientation_sign(points.row(mesh.faces(f, 0)), points.row(mesh.faces(f, 1)),
                                points.row(mesh.faces(f, 2))) <= 0)
      return std::nullopt;
  }
  return points;
}

// The rotation taking `north` to +z and then `south` to the half-plane y = 0, x >= 0 (longitude 0).
Eigen::Matrix3d pole_frame(const Eigen::Vector3d& north, const Eigen::Vector3d& south) {
  const Eigen::Matrix3d to_z = Eigen::Quaterniond::FromTwoVectors(north, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d turned = to_z * south;
  const double longitude = std::atan2(turned.y(), turned.x());
  return Eigen::AngleAxisd(-longitude, Eigen::Vector3d::UnitZ()).toRotationMatrix() * to_z;
}

}  // namespace

std::optional<CentralProjection> central_projection(const Mesh& mesh, const std::array<int, 2>& poles) {
  std::vector<std::pair<Eigen::Vector3d, std::string>> centres;
  if (const std::optional<Eigen::Vector3d> solid = solid_centroid(mesh)) centres.emplace_back(*solid, "the centroid of the solid");
  centres.emplace_back(mesh.vertices.colwise().mean().transpose(), "the centroid of the vertices");
  centres.emplace_back(0.5 * (mesh.vertices.colwise().minCoeff() + mesh.vertices.colwise().maxCoeff()).transpose(),
                       "the centre of the bounding box");
  for (auto& [centre, name] : centres) {
    std::optional<Eigen::MatrixX3d> points = projection_from(mesh, centre);
    if (!points) continue;
    // Turned rigidly: every orientation stays; the turned points are checked again below all the
    // same, as rounding could move one off its sign where a chord triangle is nearly flat.
    const Eigen::Matrix3d frame = pole_frame(points->row(poles[0]).transpose(), points->row(poles[1]).transpose());
    Eigen::MatrixX3d turned = *points * frame.transpose();
    turned.rowwise().normalize();
    turned.row(poles[0]) << 0.0, 0.0, 1.0;
    bool valid = true;
    for (Eigen::Index f = 0; f < mesh.faces.rows() && valid; ++f)
      valid = sphere_orientation_sign(turned.row(mesh.faces(f, 0)), turned.row(mesh.faces(f, 1)),
                                      turned.row(mesh.faces(f, 2))) > 0;
    if (!valid) continue;
    return CentralProjection{std::move(turned), centre, name};
  }
  return std::nullopt;
}

}  // namespace harmonia::detail
