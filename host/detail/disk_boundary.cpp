#include "detail/disk_boundary.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <utility>

namespace harmonia::detail {
namespace {

DiskInput failure(Status status, std::string message) {
  DiskInput result;
  result.status = status;
  result.message = std::move(message);
  return result;
}

std::string edge_name(int a, int b) {
  return "edge (" + std::to_string(a) + ", " + std::to_string(b) + ")";
}

const char* const cut_hint = "cut it into a disk first with `harmonia cut`";

// Union-find over vertices, for connectivity of the face graph.
int find_root(std::vector<int>& parent, int v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];
    v = parent[v];
  }
  return v;
}

}  // namespace

DiskInput examine_disk(const Mesh& mesh) {
  const int vertex_count = mesh.vertex_count(), face_count = mesh.face_count();
  if (face_count == 0) return failure(Status::invalid_input, "the mesh has no faces");

  for (int f = 0; f < face_count; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces(f, k);
      if (v < 0 || v >= vertex_count)
        return failure(Status::invalid_input, "face " + std::to_string(f) + " has vertex index " +
                                                  std::to_string(v) + " out of range [0, " +
                                                  std::to_string(vertex_count) + ")");
    }
  }
  for (int v = 0; v < vertex_count; ++v) {
    if (!mesh.vertices.row(v).allFinite())
      return failure(Status::invalid_input,
                     "vertex " + std::to_string(v) + " has a non-finite coordinate");
  }
  std::vector<int> uses(vertex_count, 0);
  for (int f = 0; f < face_count; ++f) {
    const int a = mesh.faces(f, 0), b = mesh.faces(f, 1), c = mesh.faces(f, 2);
    if (a == b || b == c || c == a)
      return failure(Status::invalid_input,
                     "face " + std::to_string(f) + " repeats a vertex (" + std::to_string(a) +
                         ", " + std::to_string(b) + ", " + std::to_string(c) +
                         "); remove degenerate faces with harmonia::cleanup (repair mode)");
    ++uses[a], ++uses[b], ++uses[c];
  }
  for (int v = 0; v < vertex_count; ++v) {
    if (uses[v] == 0)
      return failure(Status::invalid_input,
                     "vertex " + std::to_string(v) +
                         " is used by no face; remove unreferenced vertices with harmonia::cleanup "
                         "(repair mode)");
  }

  // Directed half-edges: each must appear once; its twin appears at most once.
  std::map<std::pair<int, int>, int> half_edges;  // (from, to) -> face
  for (int f = 0; f < face_count; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int from = mesh.faces(f, k), to = mesh.faces(f, (k + 1) % 3);
      const auto [where, inserted] = half_edges.emplace(std::make_pair(from, to), f);
      if (!inserted)
        return failure(Status::non_manifold,
                       edge_name(from, to) + " is used twice in the same direction (faces " +
                           std::to_string(where->second) + " and " + std::to_string(f) +
                           "): the mesh is non-manifold or inconsistently oriented");
    }
  }
  // Boundary half-edges (no twin); at most one leaves each vertex, or the vertex is a bowtie.
  std::map<int, int> boundary_next;
  int edge_count = 0;
  for (const auto& [edge, face] : half_edges) {
    const auto [from, to] = edge;
    if (!half_edges.contains({to, from})) {
      const auto [where, inserted] = boundary_next.emplace(from, to);
      if (!inserted)
        return failure(Status::non_manifold,
                       "vertex " + std::to_string(from) +
                           " is non-manifold (two boundary fans meet there); split it with "
                           "harmonia::cleanup or `harmonia cut`");
      ++edge_count;
    } else if (from < to) {
      ++edge_count;
    }
  }

  std::vector<int> parent(vertex_count);
  std::iota(parent.begin(), parent.end(), 0);
  for (int f = 0; f < face_count; ++f) {
    for (int k = 1; k < 3; ++k) {
      const int a = find_root(parent, mesh.faces(f, 0)), b = find_root(parent, mesh.faces(f, k));
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  int components = 0;
  for (int v = 0; v < vertex_count; ++v) components += find_root(parent, v) == v ? 1 : 0;
  if (components > 1)
    return failure(Status::not_a_disk,
                   "the mesh has " + std::to_string(components) +
                       " connected components; a disk has one (split it, then map each part)");

  if (boundary_next.empty())
    return failure(Status::not_a_disk, std::string("closed mesh (no boundary): ") + cut_hint);

  // Walk the loops; the first starts at the smallest boundary vertex (std::map order).
  std::vector<std::vector<int>> loops;
  std::map<int, bool> visited;
  for (const auto& [start, next] : boundary_next) {
    if (visited[start]) continue;
    std::vector<int> loop;
    int v = start;
    do {
      visited[v] = true;
      loop.push_back(v);
      const auto step = boundary_next.find(v);
      if (step == boundary_next.end())
        return failure(Status::non_manifold,
                       "the boundary is broken at vertex " + std::to_string(v));
      v = step->second;
    } while (v != start && loop.size() <= boundary_next.size());
    loops.push_back(std::move(loop));
  }
  if (loops.size() > 1)
    return failure(Status::not_a_disk, "the mesh has " + std::to_string(loops.size()) +
                                           " boundary loops; a disk has one: " + cut_hint +
                                           " (it joins the holes into one boundary)");

  const int euler = vertex_count - edge_count + face_count;
  if (euler != 1) {
    const int genus = (1 - euler) / 2;
    return failure(Status::not_a_disk, "the mesh has one boundary loop but genus " +
                                           std::to_string(genus) + " (Euler characteristic " +
                                           std::to_string(euler) + "): " + cut_hint);
  }
  DiskInput result;
  result.boundary_loop = std::move(loops.front());
  return result;
}

}  // namespace harmonia::detail
