// Faces of zero area drawn inside a neighbouring chart (zero_area_faces.h).
#include "atlas/zero_area_faces.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <tuple>

#include <Eigen/Core>

namespace harmonia::detail {

namespace {

// Each corner of a hosted face is pulled from where its point falls on the host towards the host's
// centroid by kPull: every corner then has a weight of at least kPull / 3 on each of the host's
// corners, strictly inside it with room to spare. The triangle is then widened by kWiden of the
// host towards the host's corners (see sliver_inside): wide enough to keep an area after its UVs
// are rounded to float32 (glTF) in any atlas up to 4096 texels whose faces are a texel or more
// across, thin enough that the chart's UV area, by which the stretch figures scale each chart,
// grows by at most about 2 kWiden of the host's area per hosted face.
constexpr double kPull = 0x1p-6;
constexpr double kWiden = 0x1p-10;

double signed_area(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const Eigen::Vector2d first = b - a, second = c - a;
  return 0.5 * (first.x() * second.y() - first.y() * second.x());
}

// Barycentric coordinates of the point of triangle (a, b, c) closest to p: the projection onto
// its plane when that falls inside, else the closest point of its nearest edge or corner (the
// regions of the triangle's Voronoi diagram, as in Ericson's Real-Time Collision Detection 5.1.5).
Eigen::Vector3d closest_point_weights(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                      const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {1.0, 0.0, 0.0};
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {0.0, 1.0, 0.0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double t = d1 / (d1 - d3);
    return {1.0 - t, t, 0.0};
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {0.0, 0.0, 1.0};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double t = d2 / (d2 - d6);
    return {1.0 - t, 0.0, t};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0.0, 1.0 - t, t};
  }
  const double denominator = 1.0 / (va + vb + vc);
  const double v = vb * denominator, w = vc * denominator;
  return {1.0 - v - w, v, w};
}

// The hosted face's corners in the host's layout: corner k at
//   q_k + kWiden (host_{s(k)} - centroid),   q_k = (1 - kPull) b_k + kPull centroid,
// b_k where its point falls on the host, s a cyclic shift of the host's corners. For a face of
// zero area the q_k are collinear, and the terms that mix them with the widening sum to zero over
// the three shifts (each corner's three widenings add up to nothing), so one shift at least
// leaves a triangle of the host's orientation with an area of at least kWiden^2 of the host's;
// the shift with the largest such area is taken. Where the q_k are not collinear enough for that
// (a face whose corners fall far apart on the host), they are taken together at their mean, and
// the triangle is the host shrunk by kWiden there.
std::array<Eigen::Vector2d, 3> sliver_inside(const std::array<Eigen::Vector2d, 3>& host,
                                             const std::array<Eigen::Vector2d, 3>& fallen) {
  const Eigen::Vector2d centroid = (host[0] + host[1] + host[2]) / 3.0;
  const double orientation = signed_area(host[0], host[1], host[2]) >= 0.0 ? 1.0 : -1.0;
  std::array<Eigen::Vector2d, 3> pulled;
  for (std::size_t k = 0; k < 3; ++k) pulled[k] = (1.0 - kPull) * fallen[k] + kPull * centroid;
  const auto widest = [&](const std::array<Eigen::Vector2d, 3>& base, double& best_area) {
    std::array<Eigen::Vector2d, 3> best;
    best_area = -1.0;
    for (std::size_t shift = 0; shift < 3; ++shift) {
      std::array<Eigen::Vector2d, 3> corners;
      for (std::size_t k = 0; k < 3; ++k) corners[k] = base[k] + kWiden * (host[(k + shift) % 3] - centroid);
      const double area = orientation * signed_area(corners[0], corners[1], corners[2]);
      if (area > best_area) {
        best_area = area;
        best = corners;
      }
    }
    return best;
  };
  double area = 0.0;
  std::array<Eigen::Vector2d, 3> corners = widest(pulled, area);
  if (area > 0.0) return corners;
  const Eigen::Vector2d mean = (pulled[0] + pulled[1] + pulled[2]) / 3.0;
  return widest({mean, mean, mean}, area);
}

// The part of a host that the index-th of its `guests` faces is drawn in: the whole host for one;
// for more, the host cut by a lattice of m steps along each side into m^2 triangles, of which the
// m(m+1)/2 turned as the host are taken, row by row. Those touch at corners only, so triangles
// strictly inside each cross none of the others.
std::array<Eigen::Vector2d, 3> part_of_host(const std::array<Eigen::Vector2d, 3>& host, int guests, int index) {
  int steps = 1;
  while (steps * (steps + 1) / 2 < guests) ++steps;
  int row = 0;
  while (index >= steps - row) index -= steps - row++;
  const Eigen::Vector2d along = (host[1] - host[0]) / steps, up = (host[2] - host[0]) / steps;
  const Eigen::Vector2d corner = host[0] + index * along + row * up;
  return {corner, corner + along, corner + up};
}

}  // namespace

