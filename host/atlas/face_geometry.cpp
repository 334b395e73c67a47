#include "atlas/face_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>

#include <Eigen/Geometry>

#include "mesh/for_each_index.h"

namespace harmonia::detail {
namespace {

// Faces in blocks of this many per work item of the threads.
constexpr std::size_t kFacesPerBlock = 4096;

// Calls work(f) for every face, on `threads` threads, a block of faces at a time.
template <typename Work>
void for_each_face(std::size_t count, int threads, const Work& work) {
  for_each_index((count + kFacesPerBlock - 1) / kFacesPerBlock, threads, [&](std::size_t block) {
    const std::size_t end = std::min(count, (block + 1) * kFacesPerBlock);
    for (std::size_t f = block * kFacesPerBlock; f < end; ++f) work(f);
  });
}

// Each face's neighbour across each edge: the one other face of area on the edge when exactly two
// faces of area hold it, in opposite directions (an oriented manifold edge of the surface that has
// area; a face of zero area on it, such as a pole's repeated vertex leaves, covers nothing and
// links nothing). The faces of area around each vertex in compressed rows; each face then finds
// its neighbours around its edges' first vertices and writes only its own entries.
void link_faces_across_edges(const Mesh& mesh, int threads, FaceGeometry& geometry) {
  const Eigen::MatrixX3i& faces = mesh.faces;
  const auto count = static_cast<std::size_t>(faces.rows());
  std::vector<int> first(static_cast<std::size_t>(mesh.vertices.rows()) + 1, 0);
  for (std::size_t f = 0; f < count; ++f)
    if (!geometry.degenerate[f])
      for (int k = 0; k < 3; ++k) ++first[static_cast<std::size_t>(faces(static_cast<Eigen::Index>(f), k)) + 1];
  for (std::size_t v = 1; v < first.size(); ++v) first[v] += first[v - 1];
  std::vector<int> faces_at(static_cast<std::size_t>(first.back()));
  {
    std::vector<int> next(first.begin(), first.end() - 1);
    for (std::size_t f = 0; f < count; ++f)
      if (!geometry.degenerate[f])
        for (int k = 0; k < 3; ++k)
          faces_at[static_cast<std::size_t>(next[static_cast<std::size_t>(faces(static_cast<Eigen::Index>(f), k))]++)] =
              static_cast<int>(f);
  }
  for_each_face(count, threads, [&](std::size_t f) {
    if (geometry.degenerate[f]) return;  // joins no chart
    const auto row = static_cast<Eigen::Index>(f);
    for (int k = 0; k < 3; ++k) {
      const int from = faces(row, k), to = faces(row, (k + 1) % 3);
      int holders = 0, opposite = -1;
      for (int slot = first[static_cast<std::size_t>(from)]; slot < first[static_cast<std::size_t>(from) + 1]; ++slot) {
        const int g = faces_at[static_cast<std::size_t>(slot)];
        for (int j = 0; j < 3; ++j) {
          if (faces(g, j) != to) continue;
          ++holders;
          // g runs to -> from where its corner after `to` is `from`.
          if (g != static_cast<int>(f) && faces(g, (j + 1) % 3) == from) opposite = g;
        }
      }
      geometry.across[f][static_cast<std::size_t>(k)] = holders == 2 ? opposite : -1;
    }
  });
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

FaceGeometry face_geometry(const Mesh& mesh, int threads) {
  const Eigen::MatrixX3d grid_vertices = snapped(mesh.vertices);
  const auto count = static_cast<std::size_t>(mesh.faces.rows());
  FaceGeometry geometry;
  geometry.normal.resize(count);
  geometry.centroid.resize(count);
  geometry.area.resize(count);
  geometry.edge_length.resize(count);
  geometry.across.assign(count, {-1, -1, -1});
  geometry.degenerate.assign(count, 0);
  for_each_face(count, threads, [&](std::size_t f) {
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
  });
  link_faces_across_edges(mesh, threads, geometry);
  // The rank: faces sorted by (centroid, area, index), a total order, in two halves on two
  // threads and merged.
  const auto before = [&geometry](int x, int y) {
    const Eigen::Vector3d& p = geometry.centroid[static_cast<std::size_t>(x)];
    const Eigen::Vector3d& q = geometry.centroid[static_cast<std::size_t>(y)];
    return std::make_tuple(p.x(), p.y(), p.z(), geometry.area[static_cast<std::size_t>(x)], x) <
           std::make_tuple(q.x(), q.y(), q.z(), geometry.area[static_cast<std::size_t>(y)], y);
  };
  std::vector<int> order(count);
  std::iota(order.begin(), order.end(), 0);
  const auto middle = order.begin() + static_cast<std::ptrdiff_t>(count / 2);
  for_each_index(2, threads, [&](std::size_t half) {
    if (half == 0) std::sort(order.begin(), middle, before);
    else std::sort(middle, order.end(), before);
  });
  std::inplace_merge(order.begin(), middle, order.end(), before);
  geometry.rank.resize(count);
  for (std::size_t i = 0; i < count; ++i) geometry.rank[static_cast<std::size_t>(order[i])] = static_cast<int>(i);
  return geometry;
}

}  // namespace harmonia::detail
