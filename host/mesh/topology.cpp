#include "harmonia/topology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <span>
#include <string>
#include <tuple>

#include "mesh/disk_diagnosis.h"
#include "mesh/edge_table.h"
#include "mesh/face_checks.h"
#include "mesh/halfedge_map.h"

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
//! across edges with exactly two faces (faces with a repeated vertex take no part).
std::vector<int> find_non_manifold_vertices(const Mesh& mesh, const detail::EdgeTable& edges) {
  const int face_count = mesh.face_count();
  DisjointSets corners(face_count * 3);
  for (int edge = 0; edge < edges.size(); ++edge) {
    // Two uses by two faces is exactly "two faces, neither with a repeated vertex": such a face
    // would use the edge twice.
    const std::span<const detail::EdgeUse> uses = edges.uses(edge);
    if (uses.size() != 2 || uses[0].face() == uses[1].face()) continue;
    // Each use joins the corner it starts at and the one it ends at to the other face's corners
    // of the same vertices.
    auto corner_of_first = [](const detail::EdgeUse& use) {
      return use.backward() ? use.next_corner_index() : use.corner_index();
    };
    auto corner_of_second = [](const detail::EdgeUse& use) {
      return use.backward() ? use.corner_index() : use.next_corner_index();
    };
    corners.unite(corner_of_first(uses[0]), corner_of_first(uses[1]));
    corners.unite(corner_of_second(uses[0]), corner_of_second(uses[1]));
  }
  // A vertex is non-manifold when one of its corners lies in another fan than its first corner.
  std::vector<int> first_fan(static_cast<std::size_t>(mesh.vertex_count()), -1);
  std::vector<char> non_manifold(static_cast<std::size_t>(mesh.vertex_count()), 0);
  for (int face = 0; face < face_count; ++face) {
    if (detail::face_has_repeated_vertex(mesh, face)) continue;
    for (int k = 0; k < 3; ++k) {
      const auto vertex = static_cast<std::size_t>(mesh.faces(face, k));
      const int fan = corners.find(face * 3 + k);
      if (first_fan[vertex] < 0) {
        first_fan[vertex] = fan;
      } else if (first_fan[vertex] != fan) {
        non_manifold[vertex] = 1;
      }
    }
  }
  std::vector<int> result;
  for (std::size_t v = 0; v < non_manifold.size(); ++v) {
    if (non_manifold[v]) result.push_back(static_cast<int>(v));
  }
  return result;
}

//! How many faces hold the edge as first->second ([0]) and as second->first ([1]). A face holds a
//! directed half-edge at most once, so counting uses counts faces.
std::array<int, 2> direction_counts(std::span<const detail::EdgeUse> uses) {
  std::array<int, 2> counts{0, 0};
  for (const detail::EdgeUse& use : uses) ++counts[use.backward() ? 1 : 0];
  return counts;
}

//! The first reason a report is not a disk, with the status check_disk gives for it, in the order
//! in which things must be fixed: dirt that cleanup removes (it also fakes non-manifold edges),
//! then structure, then topology. Empty text for a disk.
struct Diagnosis {
  Status status = Status::ok;
  std::string text;
};

// What the mesh is being checked for: the words of the messages.
enum class Purpose { disk, sphere };

