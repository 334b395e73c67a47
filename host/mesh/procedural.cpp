#include "harmonia/procedural.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace harmonia {
namespace {

// Concentric rings around a centre vertex: ring k (1-based) has 6k vertices at radius k/rings,
// the classic hexagonal disk triangulation. Returns planar (x, y) positions and CCW faces.
struct RingDisk {
  std::vector<Eigen::Vector2d> points;
  std::vector<Eigen::Vector3i> faces;
};

int ring_start(int ring) { return ring == 0 ? 0 : 1 + 3 * ring * (ring - 1); }

RingDisk ring_disk(int rings) {
  if (rings < 1) throw std::invalid_argument("ring_disk: rings must be >= 1");
  RingDisk disk;
  disk.points.emplace_back(0.0, 0.0);
  for (int ring = 1; ring <= rings; ++ring) {
    const int count = 6 * ring;
    const double radius = static_cast<double>(ring) / rings;
    for (int i = 0; i < count; ++i) {
      const double angle = 2.0 * std::numbers::pi * i / count;
      disk.points.emplace_back(radius * std::cos(angle), radius * std::sin(angle));
    }
  }
  // Between ring r-1 (6(r-1) vertices) and ring r (6r vertices): each of the 6 sectors has r outer
  // and r-1 inner vertices (plus the next sector's first), giving 2r-1 triangles per sector.
  for (int ring = 1; ring <= rings; ++ring) {
    const int outer_start = ring_start(ring), outer_count = 6 * ring;
    const int inner_start = ring_start(ring - 1), inner_count = ring == 1 ? 1 : 6 * (ring - 1);
    for (int sector = 0; sector < 6; ++sector) {
      for (int j = 0; j < ring; ++j) {
        const int outer = sector * ring + j;
        const int inner = sector * (ring - 1) + j;
        const int o0 = outer_start + outer % outer_count;
        const int o1 = outer_start + (outer + 1) % outer_count;
        const int i0 = ring == 1 ? 0 : inner_start + inner % inner_count;
        disk.faces.emplace_back(i0, o0, o1);
        if (j < ring - 1) {
          const int i1 = inner_start + (inner + 1) % inner_count;
          disk.faces.emplace_back(i0, o1, i1);
        }
      }
    }
  }
  return disk;
}

Mesh to_mesh(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3i>& faces) {
  Mesh mesh;
  mesh.vertices.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) mesh.vertices.row(static_cast<Eigen::Index>(i)) = points[i];
  mesh.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) mesh.faces.row(static_cast<Eigen::Index>(f)) = faces[f];
  return mesh;
}

}  // namespace

Mesh hemisphere(int rings) {
  const RingDisk disk = ring_disk(rings);
  std::vector<Eigen::Vector3d> points;
  points.reserve(disk.points.size());
  for (const Eigen::Vector2d& p : disk.points) {
    // Ring radius r in [0,1] becomes polar angle r * pi/2: rings are equally spaced in latitude.
    const double r = p.norm();
    const double polar = r * std::numbers::pi / 2.0;
    const double azimuth = std::atan2(p.y(), p.x());
    points.emplace_back(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
                        std::cos(polar));
  }
  return to_mesh(points, disk.faces);
}

Mesh planar_disk(int rings, double jitter) {
  const RingDisk disk = ring_disk(rings);
  std::vector<Eigen::Vector3d> points;
  const int interior_end = ring_start(rings);
  const double spacing = 1.0 / rings;
  for (std::size_t i = 0; i < disk.points.size(); ++i) {
    Eigen::Vector2d p = disk.points[i];
    if (jitter > 0.0 && static_cast<int>(i) < interior_end) {
      // Deterministic pseudo-random offsets (a hash of the index), small enough to keep faces valid.
      const double a = std::sin(12.9898 * static_cast<double>(i) + 1.0) * 43758.5453;
      const double b = std::sin(78.233 * static_cast<double>(i) + 2.0) * 12543.1234;
      p += jitter * spacing * 0.3 * Eigen::Vector2d(a - std::floor(a) - 0.5, b - std::floor(b) - 0.5);
    }
    points.emplace_back(p.x(), p.y(), 0.0);
  }
  return to_mesh(points, disk.faces);
}