std::vector<int> zero_area_hosts(const Mesh& surface, const FaceGeometry& geometry) {
  const int face_count = geometry.face_count();
  std::vector<int> host(static_cast<std::size_t>(face_count), -1);
  // The faces of area around each vertex.
  std::vector<std::vector<int>> faces_at(static_cast<std::size_t>(surface.vertices.rows()));
  bool any_degenerate = false;
  for (int f = 0; f < face_count; ++f) {
    if (geometry.degenerate[static_cast<std::size_t>(f)]) {
      any_degenerate = true;
      continue;
    }
    for (int k = 0; k < 3; ++k) faces_at[static_cast<std::size_t>(surface.faces(f, k))].push_back(f);
  }
  if (!any_degenerate) return host;
  for (int f = 0; f < face_count; ++f) {
    if (!geometry.degenerate[static_cast<std::size_t>(f)]) continue;
    // Best: most vertices shared, then the largest area, then the lowest rank.
    std::tuple<int, double, int> best{0, 0.0, 0};
    for (int k = 0; k < 3; ++k) {
      for (const int candidate : faces_at[static_cast<std::size_t>(surface.faces(f, k))]) {
        int shared = 0;
        for (int j = 0; j < 3; ++j) {
          const int vertex = surface.faces(f, j);
          if (j > 0 && vertex == surface.faces(f, 0)) continue;  // a repeated vertex counts once
          if (j > 1 && vertex == surface.faces(f, 1)) continue;
          shared += (surface.faces(candidate, 0) == vertex || surface.faces(candidate, 1) == vertex ||
                     surface.faces(candidate, 2) == vertex);
        }
        const std::tuple<int, double, int> score{shared, geometry.area[static_cast<std::size_t>(candidate)],
                                                 -geometry.rank[static_cast<std::size_t>(candidate)]};
        if (host[static_cast<std::size_t>(f)] < 0 || score > best) {
          best = score;
          host[static_cast<std::size_t>(f)] = candidate;
        }
      }
    }
  }
  return host;
}

