#pragma once
// The two halves of cutting a surface into a disk: choosing the cut graph (tree-cotree, joined to
// the boundary) and cutting the mesh open along a set of edges.

#include <utility>
#include <vector>

#include "harmonia/mesh.h"
#include "mesh/edge_table.h"
#include "mesh/halfedge_map.h"

namespace harmonia::detail {

//! An edge to cut, as an ordered pair of vertices. The order matters only for the numbering of the
//! copies (see cut_along_edges).
using CutEdge = std::pair<int, int>;

//! Interior edges of a cut graph for a connected, consistently oriented manifold that is not a
//! closed genus-0 surface, sorted. Together with the boundary they form a connected graph whose
//! complement is one disk.
//!
//! Tree-cotree: a primal spanning tree T grown by Dijkstra from the first boundary loop (or from
//! vertex 0 when closed), in which each boundary loop joins the tree whole, at the vertex where the
//! growth first reaches it (so T holds every boundary edge but one per loop and the shortest paths
//! that join the holes); then a spanning tree of the faces across interior edges not in T. The 2g
//! interior edges in neither tree close the handle loops. T, those edges and the boundary,
//! stripped of dangling branches, are the cut graph.
[[nodiscard]] std::vector<CutEdge> tree_cotree_cut_graph(
    const Mesh& mesh, const EdgeTable& edges, const std::vector<std::vector<int>>& loops);

//! A mesh cut open along interior edges.
struct CutMesh {
  Mesh mesh;
  std::vector<int> original_vertex;  //!< Per output vertex: the input vertex it copies.
};

//! Cuts a consistently oriented manifold open along `cut_edges` (interior edges).
//!
//! Each vertex touched by the cut has its face fan split into wedges at the cut edges (and at the
//! boundary). Vertices are visited in order of first appearance in `cut_edges`; one wedge keeps
//! the original vertex and every further wedge, counter-clockwise from it, gets a copy appended to
//! the vertex list. The wedge that keeps the original begins, counter-clockwise, at the fan's start
//! on the boundary for a boundary vertex, and otherwise at the vertex's first listed cut edge. For
//! a path listed from A to B this keeps the original on the right-hand side of the path and appends
//! the copies of the inner path vertices in path order. Faces keep their order.
[[nodiscard]] CutMesh cut_along_edges(const Mesh& mesh, const HalfedgeMap& halfedges,
                                      const std::vector<CutEdge>& cut_edges);

}  // namespace harmonia::detail
