#include "harmonia/topology.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "host/detail/face_checks.h"
#include "host/detail/halfedge_map.h"

namespace harmonia {

namespace {

//! Union-find with path halving; the root of a set is its smallest member (deterministic).
class DisjointSets {
 public:
  explicit DisjointSets(int size) : parent_(static_cast<std::size_t>(size)) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  int find(int x) {
    while (parent_[static_cast<std::size_t>(x)] != x) {
      parent_[static_cast<std::size_t>(x)] =
          parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(x)])];
      x = parent_[static_cast<std::size_t>(x)];
    }
    return x;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (a < b) std::swap(a, b);
    parent_[static_cast<std::size_t>(a)] = b;
  }

 private:
  std::vector<int> parent_;
};

// Appending (rather than `"v" + std::to_string(v)`) avoids a false -Wrestrict warning of GCC 12.
std::string prefixed(char prefix, int index) {
  std::string name(1, prefix);
  name += std::to_string(index);
  return name;
}
std::string vertex_name(int v) { return prefixed('v', v); }
std::string face_name(int f) { return prefixed('f', f); }

std::string plural(int count, const std::string& singular, const std::string& plural_form) {
  return std::to_string(count) + " " + (count == 1 ? singular : plural_form);
}

//! "f3" or "f3 (and 4 more)".
std::string first_of(const std::vector<int>& faces_or_vertices, char prefix) {
  std::string text = prefixed(prefix, faces_or_vertices.front());
  if (faces_or_vertices.size() > 1) {
    text += " (and " + std::to_string(faces_or_vertices.size() - 1) + " more)";
  }
  return text;
}

//! Vertices whose corners fall into more than one fan when corners of the same vertex are joined
//! across edges with exactly two faces.
std::vector<int> find_non_manifold_vertices(const Mesh& mesh,
                                            const std::vector<detail::EdgeFaces>& edges) {
  const int face_count = mesh.face_count();
  DisjointSets corners(face_count * 3);
  auto corner_of = [&mesh](int face, int vertex) {
    for (int k = 0; k < 3; ++k) {
      if (mesh.faces(face, k) == vertex) return face * 3 + k;
    }
    return -1;
  };
  for (const detail::EdgeFaces& edge : edges) {
    if (edge.faces.size() != 2) continue;
    const int f = edge.faces[0];
    const int g = edge.faces[1];
    if (detail::face_has_repeated_vertex(mesh, f) || detail::face_has_repeated_vertex(mesh, g)) {
      continue;
    }
    corners.unite(corner_of(f, edge.first), corner_of(g, edge.first));
    corners.unite(corner_of(f, edge.second), corner_of(g, edge.second));
  }
  // (vertex, fan root) pairs; a vertex with two different roots is non-manifold.
  std::vector<std::pair<int, int>> fans;
  for (int face = 0; face < face_count; ++face) {
    if (detail::face_has_repeated_vertex(mesh, face)) continue;
    for (int k = 0; k < 3; ++k) fans.emplace_back(mesh.faces(face, k), corners.find(face * 3 + k));
  }
  std::sort(fans.begin(), fans.end());
  fans.erase(std::unique(fans.begin(), fans.end()), fans.end());
  std::vector<int> result;
  for (std::size_t k = 1; k < fans.size(); ++k) {
    if (fans[k].first == fans[k - 1].first &&
        (result.empty() || result.back() != fans[k].first)) {
      result.push_back(fans[k].first);
    }
  }
  return result;
}

//! The first reason a report is not a disk, with the status check_disk gives for it, in the order
//! in which things must be fixed: dirt that cleanup removes (it also fakes non-manifold edges), then
//! structure, then topology. Empty text for a disk.
struct Diagnosis {
  Status status = Status::ok;
  std::string text;
};