Mesh developable_strip(int nu, int nv, double length, double width, double radius) {
  if (nu < 1 || nv < 1) throw std::invalid_argument("developable_strip: nu and nv must be >= 1");
  std::vector<Eigen::Vector3d> points;
  for (int j = 0; j <= nv; ++j) {
    for (int i = 0; i <= nu; ++i) {
      const double x = length * i / nu, y = width * j / nv;
      const double angle = x / radius;  // arc length along the cylinder = x: isometric
      points.emplace_back(radius * std::sin(angle), y, radius * (1.0 - std::cos(angle)));
    }
  }
  std::vector<Eigen::Vector3i> faces;
  const auto index = [nu](int i, int j) { return j * (nu + 1) + i; };
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      // Alternate the diagonal so the triangulation has no preferred direction.
      if ((i + j) % 2 == 0) {
        faces.emplace_back(index(i, j), index(i + 1, j), index(i + 1, j + 1));
        faces.emplace_back(index(i, j), index(i + 1, j + 1), index(i, j + 1));
      } else {
        faces.emplace_back(index(i, j), index(i + 1, j), index(i, j + 1));
        faces.emplace_back(index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
      }
    }
  }
  return to_mesh(points, faces);
}

Mesh demo_surface(int rings) {
  const RingDisk disk = ring_disk(rings);
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector2d& p : disk.points) {
    // A cap with three bumps of different widths and one dimple: strongly non-developable.
    const auto bump = [&p](double cx, double cy, double height, double sigma) {
      const double d2 = (p - Eigen::Vector2d(cx, cy)).squaredNorm();
      return height * std::exp(-d2 / (2.0 * sigma * sigma));
    };
    const double z = 0.6 * (1.0 - p.squaredNorm()) + bump(0.35, 0.2, 0.5, 0.15) +
                     bump(-0.4, 0.3, 0.35, 0.2) - bump(0.0, -0.45, 0.3, 0.18);
    points.emplace_back(p.x(), p.y(), z);
  }
  return to_mesh(points, disk.faces);
}

Mesh unit_sphere(int subdivisions) {
  if (subdivisions < 0 || subdivisions > 8)
    throw std::invalid_argument("unit_sphere: subdivisions must be in [0, 8]");
  // The icosahedron: 12 vertices (0, +-1, +-g) and their cyclic permutations, g the golden ratio.
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> points = {
      {-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
      {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  std::vector<Eigen::Vector3i> faces = {
      {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
      {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (Eigen::Vector3d& p : points) p.normalize();
  // Each subdivision splits every triangle into four at its edge midpoints (projected outward).
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    const auto middle = [&](int a, int b) {
      const std::pair<int, int> key(std::min(a, b), std::max(a, b));
      const auto found = midpoint.find(key);
      if (found != midpoint.end()) return found->second;
      points.push_back((points[static_cast<std::size_t>(a)] + points[static_cast<std::size_t>(b)]).normalized());
      const int index = static_cast<int>(points.size()) - 1;
      midpoint.emplace(key, index);
      return index;
    };
    std::vector<Eigen::Vector3i> finer;
    for (const Eigen::Vector3i& f : faces) {
      const int ab = middle(f[0], f[1]), bc = middle(f[1], f[2]), ca = middle(f[2], f[0]);
      finer.emplace_back(f[0], ab, ca);
      finer.emplace_back(f[1], bc, ab);
      finer.emplace_back(f[2], ca, bc);
      finer.emplace_back(ab, bc, ca);
    }
    faces = std::move(finer);
  }
  return to_mesh(points, faces);
}

Mesh tentacle_sphere(int subdivisions, const std::vector<Eigen::Vector3d>& directions,
                     double length, double cap_angle) {
  if (!(length > 0.0) || !(cap_angle > 0.0 && cap_angle < 1.0))
    throw std::invalid_argument("tentacle_sphere: length must be > 0 and cap_angle in (0, 1)");
  Mesh mesh = unit_sphere(subdivisions);
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    const Eigen::Vector3d p = mesh.vertices.row(v).transpose();
    for (const Eigen::Vector3d& raw : directions) {
      const Eigen::Vector3d axis = raw.normalized();
      const double angle = std::acos(std::clamp(p.dot(axis), -1.0, 1.0));
      if (angle >= cap_angle) continue;
      // The cap pulled out into a tube: t = 0 at the tip, 1 at the cap's rim (where it meets the
      // sphere); the tube keeps most of the rim's radius over its length and closes at the tip.
      const double t = angle / cap_angle;
      const Eigen::Vector3d across = (p - p.dot(axis) * axis).normalized();
      const Eigen::Vector3d moved = axis * (std::cos(cap_angle) + length * (1.0 - t)) +
                                    (angle > 0.0 ? across : Eigen::Vector3d::Zero()) *
                                        std::sin(cap_angle) * std::pow(t, 0.25);
      mesh.vertices.row(v) = moved.transpose();
    }
  }
  return mesh;
}

}  // namespace harmonia