Diagnosis diagnose_structure(const TopologyReport& r, Purpose purpose) {
  const char* const nothing = purpose == Purpose::disk ? "nothing to flatten" : "nothing to map";
  if (r.faces == 0) return {Status::invalid_input, std::string("empty mesh (no faces): ") + nothing};
  if (!r.degenerate_faces.empty()) {
    return {
        Status::invalid_input,
        plural(static_cast<int>(r.degenerate_faces.size()), "degenerate face", "degenerate faces") +
            " (repeated vertex or zero area), first " + face_name(r.degenerate_faces.front()) +
            ": run cleanup in repair mode to drop them"};
  }
  if (!r.duplicate_faces.empty()) {
    return {Status::invalid_input, plural(static_cast<int>(r.duplicate_faces.size()),
                                          "duplicate face", "duplicate faces") +
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
            purpose == Purpose::disk
                ? "not orientable (like a Moebius strip): it cannot be flattened as a disk"
                : "not orientable (like a Klein bottle): it cannot be mapped to the sphere"};
  }
  if (!r.consistently_oriented) {
    return {Status::non_manifold,
            "inconsistent orientation at faces " + first_of(r.inconsistent_edges_faces, 'f') +
                ": run cleanup in repair mode to orient the faces consistently"};
  }
  if (r.components > 1) {
    return {purpose == Purpose::disk ? Status::not_a_disk : Status::not_a_sphere,
            plural(r.components, "connected component", "connected components") +
                (purpose == Purpose::disk ? ": split it into parts and flatten each"
                                          : ": split it into parts and map each")};
  }
  if (!r.unreferenced_vertices.empty()) {
    return {Status::invalid_input, plural(static_cast<int>(r.unreferenced_vertices.size()),
                                          "unreferenced vertex", "unreferenced vertices") +
                                       ", first " + vertex_name(r.unreferenced_vertices.front()) +
                                       ": run cleanup in repair mode to drop them"};
  }
  return {};
}

Diagnosis diagnose(const TopologyReport& r) {
  Diagnosis structure = diagnose_structure(r, Purpose::disk);
  if (structure.status != Status::ok) return structure;
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

// The first reason a report is not a closed genus-0 surface (what check_sphere gives for it).
Diagnosis diagnose_sphere(const TopologyReport& r) {
  Diagnosis structure = diagnose_structure(r, Purpose::sphere);
  if (structure.status != Status::ok) return structure;
  if (r.boundary_loops > 0) {
    return {Status::not_a_sphere,
            "open mesh with " + plural(r.boundary_loops, "boundary loop", "boundary loops") +
                " and genus " + std::to_string(r.genus) +
                ": a spherical map needs a closed surface; close the holes first, or flatten a "
                "disk with `harmonia unwrap`"};
  }
  if (r.genus > 0) {
    return {Status::not_a_sphere,
            "closed mesh of genus " + std::to_string(r.genus) +
                ": a spherical map needs genus 0; cut it into a disk with `harmonia cut` and "
                "flatten that with `harmonia unwrap`"};
  }
  return {};
}

}  // namespace