Diagnosis diagnose(const TopologyReport& r) {
  if (r.faces == 0) return {Status::invalid_input, "empty mesh (no faces): nothing to flatten"};
  if (!r.degenerate_faces.empty()) {
    return {Status::invalid_input,
            plural(static_cast<int>(r.degenerate_faces.size()), "degenerate face",
                   "degenerate faces") +
                " (repeated vertex or zero area), first " + face_name(r.degenerate_faces.front()) +
                ": run cleanup in repair mode to drop them"};
  }
  if (!r.duplicate_faces.empty()) {
    return {Status::invalid_input,
            plural(static_cast<int>(r.duplicate_faces.size()), "duplicate face",
                   "duplicate faces") +
                ", first " + face_name(r.duplicate_faces.front()) +
                ": run cleanup in repair mode to drop them"};
  }
  if (!r.non_manifold_edges.empty()) {
    const EdgeKey& edge = r.non_manifold_edges.front();
    std::string text = "non-manifold edge (" + vertex_name(edge.first) + ", " +
                       vertex_name(edge.second) + ") used by " +
                       std::to_string(r.non_manifold_edge_faces.front()) + " faces";
    if (r.non_manifold_edges.size() > 1) {
      text += " (" + std::to_string(r.non_manifold_edges.size()) + " such edges)";
    }
    return {Status::non_manifold, text + ": repair the mesh first"};
  }
  if (!r.non_manifold_vertices.empty()) {
    std::string text = "non-manifold vertex " + vertex_name(r.non_manifold_vertices.front()) +
                       " (its faces form separate fans that meet only there";
    if (r.non_manifold_vertices.size() > 1) {
      text += "; " + std::to_string(r.non_manifold_vertices.size()) + " such vertices";
    }
    return {Status::non_manifold, text + "): repair the mesh first"};
  }
  if (!r.orientable) {
    return {Status::non_manifold,
            "not orientable (like a Moebius strip): it cannot be flattened as a disk"};
  }
  if (!r.consistently_oriented) {
    return {Status::non_manifold,
            "inconsistent orientation at faces " + first_of(r.inconsistent_edges_faces, 'f') +
                ": run cleanup in repair mode to orient the faces consistently"};
  }
  if (r.components > 1) {
    return {Status::not_a_disk, plural(r.components, "connected component",
                                       "connected components") +
                                    ": split it into parts and flatten each"};
  }
  if (!r.unreferenced_vertices.empty()) {
    return {Status::invalid_input,
            plural(static_cast<int>(r.unreferenced_vertices.size()), "unreferenced vertex",
                   "unreferenced vertices") +
                ", first " + vertex_name(r.unreferenced_vertices.front()) +
                ": run cleanup in repair mode to drop them"};
  }
  if (r.boundary_loops == 0) {
    if (r.genus == 0) {
      return {Status::not_a_disk,
              "closed mesh (no boundary loop): cut it open with `harmonia cut`"};
    }
    return {Status::not_a_disk, "closed mesh of genus " + std::to_string(r.genus) +
                                    " (no boundary loop): cut it open with `harmonia cut`"};
  }
  if (r.genus > 0) {
    return {Status::not_a_disk, "genus " + std::to_string(r.genus) + " with " +
                                    plural(r.boundary_loops, "boundary loop", "boundary loops") +
                                    ": cut it to a disk with `harmonia cut`"};
  }
  if (r.boundary_loops > 1) {
    return {Status::not_a_disk,
            std::to_string(r.boundary_loops) +
                " boundary loops (genus 0): join the holes with `harmonia cut`"};
  }
  return {};
}

}  // namespace

