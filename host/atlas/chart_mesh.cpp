#include "atlas/chart_mesh.h"

#include <algorithm>
#include <deque>
#include <limits>
#include <map>
#include <numeric>
#include <queue>
#include <unordered_map>

#include "harmonia/topology.h"

namespace harmonia::detail {
namespace {

// Union-find over the corners of a chart: two corners at the same surface vertex are one chart
// vertex when their faces are neighbours across an edge through that vertex.
class CornerSets {
 public:
  explicit CornerSets(std::size_t count) : parent_(count) { std::iota(parent_.begin(), parent_.end(), 0); }
  std::size_t root(std::size_t corner) {
    while (parent_[corner] != corner) corner = parent_[corner] = parent_[parent_[corner]];
    return corner;
  }
  void join(std::size_t a, std::size_t b) {
    a = root(a);
    b = root(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::size_t> parent_;
};

// Breadth-first steps across the chart's edges from `start`; -1 for faces it cannot reach.
std::vector<int> steps_from(const FaceGeometry& geometry, const std::unordered_map<int, int>& index,
                            const std::vector<int>& faces, const std::vector<int>& starts) {
  std::vector<int> steps(faces.size(), -1);
  std::deque<int> frontier;
  for (const int start : starts) {
    steps[static_cast<std::size_t>(index.at(start))] = 0;
    frontier.push_back(start);
  }
  while (!frontier.empty()) {
    const int face = frontier.front();
    frontier.pop_front();
    const int here = steps[static_cast<std::size_t>(index.at(face))];
    for (const int other : geometry.across[static_cast<std::size_t>(face)]) {
      if (other < 0) continue;
      const auto found = index.find(other);
      if (found == index.end() || steps[static_cast<std::size_t>(found->second)] >= 0) continue;
      steps[static_cast<std::size_t>(found->second)] = here + 1;
      frontier.push_back(other);
    }
  }
  return steps;
}

// The face farthest from `start` in steps (ties: lower rank).
int farthest_face(const FaceGeometry& geometry, const std::unordered_map<int, int>& index,
                  const std::vector<int>& faces, int start) {
  const std::vector<int> steps = steps_from(geometry, index, faces, {start});
  int best = start;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const int best_steps = steps[static_cast<std::size_t>(index.at(best))];
    if (steps[i] > best_steps ||
        (steps[i] == best_steps && geometry.rank[static_cast<std::size_t>(faces[i])] <
                                       geometry.rank[static_cast<std::size_t>(best)]))
      best = faces[i];
  }
  return best;
}

}  // namespace

ChartMesh chart_mesh(const Mesh& surface, const FaceGeometry& geometry, std::vector<int> faces,
                     const std::set<SurfaceEdge>& cuts) {
  std::sort(faces.begin(), faces.end());
  std::unordered_map<int, int> index;  // surface face -> chart face
  index.reserve(faces.size());
  for (std::size_t i = 0; i < faces.size(); ++i) index.emplace(faces[i], static_cast<int>(i));
  CornerSets corners(faces.size() * 3);
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const int other = geometry.across[static_cast<std::size_t>(faces[i])][static_cast<std::size_t>(k)];
      if (other < 0) continue;
      const auto found = index.find(other);
      if (found == index.end()) continue;
      // Edge k runs from corner k to corner k+1; in the other face the same two vertices.
      const auto j = static_cast<std::size_t>(found->second);
      if (!cuts.empty()) {
        const int from = surface.faces(faces[i], k), to = surface.faces(faces[i], (k + 1) % 3);
        if (cuts.contains({std::min(from, to), std::max(from, to)})) continue;
      }
      for (int end = 0; end < 2; ++end) {
        const int vertex = surface.faces(faces[i], (k + end) % 3);
        for (int m = 0; m < 3; ++m)
          if (surface.faces(other, m) == vertex) corners.join(3 * i + static_cast<std::size_t>((k + end) % 3), 3 * j + static_cast<std::size_t>(m));
      }
    }
  ChartMesh chart;
  chart.surface_face = faces;
  chart.mesh.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
  std::vector<int> vertex_of_root(faces.size() * 3, -1);
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const std::size_t root = corners.root(3 * i + static_cast<std::size_t>(k));
      if (vertex_of_root[root] < 0) {
        vertex_of_root[root] = static_cast<int>(chart.surface_vertex.size());
        chart.surface_vertex.push_back(surface.faces(faces[i], k));
      }
      chart.mesh.faces(static_cast<Eigen::Index>(i), k) = vertex_of_root[root];
    }
  chart.mesh.vertices.resize(static_cast<Eigen::Index>(chart.surface_vertex.size()), 3);
  for (std::size_t v = 0; v < chart.surface_vertex.size(); ++v)
    chart.mesh.vertices.row(static_cast<Eigen::Index>(v)) = surface.vertices.row(chart.surface_vertex[v]);
  return chart;
}

