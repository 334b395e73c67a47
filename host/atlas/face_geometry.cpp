#include "atlas/face_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>

#include <Eigen/Geometry>

namespace harmonia::detail {
namespace {

// Half-edges sorted by their undirected edge: the faces around one edge come out together.
struct HalfEdge {
  int low = 0, high = 0;  // the edge's vertices, low < high
  int face = 0;
  int edge = 0;           // k: from corner k to corner k+1
  bool forward = false;   // runs from low to high
};

void link_faces_across_edges(const Mesh& mesh, FaceGeometry& geometry) {
  std::vector<HalfEdge> half_edges;
  half_edges.reserve(static_cast<std::size_t>(mesh.faces.rows()) * 3);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int from = mesh.faces(f, k), to = mesh.faces(f, (k + 1) % 3);
      half_edges.push_back({std::min(from, to), std::max(from, to), static_cast<int>(f), k, from < to});
    }
  std::sort(half_edges.begin(), half_edges.end(), [](const HalfEdge& a, const HalfEdge& b) {
    return std::tie(a.low, a.high, a.face, a.edge) < std::tie(b.low, b.high, b.face, b.edge);
  });
  for (std::size_t begin = 0, end = 0; begin < half_edges.size(); begin = end) {
    end = begin + 1;
    while (end < half_edges.size() && half_edges[end].low == half_edges[begin].low &&
           half_edges[end].high == half_edges[begin].high)
      ++end;
    if (end - begin != 2) continue;  // a boundary or a non-manifold edge
    const HalfEdge& a = half_edges[begin];
    const HalfEdge& b = half_edges[begin + 1];
    if (a.forward == b.forward || a.face == b.face) continue;  // opposite orientations, or a fold onto itself
    geometry.across[static_cast<std::size_t>(a.face)][static_cast<std::size_t>(a.edge)] = b.face;
    geometry.across[static_cast<std::size_t>(b.face)][static_cast<std::size_t>(b.edge)] = a.face;
  }
}

// Coordinates rounded to multiples of 2^-30.
Eigen::MatrixX3d snapped(const Eigen::MatrixX3d& vertices) {
  constexpr double kGrid = 1073741824.0;  // 2^30
  return (vertices * kGrid).array().round().matrix() / kGrid;
}

// Zero area, or an area below what the rounding of the corners allows.
bool is_degenerate(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
  const Eigen::Vector3d first = b - a, second = c - a;
  const double length = first.cross(second).norm();
  return !(length > 16.0 * kEpsilon * first.norm() * second.norm()) || !std::isfinite(length);
}

}  // namespace

FaceGeometry face_geometry(const Mesh& mesh) {
  const Eigen::MatrixX3d grid_vertices = snapped(mesh.vertices);
  const auto count = static_cast<std::size_t>(mesh.faces.rows());
  FaceGeometry geometry;
  geometry.normal.resize(count);
  geometry.centroid.resize(count);
  geometry.area.resize(count);
  geometry.edge_length.resize(count);
  geometry.across.assign(count, {-1, -1, -1});
  geometry.degenerate.assign(count, 0);
  for (std::size_t f = 0; f < count; ++f) {
    const auto row = static_cast<Eigen::Index>(f);
    geometry.degenerate[f] = is_degenerate(mesh.vertices.row(mesh.faces(row, 0)), mesh.vertices.row(mesh.faces(row, 1)),
                                           mesh.vertices.row(mesh.faces(row, 2)))
                                 ? 1
                                 : 0;
    const Eigen::Vector3d a = grid_vertices.row(mesh.faces(row, 0));
    const Eigen::Vector3d b = grid_vertices.row(mesh.faces(row, 1));
    const Eigen::Vector3d c = grid_vertices.row(mesh.faces(row, 2));
    const Eigen::Vector3d first = b - a, second = c - a;
    const Eigen::Vector3d cross = first.cross(second);
    const double length = cross.norm();
    geometry.centroid[f] = (a + b + c) / 3.0;
    geometry.edge_length[f] = {first.norm(), (c - b).norm(), second.norm()};
    geometry.area[f] = 0.5 * length;
    // A face too small for the grid has no normal there: it joins no chart and gets its own.
    if (length == 0.0) geometry.degenerate[f] = 1;
    geometry.normal[f] = geometry.degenerate[f] ? Eigen::Vector3d::Zero() : Eigen::Vector3d(cross / length);
  }
  link_faces_across_edges(mesh, geometry);
  // A degenerate face joins no chart: its neighbours see a boundary there.
  for (std::size_t f = 0; f < count; ++f)
    for (int& other : geometry.across[f])
      if (other >= 0 && (geometry.degenerate[f] || geometry.degenerate[static_cast<std::size_t>(other)]))
        other = -1;
  std::vector<int> order(count);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&geometry](int x, int y) {
    const Eigen::Vector3d& p = geometry.centroid[static_cast<std::size_t>(x)];
    const Eigen::Vector3d& q = geometry.centroid[static_cast<std::size_t>(y)];
    return std::make_tuple(p.x(), p.y(), p.z(), geometry.area[static_cast<std::size_t>(x)], x) <
           std::make_tuple(q.x(), q.y(), q.z(), geometry.area[static_cast<std::size_t>(y)], y);
  });
  geometry.rank.resize(count);
  for (std::size_t i = 0; i < count; ++i) geometry.rank[static_cast<std::size_t>(order[i])] = static_cast<int>(i);
  return geometry;
}

}  // namespace harmonia::detail
