// The curvilinear domain of a spherical map (curvilinear_domain.h).

#include "sphere/curvilinear_domain.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <Eigen/Geometry>

#include "harmonia/cut.h"
#include "harmonia/topology.h"
#include "harmonia/types.h"

namespace harmonia::detail {
namespace {

[[noreturn]] void fail(const std::string& what) {
  throw Error(Status::numerical_failure,
              "spherical map: the date-line cut did not give the expected disk (" + what +
                  "); please report this mesh as a bug");
}

// The angle between u and v, accurate for small and large angles.
double angle_between(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

}  // namespace

Eigen::MatrixX2d polar_angles(const Eigen::MatrixX2d& plane) {
  Eigen::MatrixX2d angles(plane.rows(), 2);
  angles.col(0) = plane.col(0);
  for (Eigen::Index v = 0; v < plane.rows(); ++v) angles(v, 1) = polar_angle(plane(v, 1));
  return angles;
}

double mercator_latitude(double phi) { return std::log(1.0 / std::tan(phi / 2.0)); }

double polar_angle(double psi) { return 2.0 * std::atan(std::exp(-psi)); }

CurvilinearDomain curvilinear_domain(const Mesh& mesh, int north, int south, double pole_margin) {
  CutOptions cut_options;
  cut_options.from_vertex = north;
  cut_options.to_vertex = south;
  const CutResult cut = cut_to_disk(mesh, cut_options);
  if (cut.status != Status::ok) fail(cut.message);
  const int input_count = mesh.vertex_count();
  const auto cut_count = static_cast<int>(cut.disk.vertices.rows());

  // The date line: the copies are appended in path order (cut.h); the ends stay single.
  CurvilinearDomain domain;
  domain.date_line.push_back(north);
  for (int v = input_count; v < cut_count; ++v) domain.date_line.push_back(cut.original_vertex[v]);
  domain.date_line.push_back(south);
  const auto path_length = static_cast<int>(domain.date_line.size());
  if (path_length < 4) fail("the date line has fewer than three edges");

  // Drop the poles and their faces; number the rest densely in the cut's order.
  std::vector<int> domain_index(static_cast<std::size_t>(cut_count), -1);
  for (int v = 0; v < cut_count; ++v) {
    if (v == north || v == south) continue;
    domain_index[static_cast<std::size_t>(v)] = static_cast<int>(domain.original_vertex.size());
    domain.original_vertex.push_back(cut.original_vertex[v]);
  }
  std::vector<Eigen::Vector3i> faces;
  for (Eigen::Index f = 0; f < cut.disk.faces.rows(); ++f) {
    const Eigen::Vector3i face = cut.disk.faces.row(f);
    if ((face.array() == north).any() || (face.array() == south).any()) continue;
    faces.emplace_back(domain_index[static_cast<std::size_t>(face[0])],
                       domain_index[static_cast<std::size_t>(face[1])],
                       domain_index[static_cast<std::size_t>(face[2])]);
    domain.original_face.push_back(static_cast<int>(f));
  }
  domain.disk.vertices.resize(static_cast<Eigen::Index>(domain.original_vertex.size()), 3);
  for (std::size_t v = 0; v < domain.original_vertex.size(); ++v)
    domain.disk.vertices.row(static_cast<Eigen::Index>(v)) =
        mesh.vertices.row(domain.original_vertex[v]);
  domain.disk.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    domain.disk.faces.row(static_cast<Eigen::Index>(f)) = faces[f].transpose();
  std::string message;
  if (check_disk(domain.disk, &message) != Status::ok) fail(message);
  const std::vector<int> loop = boundary_loops(domain.disk).front();
  const auto loop_size = static_cast<int>(loop.size());

  // The corners: both copies of the date line's second and second-to-last vertices.
  const int north_corner_original = domain.date_line[1];
  const int south_corner_original = domain.date_line[static_cast<std::size_t>(path_length) - 2];
  std::vector<int> north_corners, south_corners;  // positions in the loop
  for (int k = 0; k < loop_size; ++k) {
    const int original = domain.original_vertex[static_cast<std::size_t>(loop[static_cast<std::size_t>(k)])];
    if (original == north_corner_original) north_corners.push_back(k);
    if (original == south_corner_original) south_corners.push_back(k);
  }
  if (north_corners.size() != 2 || south_corners.size() != 2) fail("corners not found");

  // Rotate the loop so that it starts at the north ring's first corner: the north ring is the arc
  // between the two north corners without a south corner.
  const auto between = [&](int from, int to, int k) {  // k strictly inside the arc from -> to
    const int length = (to - from + loop_size) % loop_size;
    const int offset = (k - from + loop_size) % loop_size;
    return offset > 0 && offset < length;
  };
  int start = north_corners[0], end = north_corners[1];
  if (between(start, end, south_corners[0]) || between(start, end, south_corners[1]))
    std::swap(start, end);
  std::vector<int> ordered(static_cast<std::size_t>(loop_size));
  for (int k = 0; k < loop_size; ++k)
    ordered[static_cast<std::size_t>(k)] = loop[static_cast<std::size_t>((start + k) % loop_size)];
  // ordered: north ring [0, north_end], the theta = 0 side down to the first south corner, the
  // south ring to the second south corner, the theta = 2 pi side back up.
  const int north_end = (end - start + loop_size) % loop_size;
  int south_begin = -1, south_end = -1;
  for (int k = north_end; k < loop_size; ++k) {
    const int original = domain.original_vertex[static_cast<std::size_t>(ordered[static_cast<std::size_t>(k)])];
    if (original != south_corner_original) continue;
    if (south_begin < 0) south_begin = k; else south_end = k;
  }
  if (south_begin < 0 || south_end < 0) fail("south corners out of order");

  // phi along the date line: its length from the north pole, scaled so that the whole line is
  // pi long (a meridian of the unit sphere).
  std::vector<double> from_north(static_cast<std::size_t>(path_length), 0.0);
  for (int k = 1; k < path_length; ++k)
    from_north[static_cast<std::size_t>(k)] =
        from_north[static_cast<std::size_t>(k) - 1] +
        (mesh.vertices.row(domain.date_line[static_cast<std::size_t>(k)]) -
         mesh.vertices.row(domain.date_line[static_cast<std::size_t>(k) - 1]))
            .norm();
  const double pi = std::numbers::pi;
  const double sphere_scale = pi / from_north.back();
  // The pole rings sit at their mean distance from their pole, at that scale (what a sphere of the
  // same pole-to-pole length would give), but at least pole_margin from the pole ...
  const auto ring_radius = [&](int pole, int first, int last) {
    double sum = 0.0;
    for (int k = first; k <= last; ++k)
      sum += (mesh.vertices.row(domain.original_vertex[static_cast<std::size_t>(ordered[static_cast<std::size_t>(k)])]) -
              mesh.vertices.row(pole)).norm();
    return std::clamp(sphere_scale * sum / (last - first + 1), pole_margin, pi / 4.0);
  };
  const double north_radius = ring_radius(north, 0, north_end);
  const double south_radius = ring_radius(south, south_begin, south_end);
  // ... and the date line between them keeps its proportions.
  const double first = from_north[1], last = from_north[static_cast<std::size_t>(path_length) - 2];
  std::vector<int> path_index(static_cast<std::size_t>(input_count), -1);
  for (int k = 0; k < path_length; ++k)
    path_index[static_cast<std::size_t>(domain.date_line[static_cast<std::size_t>(k)])] = k;
  const double psi_top = mercator_latitude(north_radius);
  const double psi_bottom = mercator_latitude(pi - south_radius);
  const auto date_line_psi = [&](int original) {
    const int k = path_index[static_cast<std::size_t>(original)];
    if (k < 1 || k > path_length - 2) fail("a date-line side leaves the date line");
    const double fraction =
        last > first ? (from_north[static_cast<std::size_t>(k)] - first) / (last - first) : 0.0;
    return mercator_latitude(north_radius + fraction * (pi - south_radius - north_radius));
  };
  // theta around a pole ring: the angles at the pole between consecutive ring vertices.
  const auto ring_fractions = [&](int begin, int end, int pole) {
    std::vector<double> cumulative(1, 0.0);
    for (int k = begin; k < end; ++k) {
      const Eigen::Vector3d p = mesh.vertices.row(pole);
      const Eigen::Vector3d a = mesh.vertices.row(domain.original_vertex[static_cast<std::size_t>(ordered[static_cast<std::size_t>(k)])]);
      const Eigen::Vector3d b = mesh.vertices.row(domain.original_vertex[static_cast<std::size_t>(ordered[static_cast<std::size_t>(k) + 1])]);
      cumulative.push_back(cumulative.back() + angle_between(a - p, b - p));
    }
    for (double& value : cumulative) value /= cumulative.back();
    return cumulative;
  };
  const std::vector<double> north_fraction = ring_fractions(0, north_end, north);
  const std::vector<double> south_fraction = ring_fractions(south_begin, south_end, south);

  domain.boundary.resize(loop_size);
  domain.boundary_plane.resize(loop_size, 2);
  for (int k = 0; k < loop_size; ++k) {
    const int v = ordered[static_cast<std::size_t>(k)];
    const int original = domain.original_vertex[static_cast<std::size_t>(v)];
    double theta = 0.0, psi = 0.0;
    if (k <= north_end) {  // north ring, theta from 2 pi down to 0
      theta = 2.0 * pi * (1.0 - north_fraction[static_cast<std::size_t>(k)]);
      psi = psi_top;
    } else if (k < south_begin) {  // theta = 0 side
      theta = 0.0;
      psi = date_line_psi(original);
    } else if (k <= south_end) {  // south ring, theta from 0 up to 2 pi
      theta = 2.0 * pi * south_fraction[static_cast<std::size_t>(k - south_begin)];
      psi = psi_bottom;
    } else {  // theta = 2 pi side
      theta = 2.0 * pi;
      psi = date_line_psi(original);
    }
    domain.boundary[k] = v;
    domain.boundary_plane(k, 0) = theta;
    domain.boundary_plane(k, 1) = psi;
  }
  // The corners exactly on the date line.
  domain.boundary_plane(0, 0) = 2.0 * pi;
  domain.boundary_plane(north_end, 0) = 0.0;
  domain.boundary_plane(south_begin, 0) = 0.0;
  domain.boundary_plane(south_end, 0) = 2.0 * pi;
  for (const int k : {0, north_end}) domain.boundary_plane(k, 1) = psi_top;
  for (const int k : {south_begin, south_end}) domain.boundary_plane(k, 1) = psi_bottom;
  return domain;
}

}  // namespace harmonia::detail