bool is_disk(const ChartMesh& chart) {
  const Eigen::MatrixX3i& faces = chart.mesh.faces;
  const auto face_count = static_cast<int>(faces.rows());
  const auto vertex_count = static_cast<int>(chart.surface_vertex.size());
  if (face_count == 0) return false;
  // The faces around each vertex (compressed rows: faces_at[first[v] .. first[v + 1])).
  std::vector<int> first(static_cast<std::size_t>(vertex_count) + 1, 0);
  for (int f = 0; f < face_count; ++f)
    for (int k = 0; k < 3; ++k) ++first[static_cast<std::size_t>(faces(f, k)) + 1];
  for (int v = 0; v < vertex_count; ++v) first[v + 1] += first[v];
  std::vector<int> faces_at(static_cast<std::size_t>(3 * face_count));
  {
    std::vector<int> next(first.begin(), first.end() - 1);
    for (int f = 0; f < face_count; ++f)
      for (int k = 0; k < 3; ++k) faces_at[static_cast<std::size_t>(next[faces(f, k)]++)] = f;
  }
  // Each half-edge a -> b: the faces holding both ends, found around a. An edge counts once (at
  // its lowest face); a boundary edge (one face) links a to b along its loop.
  std::vector<int> boundary_next(static_cast<std::size_t>(vertex_count), -1);
  long long unique_edges = 0, boundary_edges = 0;
  for (int f = 0; f < face_count; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = faces(f, k), b = faces(f, (k + 1) % 3);
      int sharing = 0, lowest = f;
      for (int slot = first[a]; slot < first[a + 1]; ++slot) {
        const int g = faces_at[static_cast<std::size_t>(slot)];
        if (faces(g, 0) == b || faces(g, 1) == b || faces(g, 2) == b) {
          ++sharing;
          lowest = std::min(lowest, g);
        }
      }
      if (lowest == f) ++unique_edges;
      if (sharing == 1) {
        ++boundary_edges;
        if (boundary_next[static_cast<std::size_t>(a)] >= 0) return false;  // pinched boundary
        boundary_next[static_cast<std::size_t>(a)] = b;
      }
    }
  if (boundary_edges == 0) return false;  // closed
  // One boundary loop: following it from one boundary vertex passes every boundary edge.
  int start = -1;
  for (int v = 0; v < vertex_count && start < 0; ++v)
    if (boundary_next[static_cast<std::size_t>(v)] >= 0) start = v;
  long long loop_length = 0;
  for (int v = start; loop_length <= boundary_edges;) {
    v = boundary_next[static_cast<std::size_t>(v)];
    ++loop_length;
    if (v < 0) return false;
    if (v == start) break;
  }
  if (loop_length != boundary_edges) return false;  // more than one boundary loop
  const long long euler = static_cast<long long>(vertex_count) - unique_edges + face_count;
  if (euler != 1) return false;
  // Connected: every face reached from the first through shared vertices.
  std::vector<char> reached(static_cast<std::size_t>(face_count), 0);
  std::vector<int> frontier{0};
  reached[0] = 1;
  int reached_count = 1;
  while (!frontier.empty()) {
    const int f = frontier.back();
    frontier.pop_back();
    for (int k = 0; k < 3; ++k) {
      const int v = faces(f, k);
      for (int slot = first[v]; slot < first[v + 1]; ++slot) {
        const int g = faces_at[static_cast<std::size_t>(slot)];
        if (!reached[static_cast<std::size_t>(g)]) {
          reached[static_cast<std::size_t>(g)] = 1;
          ++reached_count;
          frontier.push_back(g);
        }
      }
    }
  }
  return reached_count == face_count;
}