TopologyReport analyze_topology(const Mesh& mesh) {
  TopologyReport report;
  report.vertices = mesh.vertex_count();
  report.faces = mesh.face_count();
  const std::vector<detail::EdgeFaces> edges = detail::edges_with_faces(mesh);
  report.edges = static_cast<int>(edges.size());

  // Referenced vertices and connected components (faces joined through shared vertices).
  std::vector<char> referenced(static_cast<std::size_t>(report.vertices), 0);
  DisjointSets vertex_sets(report.vertices);
  for (int face = 0; face < report.faces; ++face) {
    for (int k = 0; k < 3; ++k) {
      referenced[static_cast<std::size_t>(mesh.faces(face, k))] = 1;
      vertex_sets.unite(mesh.faces(face, 0), mesh.faces(face, k));
    }
  }
  int referenced_count = 0;
  for (int v = 0; v < report.vertices; ++v) {
    if (referenced[static_cast<std::size_t>(v)]) {
      ++referenced_count;
      if (vertex_sets.find(v) == v) ++report.components;
    } else {
      report.unreferenced_vertices.push_back(v);
    }
  }

  for (int face = 0; face < report.faces; ++face) {
    if (detail::face_is_degenerate(mesh, face)) report.degenerate_faces.push_back(face);
  }
  report.duplicate_faces = detail::duplicate_face_list(mesh);

  // Edges: boundary (one face) and non-manifold (three or more).
  std::vector<int> boundary_degree(static_cast<std::size_t>(report.vertices), 0);
  for (const detail::EdgeFaces& edge : edges) {
    if (edge.faces.size() == 1) {
      ++report.boundary_edges;
      ++boundary_degree[static_cast<std::size_t>(edge.first)];
      ++boundary_degree[static_cast<std::size_t>(edge.second)];
    } else if (edge.faces.size() > 2) {
      report.non_manifold_edges.push_back({edge.first, edge.second});
      report.non_manifold_edge_faces.push_back(static_cast<int>(edge.faces.size()));
    }
  }
  report.non_manifold_vertices = find_non_manifold_vertices(mesh, edges);

  // Boundary loops are only well defined when every boundary vertex has two boundary edges.
  const bool simple_boundary =
      report.non_manifold_edges.empty() &&
      std::all_of(boundary_degree.begin(), boundary_degree.end(),
                  [](int degree) { return degree == 0 || degree == 2; });
  if (simple_boundary && report.boundary_edges > 0) {
    DisjointSets boundary_sets(report.vertices);
    for (const detail::EdgeFaces& edge : edges) {
      if (edge.faces.size() == 1) boundary_sets.unite(edge.first, edge.second);
    }
    for (int v = 0; v < report.vertices; ++v) {
      if (boundary_degree[static_cast<std::size_t>(v)] > 0 && boundary_sets.find(v) == v) {
        ++report.boundary_loops;
      }
    }
  }

  // Orientation: a half-edge used by two faces means the two disagree.
  const detail::HalfedgeMap halfedges(mesh);
  const std::vector<detail::Halfedge>& sorted = halfedges.sorted();
  for (std::size_t k = 1; k < sorted.size(); ++k) {
    if (sorted[k].from == sorted[k - 1].from && sorted[k].to == sorted[k - 1].to &&
        sorted[k].from != sorted[k].to) {
      report.inconsistent_edges_faces.push_back(sorted[k - 1].face);
      report.inconsistent_edges_faces.push_back(sorted[k].face);
    }
  }
  std::sort(report.inconsistent_edges_faces.begin(), report.inconsistent_edges_faces.end());
  report.inconsistent_edges_faces.erase(
      std::unique(report.inconsistent_edges_faces.begin(), report.inconsistent_edges_faces.end()),
      report.inconsistent_edges_faces.end());
  report.consistently_oriented = report.inconsistent_edges_faces.empty();
  report.orientable = detail::orient_faces(mesh, edges).orientable;

  report.euler_characteristic = referenced_count - report.edges + report.faces;
  // chi = 2c - 2g - b holds for orientable manifolds only; elsewhere the genus is left at 0.
  const bool manifold = report.non_manifold_edges.empty() && report.non_manifold_vertices.empty();
  if (manifold && report.orientable) {
    report.genus =
        (2 * report.components - report.euler_characteristic - report.boundary_loops) / 2;
  }
  return report;
}

bool TopologyReport::is_disk() const { return diagnose(*this).status == Status::ok; }

