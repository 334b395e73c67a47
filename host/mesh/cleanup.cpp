#include "harmonia/cleanup.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <tuple>

#include "harmonia/topology.h"
#include "mesh/coincident_vertices.h"
#include "mesh/edge_table.h"
#include "mesh/face_checks.h"
#include "mesh/number_text.h"
#include "mesh/power_of_two_scale.h"

namespace harmonia {

namespace {

// A number in its shortest round-trip form (1e-06, not 0.000001).
std::string shortest_text(double value) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, value).ptr;
  return std::string(text, end);
}

std::string count_of(std::size_t count, const char* singular, const char* plural) {
  std::string text = std::to_string(count);
  text += ' ';
  text += count == 1 ? singular : plural;
  return text;
}

std::string indexed(const char* prefix, int index) {
  std::string text = prefix;
  text += std::to_string(index);
  return text;
}

//! The first problem strict mode refuses, with its status; ok if none.
std::pair<Status, std::string> first_problem(const TopologyReport& report) {
  const std::string repair = ": run cleanup in repair mode";
  if (!report.degenerate_faces.empty()) {
    return {Status::invalid_input,
            count_of(report.degenerate_faces.size(), "degenerate face", "degenerate faces") +
                " (repeated vertex or zero area), first " +
                indexed("f", report.degenerate_faces.front()) + repair + " to drop them"};
  }
  if (!report.duplicate_faces.empty()) {
    return {Status::invalid_input,
            count_of(report.duplicate_faces.size(), "duplicate face", "duplicate faces") +
                ", first " + indexed("f", report.duplicate_faces.front()) + repair +
                " to drop them"};
  }
  if (!report.non_manifold_edges.empty()) {
    const EdgeKey& edge = report.non_manifold_edges.front();
    return {Status::non_manifold,
            "non-manifold edge (" + indexed("v", edge.first) + ", " + indexed("v", edge.second) +
                ") used by " + std::to_string(report.non_manifold_edge_faces.front()) +
                " faces: repair the mesh first (cleanup cannot decide which faces to keep)"};
  }
  if (!report.non_manifold_vertices.empty()) {
    return {Status::non_manifold,
            "non-manifold vertex " + indexed("v", report.non_manifold_vertices.front()) +
                " (separate fans of faces meet there): repair the mesh first"};
  }
  if (!report.unreferenced_vertices.empty()) {
    return {Status::invalid_input, count_of(report.unreferenced_vertices.size(),
                                            "unreferenced vertex", "unreferenced vertices") +
                                       ", first " +
                                       indexed("v", report.unreferenced_vertices.front()) + repair +
                                       " to drop them"};
  }
  if (!report.orientable) {
    return {Status::non_manifold,
            "not orientable (like a Moebius strip): no orientation of the faces is consistent"};
  }
  if (!report.consistently_oriented) {
    return {Status::non_manifold, "inconsistent orientation (first at " +
                                      indexed("f", report.inconsistent_edges_faces.front()) + ", " +
                                      std::to_string(report.inconsistent_edges_faces.size()) +
                                      " faces involved)" + repair +
                                      " to orient the faces consistently"};
  }
  return {Status::ok, ""};
}

void reverse_face(Mesh& mesh, int face) { std::swap(mesh.faces(face, 1), mesh.faces(face, 2)); }