std::optional<ChartMesh> cut_holes_open(const Mesh& surface, const FaceGeometry& geometry,
                                        const ChartMesh& chart) {
  const Mesh& mesh = chart.mesh;
  std::vector<std::vector<int>> loops = boundary_loops(mesh);
  if (loops.size() < 2) return std::nullopt;
  // Genus from the Euler characteristic: chi = 2 - 2 genus - loops.
  const long long edges = unique_edges(mesh).rows();
  const long long euler = static_cast<long long>(mesh.vertices.rows()) - edges + mesh.faces.rows();
  if (2 - static_cast<long long>(loops.size()) - euler != 0) return std::nullopt;
  const auto loop_length = [&mesh](const std::vector<int>& loop) {
    double length = 0.0;
    for (std::size_t i = 0; i < loop.size(); ++i)
      length += (mesh.vertices.row(loop[i]) - mesh.vertices.row(loop[(i + 1) % loop.size()])).norm();
    return length;
  };
  std::stable_sort(loops.begin(), loops.end(), [&](const std::vector<int>& a, const std::vector<int>& b) {
    return loop_length(a) > loop_length(b);
  });
  const auto vertex_count = static_cast<std::size_t>(mesh.vertices.rows());
  std::vector<int> loop_of(vertex_count, -1);
  for (std::size_t l = 0; l < loops.size(); ++l)
    for (const int v : loops[l]) loop_of[static_cast<std::size_t>(v)] = static_cast<int>(l);
  // Interior edges (two faces) as a graph of the chart's vertices.
  std::vector<std::vector<std::pair<int, double>>> neighbours(vertex_count);
  {
    std::map<std::pair<int, int>, int> uses;
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = mesh.faces(f, k), b = mesh.faces(f, (k + 1) % 3);
        ++uses[{std::min(a, b), std::max(a, b)}];
      }
    for (const auto& [edge, count] : uses)
      if (count == 2) {
        const double length = (mesh.vertices.row(edge.first) - mesh.vertices.row(edge.second)).norm();
        neighbours[static_cast<std::size_t>(edge.first)].emplace_back(edge.second, length);
        neighbours[static_cast<std::size_t>(edge.second)].emplace_back(edge.first, length);
      }
  }
  std::vector<char> joined(vertex_count, 0);  // on the outer loop, a joined hole or a cut
  for (const int v : loops[0]) joined[static_cast<std::size_t>(v)] = 1;
  std::vector<char> loop_joined(loops.size(), 0);
  loop_joined[0] = 1;
  std::set<SurfaceEdge> cuts;
  for (std::size_t round = 1; round < loops.size(); ++round) {
    // Dijkstra from everything joined; boundary vertices of holes not yet joined end the search,
    // and no path runs along the boundary or through another hole.
    std::vector<double> distance(vertex_count, std::numeric_limits<double>::infinity());
    std::vector<int> previous(vertex_count, -1);
    using Entry = std::pair<double, int>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
    for (std::size_t v = 0; v < vertex_count; ++v)
      if (joined[v]) {
        distance[v] = 0.0;
        queue.emplace(0.0, static_cast<int>(v));
      }
    int reached = -1;
    while (!queue.empty()) {
      const auto [here, vertex] = queue.top();
      queue.pop();
      const auto v = static_cast<std::size_t>(vertex);
      if (here > distance[v]) continue;
      if (loop_of[v] >= 0 && !loop_joined[static_cast<std::size_t>(loop_of[v])]) {
        reached = vertex;
        break;
      }
      if (loop_of[v] >= 0 && !joined[v]) continue;
      for (const auto& [next, length] : neighbours[v]) {
        const auto n = static_cast<std::size_t>(next);
        if (joined[n] && here > 0.0) continue;
        if (here + length < distance[n]) {
          distance[n] = here + length;
          previous[n] = vertex;
          queue.emplace(distance[n], next);
        }
      }
    }
    if (reached < 0) return std::nullopt;
    for (int v = reached; previous[static_cast<std::size_t>(v)] >= 0; v = previous[static_cast<std::size_t>(v)]) {
      const int a = chart.surface_vertex[static_cast<std::size_t>(v)];
      const int b = chart.surface_vertex[static_cast<std::size_t>(previous[static_cast<std::size_t>(v)])];
      cuts.insert({std::min(a, b), std::max(a, b)});
      joined[static_cast<std::size_t>(v)] = 1;
    }
    const auto hole = static_cast<std::size_t>(loop_of[static_cast<std::size_t>(reached)]);
    loop_joined[hole] = 1;
    for (const int v : loops[hole]) joined[static_cast<std::size_t>(v)] = 1;
  }
  ChartMesh opened = chart_mesh(surface, geometry, chart.surface_face, cuts);
  if (!is_disk(opened)) return std::nullopt;
  return opened;
}

