#include "harmonia/cut.h"

#include <limits>
#include <string>
#include <vector>

#include "harmonia/topology.h"
#include "mesh/cut_graph.h"
#include "mesh/disk_diagnosis.h"
#include "mesh/edge_table.h"
#include "mesh/halfedge_map.h"
#include "mesh/power_of_two_scale.h"
#include "mesh/shortest_paths.h"

namespace harmonia {

namespace {

CutResult failure(Status status, std::string message) {
  CutResult result;
  result.status = status;
  result.message = std::move(message);
  return result;
}

std::string vertex_text(int v) {
  std::string text = "vertex ";
  text += std::to_string(v);
  return text;
}

//! Checks the user's end points: both or neither, in range, distinct. Empty when fine.
std::string end_point_problem(const Mesh& mesh, const CutOptions& options) {
  if (options.from_vertex.has_value() != options.to_vertex.has_value()) {
    return "give both end points of the cut (from and to) or neither";
  }
  if (!options.from_vertex.has_value()) return "";
  for (const auto& [name, vertex] :
       {std::pair{"from", *options.from_vertex}, std::pair{"to", *options.to_vertex}}) {
    if (vertex < 0 || vertex >= mesh.vertex_count()) {
      return std::string(name) + " " + vertex_text(vertex) + " is out of range (the mesh has " +
             std::to_string(mesh.vertex_count()) + " vertices, 0-based)";
    }
  }
  if (*options.from_vertex == *options.to_vertex) {
    return "from and to are the same vertex (" + std::to_string(*options.from_vertex) +
           "): a cut needs two distinct end points";
  }
  return "";
}

//! The thesis' cut of a closed genus-0 surface: the shortest edge path between two vertices, far
//! apart unless given. Far apart = double sweep: the farthest vertex A from vertex 0, then the
//! farthest vertex B from A. Path listed from A to B (copies in path order, originals on the
//! right-hand side: the convention of the corpus' disk/*-cut.obj).
std::vector<detail::CutEdge> shortest_path_cut(const Mesh& mesh, const CutOptions& options) {
  const detail::EdgeGraph graph = detail::build_edge_graph(mesh, detail::EdgeTable(mesh));
  int from = 0;
  int to = 0;
  detail::ShortestPathTree tree;
  if (options.from_vertex.has_value()) {
    from = *options.from_vertex;
    to = *options.to_vertex;
    tree = detail::dijkstra(graph, from);
  } else {
    from = detail::farthest_vertex(detail::dijkstra(graph, 0));
    tree = detail::dijkstra(graph, from);
    to = detail::farthest_vertex(tree);
  }
  std::vector<int> path = detail::path_to(tree, to);
  if (path.size() == 2) {
    // Cutting one edge opens nothing (its ends stay single), so neighbouring end points are
    // joined through the common neighbour (third vertex of a face on the edge) nearest to both.
    const detail::HalfedgeMap halfedges(mesh);
    double best_length = std::numeric_limits<double>::infinity();
    int best = -1;
    for (const int face : {halfedges.face_of(from, to), halfedges.face_of(to, from)}) {
      for (int k = 0; k < 3; ++k) {
        const int m = mesh.faces(face, k);
        if (m == from || m == to) continue;
        const double length = (mesh.vertices.row(from) - mesh.vertices.row(m)).norm() +
                              (mesh.vertices.row(m) - mesh.vertices.row(to)).norm();
        if (length < best_length || (length == best_length && m < best)) {
          best_length = length;
          best = m;
        }
      }
    }
    path.insert(path.begin() + 1, best);
  }
  std::vector<detail::CutEdge> cut;
  for (std::size_t k = 1; k < path.size(); ++k) cut.emplace_back(path[k - 1], path[k]);
  return cut;
}

}  // namespace

CutResult cut_to_disk(const Mesh& mesh, const CutOptions& options) {
  std::string message;
  if (const Status status = check_indices_and_coordinates(mesh, &message); status != Status::ok) {
    return failure(status, message);
  }
  if (std::string problem = end_point_problem(mesh, options); !problem.empty()) {
    return failure(Status::invalid_input, problem);
  }
  const TopologyReport report = analyze_topology(mesh);
  const Status topology_status = detail::disk_status(report, &message);
  if (topology_status == Status::ok) {
    if (options.from_vertex.has_value()) {
      return failure(Status::invalid_input,
                     "the mesh already is a disk; cut end points (from/to) apply to closed "
                     "genus-0 meshes only");
    }
    CutResult result;
    result.disk = mesh;
    result.original_vertex =
        Eigen::VectorXi::LinSpaced(mesh.vertex_count(), 0, mesh.vertex_count() - 1);
    return result;
  }
  // Only the topology may be wrong: a connected, clean, consistently oriented manifold.
  if (topology_status != Status::not_a_disk || report.components != 1) {
    return failure(topology_status, "cannot cut: " + message);
  }

  const bool closed_sphere = report.boundary_loops == 0 && report.genus == 0;
  if (options.from_vertex.has_value() && !closed_sphere) {
    return failure(Status::invalid_input,
                   "cut end points (from/to) apply to closed genus-0 meshes only; this mesh has " +
                       std::to_string(report.boundary_loops) + " boundary loop(s) and genus " +
                       std::to_string(report.genus));
  }

  const detail::HalfedgeMap halfedges(mesh);
  // The seams follow edge lengths, measured on the copy of unit size: path lengths of a model in
  // units of 1e300 would overflow, and scaling by a power of two changes no comparison of lengths.
  const Mesh unit = detail::unit_scaled(mesh).mesh;
  std::vector<detail::CutEdge> cut_edges;
  if (closed_sphere) {
    cut_edges = shortest_path_cut(unit, options);
  } else {
    cut_edges = detail::tree_cotree_cut_graph(unit, detail::EdgeTable(unit), boundary_loops(unit));
  }
  detail::CutMesh cut = detail::cut_along_edges(mesh, halfedges, cut_edges);

  CutResult result;
  result.disk = std::move(cut.mesh);
  result.original_vertex = Eigen::Map<const Eigen::VectorXi>(
      cut.original_vertex.data(), static_cast<Eigen::Index>(cut.original_vertex.size()));
  result.seam_edges = static_cast<int>(cut_edges.size());
  // The cut is only handed out if it really is a disk.
  if (const Status status = check_disk(result.disk, &message); status != Status::ok) {
    return failure(Status::not_a_disk, "cutting did not produce a disk (" + message +
                                           "); please report this mesh as a bug");
  }
  return result;
}

TexturedMesh textured_from_cut(const Mesh& input, const CutResult& cut,
                               const Eigen::MatrixX2d& disk_uv) {
  if (disk_uv.rows() != cut.disk.vertices.rows()) {
    throw Error(Status::invalid_input, "textured_from_cut: " + std::to_string(disk_uv.rows()) +
                                           " UV rows for a cut mesh of " +
                                           std::to_string(cut.disk.vertices.rows()) + " vertices");
  }
  if (cut.disk.faces.rows() != input.faces.rows()) {
    throw Error(Status::invalid_input,
                "textured_from_cut: the cut mesh has " + std::to_string(cut.disk.faces.rows()) +
                    " faces but the input has " + std::to_string(input.faces.rows()));
  }
  TexturedMesh textured;
  textured.mesh = input;
  textured.uv = disk_uv;
  textured.uv_faces = cut.disk.faces;
  return textured;
}

}  // namespace harmonia
