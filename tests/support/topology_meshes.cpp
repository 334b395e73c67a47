#include "support/topology_meshes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <tuple>
#include <vector>

#include <Eigen/Geometry>

namespace harmonia::testing {

namespace {

// Points by position: a position met again (within 1e-12) is the same vertex.
class PointIndex {
 public:
  int operator()(const Eigen::Vector3d& p) {
    for (std::size_t i = 0; i < points.size(); ++i)
      if ((Eigen::Vector3d(points[i][0], points[i][1], points[i][2]) - p).norm() < 1e-12) return static_cast<int>(i);
    points.push_back({p.x(), p.y(), p.z()});
    return static_cast<int>(points.size() - 1);
  }
  std::vector<std::array<double, 3>> points;
};

}  // namespace

Mesh squares(const std::vector<std::array<Eigen::Vector3d, 4>>& corners) {
  PointIndex index_of;
  std::vector<std::array<int, 3>> faces;
  for (const auto& square : corners) {
    const int a = index_of(square[0]), b = index_of(square[1]), c = index_of(square[2]), d = index_of(square[3]);
    faces.push_back({a, b, c});
    faces.push_back({a, c, d});
  }
  return make_mesh(index_of.points, faces);
}

Mesh tented_squares(const std::vector<std::array<Eigen::Vector3d, 4>>& corners, const std::vector<double>& tents) {
  PointIndex index_of;
  std::vector<std::array<int, 3>> faces;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const std::array<Eigen::Vector3d, 4>& square = corners[i];
    const Eigen::Vector3d normal = (square[1] - square[0]).cross(square[3] - square[0]).normalized();
    const int centre = index_of((square[0] + square[1] + square[2] + square[3]) / 4.0 + tents[i] * normal);
    for (std::size_t k = 0; k < 4; ++k) faces.push_back({index_of(square[k]), index_of(square[(k + 1) % 4]), centre});
  }
  return make_mesh(index_of.points, faces);
}

Mesh make_mesh(const std::vector<std::array<double, 3>>& vertices,
               const std::vector<std::array<int, 3>>& faces) {
  Mesh mesh;
  mesh.vertices.resize(static_cast<Eigen::Index>(vertices.size()), 3);
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    for (int k = 0; k < 3; ++k) mesh.vertices(static_cast<Eigen::Index>(v), k) = vertices[v][k];
  }
  mesh.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) mesh.faces(static_cast<Eigen::Index>(f), k) = faces[f][k];
  }
  return mesh;
}

Mesh tetrahedron() {
  return make_mesh({{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}},
                   {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}});
}

Mesh octahedron() {
  return make_mesh(
      {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
      {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}});
}

Mesh grid_disk(int n, int m) {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<int, 3>> faces;
  for (int j = 0; j <= m; ++j) {
    for (int i = 0; i <= n; ++i) vertices.push_back({double(i), double(j), 0.0});
  }
  auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i) {
      faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return make_mesh(vertices, faces);
}

Mesh annulus(int around, int rings) {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<int, 3>> faces;
  for (int r = 0; r <= rings; ++r) {
    const double radius = 1.0 + static_cast<double>(r) / rings;
    for (int a = 0; a < around; ++a) {
      const double angle = 2.0 * std::numbers::pi * a / around;
      vertices.push_back({radius * std::cos(angle), radius * std::sin(angle), 0.0});
    }
  }
  auto id = [around](int a, int r) { return r * around + (a % around); };
  for (int r = 0; r < rings; ++r) {
    for (int a = 0; a < around; ++a) {
      // radial x tangential = +z: counter-clockwise seen from +z.
      faces.push_back({id(a, r), id(a + 1, r + 1), id(a + 1, r)});
      faces.push_back({id(a, r), id(a, r + 1), id(a + 1, r + 1)});
    }
  }
  return make_mesh(vertices, faces);
}

Mesh torus(int nu, int nv) {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<int, 3>> faces;
  for (int j = 0; j < nv; ++j) {
    const double phi = 2.0 * std::numbers::pi * j / nv;  // around the tube
    for (int i = 0; i < nu; ++i) {
      const double theta = 2.0 * std::numbers::pi * i / nu;  // around the axis
      const double ring = 2.0 + 0.5 * std::cos(phi);
      vertices.push_back({ring * std::cos(theta), ring * std::sin(theta), 0.5 * std::sin(phi)});
    }
  }
  auto id = [nu, nv](int i, int j) { return (j % nv) * nu + (i % nu); };
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      // d/dtheta x d/dphi points outward, so (i, j) -> (i+1, j) -> (i+1, j+1) is outward.
      faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return make_mesh(vertices, faces);
}