namespace {

// The faces nearer (in steps across edges) to `first` than to `second`, ties to `first`, and the
// rest; `index`: each face's position in `faces`.
std::vector<std::vector<int>> halves_around(const FaceGeometry& geometry,
                                            const std::unordered_map<int, int>& index,
                                            const std::vector<int>& faces, int first, int second) {
  const std::vector<int> from_first = steps_from(geometry, index, faces, {first});
  const std::vector<int> from_second = steps_from(geometry, index, faces, {second});
  std::vector<std::vector<int>> halves(2);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    // Faces the first cannot reach (another connected part) go with the second.
    const bool nearer_first = from_first[i] >= 0 && (from_second[i] < 0 || from_first[i] <= from_second[i]);
    halves[nearer_first ? 0 : 1].push_back(faces[i]);
  }
  if (halves[1].empty() || halves[0].empty()) {
    // One face apart from the rest at worst: the first face alone.
    halves = {{faces.front()}, std::vector<int>(faces.begin() + 1, faces.end())};
  }
  return halves;
}

std::unordered_map<int, int> positions_of(const std::vector<int>& faces) {
  std::unordered_map<int, int> index;
  for (std::size_t i = 0; i < faces.size(); ++i) index.emplace(faces[i], static_cast<int>(i));
  return index;
}

}  // namespace

ChartMesh opened_chart(const Mesh& surface, const FaceGeometry& geometry, const std::vector<int>& faces) {
  ChartMesh mesh = chart_mesh(surface, geometry, faces);
  if (!is_disk(mesh))
    if (std::optional<ChartMesh> opened = cut_holes_open(surface, geometry, mesh)) mesh = std::move(*opened);
  return mesh;
}

std::vector<std::vector<int>> split_in_two(const FaceGeometry& geometry, const std::vector<int>& faces) {
  if (faces.size() < 2) return {faces};
  const std::unordered_map<int, int> index = positions_of(faces);
  // Lowest rank as the start, so that the split does not depend on the order of `faces`.
  const int start = *std::min_element(faces.begin(), faces.end(), [&](int a, int b) {
    return geometry.rank[static_cast<std::size_t>(a)] < geometry.rank[static_cast<std::size_t>(b)];
  });
  const int first = farthest_face(geometry, index, faces, start);
  const int second = farthest_face(geometry, index, faces, first);
  return halves_around(geometry, index, faces, first, second);
}

std::vector<std::vector<int>> split_between(const FaceGeometry& geometry, const std::vector<int>& faces,
                                            int first, int second) {
  if (faces.size() < 2) return {faces};
  return halves_around(geometry, positions_of(faces), faces, first, second);
}

}  // namespace harmonia::detail
