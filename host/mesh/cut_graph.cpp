#include "mesh/cut_graph.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>

#include "mesh/shortest_paths.h"

namespace harmonia::detail {

namespace {

//! Parent of every vertex in the primal spanning tree (-1 at the root).
std::vector<int> primal_tree(const Mesh& mesh, const EdgeTable& edges,
                             const std::vector<std::vector<int>>& loops) {
  const EdgeGraph graph = build_edge_graph(mesh, edges);
  const int n = graph.vertex_count();
  std::vector<int> loop_of(static_cast<std::size_t>(n), -1);
  std::vector<int> position_in_loop(static_cast<std::size_t>(n), -1);
  for (std::size_t l = 0; l < loops.size(); ++l) {
    for (std::size_t k = 0; k < loops[l].size(); ++k) {
      loop_of[static_cast<std::size_t>(loops[l][k])] = static_cast<int>(l);
      position_in_loop[static_cast<std::size_t>(loops[l][k])] = static_cast<int>(k);
    }
  }
  std::vector<char> loop_joined(loops.size(), 0);
  std::vector<double> distance(static_cast<std::size_t>(n),
                               std::numeric_limits<double>::infinity());
  std::vector<int> parent(static_cast<std::size_t>(n), -1);
  std::vector<char> settled(static_cast<std::size_t>(n), 0);

  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  const int root = loops.empty() ? 0 : loops.front().front();
  distance[static_cast<std::size_t>(root)] = 0.0;
  queue.emplace(0.0, root);
  while (!queue.empty()) {
    const auto [d, u] = queue.top();
    queue.pop();
    if (settled[static_cast<std::size_t>(u)]) continue;
    settled[static_cast<std::size_t>(u)] = 1;

    const int loop = loop_of[static_cast<std::size_t>(u)];
    if (loop >= 0 && !loop_joined[static_cast<std::size_t>(loop)]) {
      // The growth reached this hole: the whole loop joins the tree here, along its own edges,
      // at the same distance (the loop then acts as one source, like the first loop does).
      loop_joined[static_cast<std::size_t>(loop)] = 1;
      const std::vector<int>& cycle = loops[static_cast<std::size_t>(loop)];
      const std::size_t m = cycle.size();
      const auto start = static_cast<std::size_t>(position_in_loop[static_cast<std::size_t>(u)]);
      for (std::size_t i = 1; i < m; ++i) {
        const int w = cycle[(start + i) % m];
        parent[static_cast<std::size_t>(w)] = cycle[(start + i - 1) % m];
        distance[static_cast<std::size_t>(w)] = d;
        queue.emplace(d, w);
      }
    }
    for (int k = graph.offset[static_cast<std::size_t>(u)];
         k < graph.offset[static_cast<std::size_t>(u) + 1]; ++k) {
      const int w = graph.neighbor[static_cast<std::size_t>(k)];
      if (settled[static_cast<std::size_t>(w)]) continue;
      // Holes are joined whole (above); the growth itself runs through the interior only.
      if (edges.face_count(graph.edge[static_cast<std::size_t>(k)]) == 1) continue;
      const double candidate = d + graph.length[static_cast<std::size_t>(k)];
      if (candidate < distance[static_cast<std::size_t>(w)]) {
        distance[static_cast<std::size_t>(w)] = candidate;
        parent[static_cast<std::size_t>(w)] = u;
        queue.emplace(candidate, w);
      }
    }
  }
  return parent;
}

}  // namespace

std::vector<CutEdge> tree_cotree_cut_graph(const Mesh& mesh, const EdgeTable& edges,
                                           const std::vector<std::vector<int>>& loops) {
  const auto edge_count = static_cast<std::size_t>(edges.size());
  std::vector<char> in_tree(edge_count, 0);
  const std::vector<int> parent = primal_tree(mesh, edges, loops);
  for (std::size_t v = 0; v < parent.size(); ++v) {
    if (parent[v] >= 0) {
      in_tree[static_cast<std::size_t>(edges.find(static_cast<int>(v), parent[v]))] = 1;
    }
  }

  // Cotree: breadth-first spanning tree of the faces across interior edges not in T.
  std::vector<char> in_cotree(edge_count, 0);
  const std::vector<int> corner_edge = edges.corner_edges();
  std::vector<char> reached(static_cast<std::size_t>(mesh.face_count()), 0);
  std::vector<int> queue{0};  // first-in first-out: faces are taken from `head` on
  reached[0] = 1;
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const int face = queue[head];
    for (int corner = 0; corner < 3; ++corner) {
      const int e =
          corner_edge[static_cast<std::size_t>(face) * 3 + static_cast<std::size_t>(corner)];
      if (edges.face_count(e) != 2 || in_tree[static_cast<std::size_t>(e)]) continue;
      const int other = edges.other_face(e, face);
      if (reached[static_cast<std::size_t>(other)]) continue;
      reached[static_cast<std::size_t>(other)] = 1;
      in_cotree[static_cast<std::size_t>(e)] = 1;
      queue.push_back(other);
    }
  }