void draw_inside_hosts(const Mesh& surface, const FaceGeometry& geometry, const std::vector<int>& host_of_face,
                       std::vector<FinishedChart>& charts) {
  // Where each face of area is: its chart and its row there.
  std::vector<std::pair<int, int>> place(host_of_face.size(), {-1, -1});
  for (std::size_t c = 0; c < charts.size(); ++c) {
    const std::vector<int>& faces = charts[c].mesh.surface_face;
    for (std::size_t row = 0; row < faces.size(); ++row)
      place[static_cast<std::size_t>(faces[row])] = {static_cast<int>(c), static_cast<int>(row)};
  }
  std::vector<std::vector<int>> guests(charts.size());
  for (std::size_t f = 0; f < host_of_face.size(); ++f)
    if (const int host = host_of_face[f]; host >= 0 && place[static_cast<std::size_t>(host)].first >= 0)
      guests[static_cast<std::size_t>(place[static_cast<std::size_t>(host)].first)].push_back(static_cast<int>(f));
  // Several faces in one host each get a triangle of their own out of it (see the loop below), in
  // the order of their rank: the same for any face order.
  std::vector<int> guests_of_host(host_of_face.size(), 0), guest_index(host_of_face.size(), 0);
  for (std::vector<int>& faces : guests) {
    std::sort(faces.begin(), faces.end(), [&geometry](int a, int b) {
      return geometry.rank[static_cast<std::size_t>(a)] < geometry.rank[static_cast<std::size_t>(b)];
    });
    for (const int face : faces)
      guest_index[static_cast<std::size_t>(face)] = guests_of_host[static_cast<std::size_t>(host_of_face[static_cast<std::size_t>(face)])]++;
  }
  for (std::size_t c = 0; c < charts.size(); ++c) {
    if (guests[c].empty()) continue;
    FinishedChart& chart = charts[c];
    Mesh& mesh = chart.mesh.mesh;
    const Eigen::Index old_faces = mesh.faces.rows(), old_vertices = mesh.vertices.rows();
    const auto added = static_cast<Eigen::Index>(guests[c].size());
    Eigen::MatrixX3i faces(old_faces + added, 3);
    faces.topRows(old_faces) = mesh.faces;
    mesh.vertices.conservativeResize(old_vertices + 3 * added, 3);
    chart.layout.uv.conservativeResize(old_vertices + 3 * added, 2);
    std::vector<int> surface_face = chart.mesh.surface_face;
    for (Eigen::Index g = 0; g < added; ++g) {
      const int face = guests[c][static_cast<std::size_t>(g)];
      const int host = host_of_face[static_cast<std::size_t>(face)];
      const int host_row = place[static_cast<std::size_t>(host)].second;
      std::array<Eigen::Vector2d, 3> host_uv, fallen;
      std::array<Eigen::Vector3d, 3> host_point;
      for (int k = 0; k < 3; ++k) {
        host_uv[static_cast<std::size_t>(k)] = chart.layout.uv.row(mesh.faces(host_row, k)).transpose();
        host_point[static_cast<std::size_t>(k)] = surface.vertices.row(surface.faces(host, k)).transpose();
      }
      const std::array<Eigen::Vector2d, 3> part =
          part_of_host(host_uv, guests_of_host[static_cast<std::size_t>(host)], guest_index[static_cast<std::size_t>(face)]);
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d weights = closest_point_weights(surface.vertices.row(surface.faces(face, k)).transpose(),
                                                              host_point[0], host_point[1], host_point[2]);
        fallen[static_cast<std::size_t>(k)] = weights[0] * part[0] + weights[1] * part[1] + weights[2] * part[2];
      }
      const std::array<Eigen::Vector2d, 3> corners = sliver_inside(part, fallen);
      for (int k = 0; k < 3; ++k) {
        const Eigen::Index vertex = old_vertices + 3 * g + k;
        mesh.vertices.row(vertex) = surface.vertices.row(surface.faces(face, k));
        chart.layout.uv.row(vertex) = corners[static_cast<std::size_t>(k)].transpose();
        chart.mesh.surface_vertex.push_back(surface.faces(face, k));
        faces(old_faces + g, k) = static_cast<int>(vertex);
      }
      surface_face.push_back(face);
    }
    // Faces in increasing order of their surface face, as every chart keeps them.
    std::vector<Eigen::Index> order(surface_face.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<Eigen::Index>(i);
    std::sort(order.begin(), order.end(), [&surface_face](Eigen::Index a, Eigen::Index b) {
      return surface_face[static_cast<std::size_t>(a)] < surface_face[static_cast<std::size_t>(b)];
    });
    mesh.faces.resize(faces.rows(), 3);
    chart.mesh.surface_face.resize(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
      mesh.faces.row(static_cast<Eigen::Index>(i)) = faces.row(order[i]);
      chart.mesh.surface_face[i] = surface_face[static_cast<std::size_t>(order[i])];
    }
  }
}

}  // namespace harmonia::detail