std::string TopologyReport::disk_problem() const { return diagnose(*this).text; }

bool TopologyReport::is_closed_manifold() const {
  return faces > 0 && non_manifold_edges.empty() && non_manifold_vertices.empty() &&
         components == 1 && boundary_edges == 0;
}

Status check_indices_and_coordinates(const Mesh& mesh, std::string* message) {
  const int vertex_count = mesh.vertex_count();
  for (int face = 0; face < mesh.face_count(); ++face) {
    for (int k = 0; k < 3; ++k) {
      const int index = mesh.faces(face, k);
      if (index < 0 || index >= vertex_count) {
        if (message != nullptr) {
          *message = "face " + face_name(face) + " uses vertex index " + std::to_string(index) +
                     ", out of range for " + std::to_string(vertex_count) + " vertices";
        }
        return Status::invalid_input;
      }
    }
  }
  for (int v = 0; v < vertex_count; ++v) {
    if (!mesh.vertices.row(v).allFinite()) {
      if (message != nullptr) {
        *message = "vertex " + vertex_name(v) + " has a non-finite coordinate (NaN or infinity)";
      }
      return Status::invalid_input;
    }
  }
  if (message != nullptr) message->clear();
  return Status::ok;
}

std::vector<std::vector<int>> boundary_loops(const Mesh& mesh) {
  const detail::HalfedgeMap halfedges(mesh);
  std::vector<detail::Halfedge> boundary;
  for (const detail::Halfedge& halfedge : halfedges.sorted()) {
    if (halfedge.from != halfedge.to && halfedges.face_of(halfedge.to, halfedge.from) < 0) {
      boundary.push_back(halfedge);
    }
  }
  // `boundary` is sorted by (from, to): the first unused half-edge starts a loop at its smallest
  // vertex, because every vertex of a loop has a boundary half-edge leaving it.
  std::vector<char> used(boundary.size(), 0);
  auto unused_leaving = [&](int vertex) -> int {
    auto it = std::lower_bound(boundary.begin(), boundary.end(), vertex,
                               [](const detail::Halfedge& h, int v) { return h.from < v; });
    for (; it != boundary.end() && it->from == vertex; ++it) {
      const auto k = static_cast<std::size_t>(it - boundary.begin());
      if (!used[k]) return static_cast<int>(k);
    }
    return -1;
  };
  std::vector<std::vector<int>> loops;
  for (std::size_t start = 0; start < boundary.size(); ++start) {
    if (used[start]) continue;
    std::vector<int> loop;
    int k = static_cast<int>(start);
    while (k >= 0) {
      used[static_cast<std::size_t>(k)] = 1;
      loop.push_back(boundary[static_cast<std::size_t>(k)].from);
      const int next = boundary[static_cast<std::size_t>(k)].to;
      if (next == loop.front()) break;
      k = unused_leaving(next);
    }
    loops.push_back(std::move(loop));
  }
  std::stable_sort(loops.begin(), loops.end(),
                   [](const std::vector<int>& a, const std::vector<int>& b) {
                     return a.size() > b.size();
                   });
  return loops;
}

Eigen::MatrixX2i unique_edges(const Mesh& mesh) {
  const std::vector<detail::EdgeFaces> edges = detail::edges_with_faces(mesh);
  Eigen::MatrixX2i result(static_cast<Eigen::Index>(edges.size()), 2);
  for (std::size_t k = 0; k < edges.size(); ++k) {
    result(static_cast<Eigen::Index>(k), 0) = edges[k].first;
    result(static_cast<Eigen::Index>(k), 1) = edges[k].second;
  }
  return result;
}

Status check_disk(const Mesh& mesh, std::string* message) {
  if (const Status status = check_indices_and_coordinates(mesh, message); status != Status::ok) {
    return status;
  }
  const Diagnosis diagnosis = diagnose(analyze_topology(mesh));
  if (message != nullptr) *message = diagnosis.text;
  return diagnosis.status;
}

}  // namespace harmonia