  // The cut graph before pruning: T, the boundary, and the edges in neither tree, with the edges
  // at each vertex in compressed rows (increasing edge index).
  const auto vertex_count = static_cast<std::size_t>(mesh.vertex_count());
  std::vector<char> in_graph(edge_count, 0);
  std::vector<int> degree(vertex_count, 0);
  for (std::size_t e = 0; e < edge_count; ++e) {
    if (in_cotree[e]) continue;
    in_graph[e] = 1;
    ++degree[static_cast<std::size_t>(edges.first(static_cast<int>(e)))];
    ++degree[static_cast<std::size_t>(edges.second(static_cast<int>(e)))];
  }
  std::vector<std::size_t> incident_offset(vertex_count + 1, 0);
  for (std::size_t v = 0; v < vertex_count; ++v) {
    incident_offset[v + 1] = incident_offset[v] + static_cast<std::size_t>(degree[v]);
  }
  std::vector<int> incident(incident_offset[vertex_count]);
  std::vector<std::size_t> next_slot(incident_offset.begin(), incident_offset.end() - 1);
  for (std::size_t e = 0; e < edge_count; ++e) {
    if (!in_graph[e]) continue;
    for (const int v : {edges.first(static_cast<int>(e)), edges.second(static_cast<int>(e))}) {
      incident[next_slot[static_cast<std::size_t>(v)]++] = static_cast<int>(e);
    }
  }
  // Strip dangling branches: repeatedly remove the edge of a vertex of degree one. What remains
  // (the 2-core) does not depend on the order of removal.
  std::vector<int> leaves;  // first-in first-out from `head`
  for (std::size_t v = 0; v < vertex_count; ++v) {
    if (degree[v] == 1) leaves.push_back(static_cast<int>(v));
  }
  for (std::size_t head = 0; head < leaves.size(); ++head) {
    const auto v = static_cast<std::size_t>(leaves[head]);
    if (degree[v] != 1) continue;
    for (std::size_t k = incident_offset[v]; k < incident_offset[v + 1]; ++k) {
      const int e = incident[k];
      if (!in_graph[static_cast<std::size_t>(e)]) continue;
      in_graph[static_cast<std::size_t>(e)] = 0;
      for (const int w : {edges.first(e), edges.second(e)}) {
        if (--degree[static_cast<std::size_t>(w)] == 1) leaves.push_back(w);
      }
      break;
    }
  }

  std::vector<CutEdge> cut;
  for (std::size_t e = 0; e < edge_count; ++e) {
    const int edge = static_cast<int>(e);
    if (in_graph[e] && edges.face_count(edge) == 2)
      cut.emplace_back(edges.first(edge), edges.second(edge));
  }
  return cut;
}

CutMesh cut_along_edges(const Mesh& mesh, const HalfedgeMap& halfedges,
                        const std::vector<CutEdge>& cut_edges) {
  std::vector<CutEdge> cut_keys;
  for (const auto& [a, b] : cut_edges) cut_keys.emplace_back(std::min(a, b), std::max(a, b));
  std::sort(cut_keys.begin(), cut_keys.end());
  auto is_cut = [&cut_keys](int a, int b) {
    return std::binary_search(cut_keys.begin(), cut_keys.end(),
                              CutEdge{std::min(a, b), std::max(a, b)});
  };

  // Vertices on the cut in order of first appearance, with the first cut edge of each.
  std::vector<int> first_cut_neighbor(static_cast<std::size_t>(mesh.vertex_count()), -1);
  std::vector<int> order;
  for (const auto& [a, b] : cut_edges) {
    for (const auto& [v, w] : {CutEdge{a, b}, CutEdge{b, a}}) {
      if (first_cut_neighbor[static_cast<std::size_t>(v)] < 0) {
        first_cut_neighbor[static_cast<std::size_t>(v)] = w;
        order.push_back(v);
      }
    }
  }

  CutMesh result;
  result.mesh.faces = mesh.faces;
  std::vector<int>& original = result.original_vertex;
  original.resize(static_cast<std::size_t>(mesh.vertex_count()));
  for (int v = 0; v < mesh.vertex_count(); ++v) original[static_cast<std::size_t>(v)] = v;

  for (const int u : order) {
    // A boundary vertex's fan starts at its boundary half-edge leaving u (mesh on its left).
    int start = -1;
    for (const Halfedge& h : halfedges.leaving(u)) {
      if (halfedges.face_of(h.to, u) < 0) {
        start = h.face;
        break;
      }
    }
    if (start < 0) start = halfedges.face_of(u, first_cut_neighbor[static_cast<std::size_t>(u)]);

    // Walk the fan counter-clockwise: from a face holding u->x and w->u, the next face holds u->w.
    int wedge_vertex = u;
    int face = start;
    for (int steps = 0; steps <= mesh.face_count(); ++steps) {
      int corner = 0;
      while (mesh.faces(face, corner) != u) ++corner;
      result.mesh.faces(face, corner) = wedge_vertex;
      const int w = mesh.faces(face, (corner + 2) % 3);
      const int next = halfedges.face_of(u, w);
      if (next < 0 || next == start) break;
      if (is_cut(u, w)) {
        wedge_vertex = static_cast<int>(original.size());
        original.push_back(u);
      }
      face = next;
    }
  }

  result.mesh.vertices.resize(static_cast<Eigen::Index>(original.size()), 3);
  for (std::size_t v = 0; v < original.size(); ++v) {
    result.mesh.vertices.row(static_cast<Eigen::Index>(v)) = mesh.vertices.row(original[v]);
  }
  return result;
}

}  // namespace harmonia::detail
