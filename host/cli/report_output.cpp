#include "cli/report_output.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace harmonia::cli {

void FieldTable::add(std::string name, std::string value) {
  rows_.emplace_back(std::move(name), std::move(value));
}

void FieldTable::add(std::string name, long long value) {
  rows_.emplace_back(std::move(name), std::to_string(value));
}

void FieldTable::add_number(std::string name, double value) {
  rows_.emplace_back(std::move(name), format_number(value));
}

void FieldTable::add_yes_no(std::string name, bool value) {
  rows_.emplace_back(std::move(name), value ? "yes" : "no");
}

void FieldTable::print(std::ostream& out) const {
  std::size_t width = 0;
  for (const auto& row : rows_) width = std::max(width, row.first.size());
  for (const auto& [name, value] : rows_) {
    out << name << std::string(width - name.size() + 2, ' ') << value << '\n';
  }
}

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

namespace {

nlohmann::json edge_list_json(const std::vector<EdgeKey>& edges) {
  nlohmann::json list = nlohmann::json::array();
  for (const EdgeKey& edge : edges) list.push_back({edge.first, edge.second});
  return list;
}

// "3: 4, 9, 17" or, past the limit, "45: 4, 9, ... (first 20 shown)".
template <typename Item, typename Format>
std::string truncated_list(const std::vector<Item>& items, std::size_t limit, Format format) {
  std::string text = std::to_string(items.size());
  if (items.empty()) return text;
  text += ": ";
  const std::size_t shown = std::min(items.size(), limit);
  for (std::size_t i = 0; i < shown; ++i) text += (i ? ", " : "") + format(items[i]);
  if (shown < items.size()) text += ", ... (first " + std::to_string(shown) + " shown)";
  return text;
}

std::string index_text(int index) { return std::to_string(index); }
std::string edge_text(const EdgeKey& edge) {
  return std::to_string(edge.first) + "-" + std::to_string(edge.second);
}

}  // namespace

nlohmann::json topology_json(const TopologyReport& report) {
  return {
      {"vertices", report.vertices},
      {"faces", report.faces},
      {"edges", report.edges},
      {"components", report.components},
      {"boundary_loops", report.boundary_loops},
      {"boundary_edges", report.boundary_edges},
      {"euler_characteristic", report.euler_characteristic},
      {"genus", report.genus},
      {"orientable", report.orientable},
      {"consistently_oriented", report.consistently_oriented},
      {"non_manifold_edges", edge_list_json(report.non_manifold_edges)},
      {"non_manifold_vertices", report.non_manifold_vertices},
      {"degenerate_faces", report.degenerate_faces},
      {"duplicate_faces", report.duplicate_faces},
      {"unreferenced_vertices", report.unreferenced_vertices},
      {"inconsistent_edges_faces", report.inconsistent_edges_faces},
      {"is_disk", report.is_disk()},
      {"is_closed_manifold", report.is_closed_manifold()},
      {"disk_problem", report.disk_problem()},
      {"is_sphere", report.is_sphere()},
      {"sphere_problem", report.sphere_problem()},
  };
}

void add_topology_rows(FieldTable& table, const TopologyReport& report, std::size_t list_limit) {
  table.add("vertices", report.vertices);
  table.add("faces", report.faces);
  table.add("edges", report.edges);
  table.add("components", report.components);
  table.add("boundary loops", report.boundary_loops);
  table.add("boundary edges", report.boundary_edges);
  table.add("euler characteristic", report.euler_characteristic);
  table.add("genus", report.genus);
  table.add_yes_no("orientable", report.orientable);
  table.add_yes_no("consistently oriented", report.consistently_oriented);
  table.add("non-manifold edges", truncated_list(report.non_manifold_edges, list_limit, edge_text));
  table.add("non-manifold vertices",
            truncated_list(report.non_manifold_vertices, list_limit, index_text));
  table.add("degenerate faces", truncated_list(report.degenerate_faces, list_limit, index_text));
  table.add("duplicate faces", truncated_list(report.duplicate_faces, list_limit, index_text));
  table.add("unreferenced vertices",
            truncated_list(report.unreferenced_vertices, list_limit, index_text));
  table.add("inconsistently oriented faces",
            truncated_list(report.inconsistent_edges_faces, list_limit, index_text));
  table.add_yes_no("closed manifold", report.is_closed_manifold());
  table.add("disk", report.is_disk() ? "yes" : "no: " + report.disk_problem());
  table.add("sphere", report.is_sphere() ? "yes (harmonia sphere maps it)"
                                         : "no: " + report.sphere_problem());
}

nlohmann::json metrics_json(const DistortionMetrics& metrics) {
  return {
      {"faces", metrics.faces},
      {"flipped_triangles", metrics.flipped_triangles},
      {"zero_area_triangles", metrics.zero_area_triangles},
      {"boundary_self_intersections", metrics.boundary_self_intersections},
      {"angle_error_mean_squared", metrics.angle_error_mean_squared},
      {"abf_energy", metrics.abf_energy},
      {"conformal_distortion_mean", metrics.conformal_distortion_mean},
      {"conformal_distortion_max", metrics.conformal_distortion_max},
      {"area_distortion_mean", metrics.area_distortion_mean},
      {"area_distortion_max", metrics.area_distortion_max},
      {"l2_stretch", metrics.l2_stretch},
  };
}

void add_metrics_rows(FieldTable& table, const DistortionMetrics& metrics) {
  table.add("faces", metrics.faces);
  table.add("flipped triangles", metrics.flipped_triangles);
  table.add("zero-area triangles", metrics.zero_area_triangles);
  table.add("boundary self-intersections", metrics.boundary_self_intersections);
  table.add_number("angle error (mean squared, rad^2)", metrics.angle_error_mean_squared);
  table.add_number("ABF energy", metrics.abf_energy);
  table.add_number("conformal distortion mean", metrics.conformal_distortion_mean);
  table.add_number("conformal distortion max", metrics.conformal_distortion_max);
  table.add_number("area distortion mean", metrics.area_distortion_mean);
  table.add_number("area distortion max", metrics.area_distortion_max);
  table.add_number("L2 stretch", metrics.l2_stretch);
}

nlohmann::json timings_json(const std::vector<PhaseTiming>& timings) {
  // nlohmann::json objects keep keys sorted, so the output is deterministic.
  nlohmann::json object = nlohmann::json::object();
  for (const PhaseTiming& timing : timings) {
    const double previous =
        object.contains(timing.phase) ? object[timing.phase].get<double>() : 0.0;
    object[timing.phase] = previous + timing.seconds;
  }
  return object;
}

}  // namespace harmonia::cli
