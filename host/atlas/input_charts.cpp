#include "atlas/input_charts.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>
#include <utility>

namespace harmonia::detail {
namespace {

// A corner as the layout sees it: its vertex and its UV (compared exactly: a shared UV is one
// value written once, as an OBJ `vt` or a glTF attribute gives it).
using LayoutPoint = std::tuple<int, double, double>;

LayoutPoint point_of(const Mesh& mesh, const Eigen::Matrix<double, Eigen::Dynamic, 6>& corner_uv, int face, int k) {
  return {mesh.faces(face, k), corner_uv(face, 2 * k), corner_uv(face, 2 * k + 1)};
}

int root_of(std::vector<int>& parent, int face) {
  while (parent[static_cast<std::size_t>(face)] != face) {
    parent[static_cast<std::size_t>(face)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(face)])];
    face = parent[static_cast<std::size_t>(face)];
  }
  return face;
}

double triangle_area(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return 0.5 * (b - a).cross(c - a).norm();
}

}  // namespace

std::vector<FinishedChart> input_charts(const Mesh& mesh, const Eigen::Matrix<double, Eigen::Dynamic, 6>& corner_uv) {
  const int face_count = static_cast<int>(mesh.faces.rows());
  // Faces joined across the edges whose ends are the same layout points in both.
  std::vector<int> parent(static_cast<std::size_t>(face_count));
  std::iota(parent.begin(), parent.end(), 0);
  std::map<std::pair<LayoutPoint, LayoutPoint>, int> first_face_of_edge;
  for (int f = 0; f < face_count; ++f) {
    for (int k = 0; k < 3; ++k) {
      LayoutPoint from = point_of(mesh, corner_uv, f, k), to = point_of(mesh, corner_uv, f, (k + 1) % 3);
      if (to < from) std::swap(from, to);
      const auto [entry, added] = first_face_of_edge.try_emplace({from, to}, f);
      if (!added) parent[static_cast<std::size_t>(root_of(parent, f))] = root_of(parent, entry->second);
    }
  }
  std::map<int, std::vector<int>> faces_of_root;  // by root; faces increasing
  for (int f = 0; f < face_count; ++f) faces_of_root[root_of(parent, f)].push_back(f);

  std::vector<FinishedChart> charts;
  charts.reserve(faces_of_root.size());
  for (auto& [root, faces] : faces_of_root) {
    FinishedChart chart;
    std::map<LayoutPoint, int> chart_vertex;
    std::vector<Eigen::Vector2d> uv;
    chart.mesh.mesh.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
    for (std::size_t i = 0; i < faces.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        const LayoutPoint point = point_of(mesh, corner_uv, faces[i], k);
        const auto [entry, added] = chart_vertex.try_emplace(point, static_cast<int>(uv.size()));
        if (added) {
          uv.emplace_back(std::get<1>(point), std::get<2>(point));
          chart.mesh.surface_vertex.push_back(std::get<0>(point));
        }
        chart.mesh.mesh.faces(static_cast<Eigen::Index>(i), k) = entry->second;
      }
    }
    chart.mesh.surface_face = std::move(faces);
    chart.mesh.mesh.vertices.resize(static_cast<Eigen::Index>(uv.size()), 3);
    for (std::size_t v = 0; v < uv.size(); ++v)
      chart.mesh.mesh.vertices.row(static_cast<Eigen::Index>(v)) = mesh.vertices.row(chart.mesh.surface_vertex[v]);
    // The scale that gives the layout its 3D area (or, without UV area, its 3D perimeter).
    double area_3d = 0.0, area_uv = 0.0, perimeter_3d = 0.0, perimeter_uv = 0.0;
    const Mesh& own = chart.mesh.mesh;
    for (Eigen::Index f = 0; f < own.faces.rows(); ++f) {
      const Eigen::Vector3d a = own.vertices.row(own.faces(f, 0)), b = own.vertices.row(own.faces(f, 1)),
                            c = own.vertices.row(own.faces(f, 2));
      const Eigen::Vector2d p = uv[static_cast<std::size_t>(own.faces(f, 0))], q = uv[static_cast<std::size_t>(own.faces(f, 1))],
                            r = uv[static_cast<std::size_t>(own.faces(f, 2))];
      area_3d += triangle_area(a, b, c);
      area_uv += 0.5 * std::abs((q - p).x() * (r - p).y() - (q - p).y() * (r - p).x());
      perimeter_3d += (b - a).norm() + (c - b).norm() + (a - c).norm();
      perimeter_uv += (q - p).norm() + (r - q).norm() + (p - r).norm();
    }
    double scale = 1.0;
    if (area_uv > 0.0 && area_3d > 0.0) {
      scale = std::sqrt(area_3d / area_uv);
    } else if (perimeter_uv > 0.0 && perimeter_3d > 0.0) {
      scale = perimeter_3d / perimeter_uv;
    }
    chart.layout.uv.resize(static_cast<Eigen::Index>(uv.size()), 2);
    for (std::size_t v = 0; v < uv.size(); ++v) chart.layout.uv.row(static_cast<Eigen::Index>(v)) = scale * uv[v].transpose();
    chart.layout.method = ChartMethod::input_layout;
    charts.push_back(std::move(chart));
  }
  std::sort(charts.begin(), charts.end(), [](const FinishedChart& a, const FinishedChart& b) {
    return a.mesh.surface_face.front() < b.mesh.surface_face.front();
  });
  return charts;
}

}  // namespace harmonia::detail