Mesh voxel_slab(int nx, int ny, const std::vector<std::array<int, 2>>& holes) {
  const std::set<std::array<int, 2>> hole_set(holes.begin(), holes.end());
  auto filled = [&](int i, int j, int k) {
    return i >= 0 && j >= 0 && k == 0 && i < nx && j < ny && hole_set.count({i, j}) == 0;
  };
  std::map<std::array<int, 3>, int> index_of;
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<int, 3>> faces;
  auto vertex = [&](std::array<int, 3> p) {
    const auto [it, inserted] = index_of.emplace(p, static_cast<int>(vertices.size()));
    if (inserted) vertices.push_back({double(p[0]), double(p[1]), double(p[2])});
    return it->second;
  };
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      if (!filled(i, j, 0)) continue;
      for (int axis = 0; axis < 3; ++axis) {
        for (int side : {-1, 1}) {
          std::array<int, 3> cell{i, j, 0};
          std::array<int, 3> neighbor = cell;
          neighbor[static_cast<std::size_t>(axis)] += side;
          if (filled(neighbor[0], neighbor[1], neighbor[2])) continue;
          // The square on that side, counter-clockwise seen from outside: with b, c the next
          // axes in cyclic order, e_b x e_c = e_axis.
          const int b = (axis + 1) % 3;
          const int c = (axis + 2) % 3;
          std::array<int, 3> base = cell;
          if (side > 0) base[static_cast<std::size_t>(axis)] += 1;
          std::array<std::array<int, 3>, 4> corners{base, base, base, base};
          corners[1][static_cast<std::size_t>(b)] += 1;
          corners[2][static_cast<std::size_t>(b)] += 1;
          corners[2][static_cast<std::size_t>(c)] += 1;
          corners[3][static_cast<std::size_t>(c)] += 1;
          if (side < 0) std::swap(corners[1], corners[3]);
          const int q0 = vertex(corners[0]), q1 = vertex(corners[1]);
          const int q2 = vertex(corners[2]), q3 = vertex(corners[3]);
          faces.push_back({q0, q1, q2});
          faces.push_back({q0, q2, q3});
        }
      }
    }
  }
  return make_mesh(vertices, faces);
}

Mesh moebius_strip(int segments) {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<int, 3>> faces;
  for (int s = 0; s < segments; ++s) {
    const double t = 2.0 * std::numbers::pi * s / segments;
    for (const double w : {-0.3, 0.3}) {
      const double radius = 1.0 + w * std::cos(t / 2.0);
      vertices.push_back({radius * std::cos(t), radius * std::sin(t), w * std::sin(t / 2.0)});
    }
  }
  for (int s = 0; s < segments; ++s) {
    const int a = 2 * s;
    const int b = 2 * s + 1;
    // The last segment closes the band with a half twist: the two sides swap.
    const int c = s + 1 < segments ? 2 * (s + 1) : 1;
    const int d = s + 1 < segments ? 2 * (s + 1) + 1 : 0;
    faces.push_back({a, c, d});
    faces.push_back({a, d, b});
  }
  return make_mesh(vertices, faces);
}

Mesh without_faces(const Mesh& mesh, const std::vector<int>& removed) {
  Mesh result;
  result.vertices = mesh.vertices;
  result.faces.resize(mesh.face_count() - static_cast<int>(removed.size()), 3);
  Eigen::Index row = 0;
  for (int f = 0; f < mesh.face_count(); ++f) {
    if (std::find(removed.begin(), removed.end(), f) != removed.end()) continue;
    result.faces.row(row++) = mesh.faces.row(f);
  }
  return result;
}

// The cube [-1, 1]^3 with each side an n x n grid of quads, each split into two triangles.
Mesh grid_cube(int n) {
  Mesh mesh;
  std::map<std::tuple<int, int, int>, int> index;  // lattice point -> vertex
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3i> faces;
  const auto vertex = [&](const Eigen::Vector3i& lattice) {
    const auto key = std::make_tuple(lattice.x(), lattice.y(), lattice.z());
    const auto found = index.find(key);
    if (found != index.end()) return found->second;
    points.push_back(lattice.cast<double>() * (2.0 / n) - Eigen::Vector3d::Ones());
    return index[key] = static_cast<int>(points.size()) - 1;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      Eigen::Vector3i u = Eigen::Vector3i::Zero(), v = Eigen::Vector3i::Zero(), origin = Eigen::Vector3i::Zero();
      u((axis + 1) % 3) = 1;
      v((axis + 2) % 3) = 1;
      origin(axis) = side * n;
      if (side == 0) std::swap(u, v);  // keep the faces counter-clockwise seen from outside
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const Eigen::Vector3i corner = origin + i * u + j * v;
          const int a = vertex(corner), b = vertex(corner + u), c = vertex(corner + u + v), d = vertex(corner + v);
          faces.emplace_back(a, b, c);
          faces.emplace_back(a, c, d);
        }
    }
  mesh.vertices.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) mesh.vertices.row(static_cast<Eigen::Index>(i)) = points[i];
  mesh.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t i = 0; i < faces.size(); ++i) mesh.faces.row(static_cast<Eigen::Index>(i)) = faces[i];
  return mesh;
}

}  // namespace harmonia::testing