TopologyReport analyze_topology(const Mesh& mesh) {
  TopologyReport report;
  report.vertices = mesh.vertex_count();
  report.faces = mesh.face_count();
  const detail::EdgeTable edges(mesh);
  report.edges = edges.size();

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

  // Edges: boundary (one face) and non-manifold (three or more). Orientation: a half-edge held
  // by two faces means the two disagree.
  std::vector<int> boundary_degree(static_cast<std::size_t>(report.vertices), 0);
  std::vector<char> inconsistent(static_cast<std::size_t>(report.faces), 0);
  for (int edge = 0; edge < edges.size(); ++edge) {
    const int face_count = edges.face_count(edge);
    if (face_count == 1) {
      ++report.boundary_edges;
      ++boundary_degree[static_cast<std::size_t>(edges.first(edge))];
      ++boundary_degree[static_cast<std::size_t>(edges.second(edge))];
    } else if (face_count > 2) {
      report.non_manifold_edges.push_back({edges.first(edge), edges.second(edge)});
      report.non_manifold_edge_faces.push_back(face_count);
    }
    const std::span<const detail::EdgeUse> uses = edges.uses(edge);
    const std::array<int, 2> counts = direction_counts(uses);
    if (counts[0] > 1 || counts[1] > 1) {
      for (const detail::EdgeUse& use : uses) {
        if (counts[use.backward() ? 1 : 0] > 1)
          inconsistent[static_cast<std::size_t>(use.face())] = 1;
      }
    }
  }
  report.non_manifold_vertices = find_non_manifold_vertices(mesh, edges);

  // Boundary loops are only well defined when every boundary vertex has two boundary edges.
  const bool simple_boundary = report.non_manifold_edges.empty() &&
                               std::all_of(boundary_degree.begin(), boundary_degree.end(),
                                           [](int degree) { return degree == 0 || degree == 2; });
  if (simple_boundary && report.boundary_edges > 0) {
    DisjointSets boundary_sets(report.vertices);
    for (int edge = 0; edge < edges.size(); ++edge) {
      if (edges.face_count(edge) == 1) boundary_sets.unite(edges.first(edge), edges.second(edge));
    }
    for (int v = 0; v < report.vertices; ++v) {
      if (boundary_degree[static_cast<std::size_t>(v)] > 0 && boundary_sets.find(v) == v) {
        ++report.boundary_loops;
      }
    }
  }

  for (int face = 0; face < report.faces; ++face) {
    if (inconsistent[static_cast<std::size_t>(face)])
      report.inconsistent_edges_faces.push_back(face);
  }
  report.consistently_oriented = report.inconsistent_edges_faces.empty();
  // Consistent orientation is an orientation, so only an inconsistent mesh needs the search (two
  // faces across a two-face edge then never run it the same way, and no face needs a flip).
  report.orientable = report.consistently_oriented || detail::orient_faces(mesh, edges).orientable;

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

bool TopologyReport::is_sphere() const { return diagnose_sphere(*this).status == Status::ok; }

std::string TopologyReport::sphere_problem() const { return diagnose_sphere(*this).text; }

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
  // Boundary half-edges: held by some face while no face holds the opposite one.
  const detail::EdgeTable edges(mesh);
  std::vector<detail::Halfedge> boundary;
  for (int edge = 0; edge < edges.size(); ++edge) {
    const std::span<const detail::EdgeUse> uses = edges.uses(edge);
    const std::array<int, 2> counts = direction_counts(uses);
    if (counts[0] > 0 && counts[1] > 0) continue;
    for (const detail::EdgeUse& use : uses) {
      const int from = use.backward() ? edges.second(edge) : edges.first(edge);
      const int to = use.backward() ? edges.first(edge) : edges.second(edge);
      boundary.push_back({from, to, use.face(), use.corner()});
    }
  }
  std::sort(boundary.begin(), boundary.end(),
            [](const detail::Halfedge& a, const detail::Halfedge& b) {
              return std::tie(a.from, a.to, a.face) < std::tie(b.from, b.to, b.face);
            });
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
  std::stable_sort(
      loops.begin(), loops.end(),
      [](const std::vector<int>& a, const std::vector<int>& b) { return a.size() > b.size(); });
  return loops;
}

Eigen::MatrixX2i unique_edges(const Mesh& mesh) {
  const detail::EdgeTable edges(mesh);
  Eigen::MatrixX2i result(edges.size(), 2);
  for (int edge = 0; edge < edges.size(); ++edge) {
    result(edge, 0) = edges.first(edge);
    result(edge, 1) = edges.second(edge);
  }
  return result;
}

Status check_disk(const Mesh& mesh, std::string* message) {
  if (const Status status = check_indices_and_coordinates(mesh, message); status != Status::ok) {
    return status;
  }
  return detail::disk_status(analyze_topology(mesh), message);
}

Status check_sphere(const Mesh& mesh, std::string* message) {
  if (const Status status = check_indices_and_coordinates(mesh, message); status != Status::ok) {
    return status;
  }
  const Diagnosis diagnosis = diagnose_sphere(analyze_topology(mesh));
  if (message != nullptr) *message = diagnosis.text;
  return diagnosis.status;
}

Status detail::disk_status(const TopologyReport& report, std::string* message) {
  const Diagnosis diagnosis = diagnose(report);
  if (message != nullptr) *message = diagnosis.text;
  return diagnosis.status;
}

}  // namespace harmonia