//! Makes the orientation consistent per component, then outward for closed components. Returns
//! false (and leaves the faces) when some component is not orientable.
bool orient_consistently(Mesh& mesh, int* conflict_face) {
  const detail::EdgeTable edges(mesh);
  const detail::FaceOrientation orientation = detail::orient_faces(mesh, edges);
  if (!orientation.orientable) {
    *conflict_face = orientation.conflict_face;
    return false;
  }
  for (int face = 0; face < mesh.face_count(); ++face) {
    if (orientation.flip[static_cast<std::size_t>(face)]) reverse_face(mesh, face);
  }
  // Closed components (every edge with two faces) should enclose a positive volume, i.e. have
  // outward normals: signed volume = sum over faces of a . (b x c) / 6.
  const std::size_t components = orientation.first_face.size();
  const std::vector<int> corner_edge = edges.corner_edges();
  std::vector<char> closed(components, 1);
  std::vector<double> volume(components, 0.0);
  for (int face = 0; face < mesh.face_count(); ++face) {
    const auto id = static_cast<std::size_t>(orientation.component[static_cast<std::size_t>(face)]);
    // (The table was built before the flips, which permute a face's corners but keep its edges.)
    for (int corner = 0; corner < 3; ++corner) {
      const int edge =
          corner_edge[static_cast<std::size_t>(face) * 3 + static_cast<std::size_t>(corner)];
      if (edge < 0 || edges.face_count(edge) != 2) closed[id] = 0;
    }
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(face, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(face, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(face, 2));
    volume[id] += a.dot(b.cross(c)) / 6.0;
  }
  for (int face = 0; face < mesh.face_count(); ++face) {
    const auto id = static_cast<std::size_t>(orientation.component[static_cast<std::size_t>(face)]);
    if (closed[id] && volume[id] < 0.0) reverse_face(mesh, face);
  }
  return true;
}

void set_identity(CleanupResult& result, const Mesh& mesh) {
  result.mesh = mesh;
  result.vertex_map = Eigen::VectorXi::LinSpaced(mesh.vertex_count(), 0, mesh.vertex_count() - 1);
  result.original_vertex = result.vertex_map;
  result.original_face = Eigen::VectorXi::LinSpaced(mesh.face_count(), 0, mesh.face_count() - 1);
}

CleanupResult repair(const Mesh& mesh, const CleanupOptions& options) {
  CleanupResult result;
  const int vertex_count = mesh.vertex_count();
  // Merging compares distances relative to the bounding box's diagonal, on the vertices scaled
  // by a power of two into the safe range: the same merges at every scale of the model, and no overflow
  // (a model at 1e200 has a diagonal that would not fit in a double).
  const Eigen::MatrixX3d safe_vertices = detail::scaled_into_safe_range(mesh.vertices);
  const double diagonal =
      vertex_count > 0
          ? (safe_vertices.colwise().maxCoeff() - safe_vertices.colwise().minCoeff()).norm()
          : 0.0;
  const double tolerance = options.merge_tolerance * diagonal;
  const std::vector<int> representative = detail::coincident_vertex_representatives(safe_vertices, tolerance);

  // Faces on representatives; drop degenerate ones, then repeats of a kept vertex set.
  Mesh merged{mesh.vertices, mesh.faces};
  for (int face = 0; face < mesh.face_count(); ++face) {
    for (int k = 0; k < 3; ++k) {
      merged.faces(face, k) = representative[static_cast<std::size_t>(mesh.faces(face, k))];
    }
  }
  std::vector<int> kept_faces;
  std::vector<int> degenerate;
  std::vector<std::pair<std::array<int, 3>, int>> keyed;
  for (int face = 0; face < mesh.face_count(); ++face) {
    if (detail::face_is_degenerate(merged, face)) {
      degenerate.push_back(face);
      continue;
    }
    std::array<int, 3> key{merged.faces(face, 0), merged.faces(face, 1), merged.faces(face, 2)};
    std::sort(key.begin(), key.end());
    keyed.emplace_back(key, face);
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<int> duplicates;
  for (std::size_t k = 0; k < keyed.size(); ++k) {
    if (k > 0 && keyed[k].first == keyed[k - 1].first) {
      duplicates.push_back(keyed[k].second);
    } else {
      kept_faces.push_back(keyed[k].second);
    }
  }
  std::sort(kept_faces.begin(), kept_faces.end());
  std::sort(duplicates.begin(), duplicates.end());

  // Keep referenced representatives, in input order.
  std::vector<char> referenced(static_cast<std::size_t>(vertex_count), 0);
  for (const int face : kept_faces) {
    for (int k = 0; k < 3; ++k) referenced[static_cast<std::size_t>(merged.faces(face, k))] = 1;
  }
  std::vector<int> new_index(static_cast<std::size_t>(vertex_count), -1);
  std::vector<int> kept_vertices;
  std::vector<int> unreferenced;
  for (int v = 0; v < vertex_count; ++v) {
    if (representative[static_cast<std::size_t>(v)] != v) {
      ++result.merged_vertices;
    } else if (referenced[static_cast<std::size_t>(v)]) {
      new_index[static_cast<std::size_t>(v)] = static_cast<int>(kept_vertices.size());
      kept_vertices.push_back(v);
    } else {
      unreferenced.push_back(v);
    }
  }

  result.vertex_map.resize(vertex_count);
  for (int v = 0; v < vertex_count; ++v) {
    result.vertex_map(v) =
        new_index[static_cast<std::size_t>(representative[static_cast<std::size_t>(v)])];
  }
  const auto kept_vertex_count = static_cast<Eigen::Index>(kept_vertices.size());
  const auto kept_face_count = static_cast<Eigen::Index>(kept_faces.size());
  result.original_vertex.resize(kept_vertex_count);
  result.mesh.vertices.resize(kept_vertex_count, 3);
  for (Eigen::Index v = 0; v < kept_vertex_count; ++v) {
    result.original_vertex(v) = kept_vertices[static_cast<std::size_t>(v)];
    result.mesh.vertices.row(v) = mesh.vertices.row(kept_vertices[static_cast<std::size_t>(v)]);
  }
  result.original_face.resize(kept_face_count);
  result.mesh.faces.resize(kept_face_count, 3);
  for (Eigen::Index f = 0; f < kept_face_count; ++f) {
    const int face = kept_faces[static_cast<std::size_t>(f)];
    result.original_face(f) = face;
    for (int k = 0; k < 3; ++k) {
      result.mesh.faces(f, k) = new_index[static_cast<std::size_t>(merged.faces(face, k))];
    }
  }

  int conflict_face = -1;
  const Mesh before_orientation = result.mesh;
  const bool orientable = orient_consistently(result.mesh, &conflict_face);
  for (Eigen::Index f = 0; f < kept_face_count; ++f) {
    // A face is flipped if its corners no longer follow the same cyclic order.
    const int a = before_orientation.faces(f, 0);
    const int b = before_orientation.faces(f, 1);
    if (!detail::face_has_halfedge(result.mesh, static_cast<int>(f), a, b)) {
      ++result.flipped_faces;
    }
  }

  result.removed_degenerate_faces = static_cast<int>(degenerate.size());
  result.removed_duplicate_faces = static_cast<int>(duplicates.size());
  result.removed_unreferenced_vertices = static_cast<int>(unreferenced.size());
  if (result.merged_vertices > 0) {
    result.changes.push_back("merged " +
                             count_of(static_cast<std::size_t>(result.merged_vertices),
                                      "duplicate vertex", "duplicate vertices") +
                             (tolerance > 0.0
                                  ? " (closer than " + shortest_text(options.merge_tolerance) +
                                        " times the bounding box's diagonal to another)"
                                  : " (same position as an earlier vertex)"));
  }
  if (!degenerate.empty()) {
    result.changes.push_back("removed " +
                             count_of(degenerate.size(), "degenerate face", "degenerate faces") +
                             " (first: input " + indexed("f", degenerate.front()) + ")");
  }
  if (!duplicates.empty()) {
    result.changes.push_back("removed " +
                             count_of(duplicates.size(), "duplicate face", "duplicate faces") +
                             " (first: input " + indexed("f", duplicates.front()) + ")");
  }
  if (!unreferenced.empty()) {
    result.changes.push_back(
        "removed " + count_of(unreferenced.size(), "unreferenced vertex", "unreferenced vertices") +
        " (first: input " + indexed("v", unreferenced.front()) + ")");
  }
  if (result.flipped_faces > 0) {
    result.changes.push_back(
        "flipped " + count_of(static_cast<std::size_t>(result.flipped_faces), "face", "faces") +
        " to orient each component consistently (closed components outward)");
  }

  // What repair cannot fix: a non-orientable surface, non-manifold edges or vertices.
  if (options.keep_non_manifold) {
    const TopologyReport report = analyze_topology(result.mesh);
    if (!report.non_manifold_edges.empty() || !report.non_manifold_vertices.empty())
      result.changes.push_back(
          "kept " + count_of(report.non_manifold_edges.size(), "non-manifold edge", "non-manifold edges") +
          " and " + count_of(report.non_manifold_vertices.size(), "non-manifold vertex", "non-manifold vertices") +
          " (charts are cut there)");
    if (!orientable)
      result.changes.push_back("kept a surface that is not orientable (orientation contradicts itself at " +
                               indexed("f", conflict_face) + " of the repaired mesh; charts are cut there)");
    return result;
  }
  if (!orientable) {
    result.status = Status::non_manifold;
    result.message = "not orientable (like a Moebius strip; orientation contradicts itself at " +
                     indexed("f", conflict_face) + " of the repaired mesh): it cannot be repaired";
    return result;
  }
  const TopologyReport report = analyze_topology(result.mesh);
  if (!report.non_manifold_edges.empty() || !report.non_manifold_vertices.empty()) {
    const auto [status, message] = first_problem(report);
    result.status = status;
    result.message = message + " (after repair, indices of the repaired mesh)";
  }
  return result;
}

}  // namespace

bool CleanupResult::changed() const {
  return merged_vertices > 0 || removed_unreferenced_vertices > 0 || removed_degenerate_faces > 0 ||
         removed_duplicate_faces > 0 || flipped_faces > 0;
}

CleanupResult cleanup(const Mesh& mesh, const CleanupOptions& options) {
  std::string message;
  if (const Status status = check_indices_and_coordinates(mesh, &message); status != Status::ok) {
    CleanupResult result;
    set_identity(result, mesh);
    result.status = status;
    result.message = message;
    return result;
  }
  if (!(options.merge_tolerance >= 0.0) || !std::isfinite(options.merge_tolerance)) {
    CleanupResult result;
    set_identity(result, mesh);
    result.status = Status::invalid_input;
    result.message = "merge_tolerance must be a finite number >= 0, got " +
                     detail::number_text(options.merge_tolerance);
    return result;
  }
  if (options.mode == CleanupMode::repair) return repair(mesh, options);

  // Strict: report the first problem, change nothing. Coincident vertices are not a problem in
  // themselves: cut meshes (disk/*-cut.obj) have them along their seams on purpose.
  CleanupResult result;
  set_identity(result, mesh);
  const auto [status, problem] = first_problem(analyze_topology(mesh));
  result.status = status;
  result.message = problem;
  return result;
}

}  // namespace harmonia
