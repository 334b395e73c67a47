#pragma once
//! \file topology.h
//! \brief Combinatorial facts about a mesh: edges, boundary loops, components, Euler characteristic,
//! genus, manifoldness, orientation, degenerate/duplicate faces, and the disk check every planar
//! method runs first.

#include <string>
#include <vector>

#include "harmonia/mesh.h"
#include "harmonia/types.h"

namespace harmonia {

//! An undirected edge as an ordered vertex pair (first < second).
struct EdgeKey {
  int first = 0;
  int second = 0;
  friend bool operator==(const EdgeKey&, const EdgeKey&) = default;
};

//! Everything `harmonia info` prints.
struct TopologyReport {
  int vertices = 0;
  int faces = 0;
  int edges = 0;
  //! Connected components of the faces (faces that share a vertex belong together).
  int components = 0;
  int boundary_loops = 0;           //!< Closed loops of boundary edges (0 for non-manifold boundaries).
  int boundary_edges = 0;
  int euler_characteristic = 0;     //!< V - E + F over referenced vertices.
  //! (2*components - chi - loops) / 2 for an orientable manifold (chi = 2c - 2g - b); 0 when the
  //! mesh is non-manifold or not orientable, where it is not defined.
  int genus = 0;
  bool orientable = true;           //!< Every component can be oriented consistently.
  bool consistently_oriented = true;//!< Every interior edge is used once in each direction.
  std::vector<EdgeKey> non_manifold_edges;  //!< Edges with more than two faces, sorted.
  std::vector<int> non_manifold_edge_faces; //!< Number of faces on each non-manifold edge.
  //! Vertices whose face fan is not one disk or half-disk: the faces around them, joined across
  //! edges with exactly two faces, fall into more than one fan (a bow-tie, or a vertex of a
  //! non-manifold edge).
  std::vector<int> non_manifold_vertices;
  //! Repeated index or zero area (|cross product| <= 1e-14 * longest edge squared).
  std::vector<int> degenerate_faces;
  std::vector<int> duplicate_faces;         //!< Same vertex set as an earlier face (later ones listed).
  std::vector<int> unreferenced_vertices;   //!< Vertices used by no face.
  //! Faces next to an edge used twice in one direction, sorted.
  std::vector<int> inconsistent_edges_faces;

  //! True for a manifold, consistently oriented, connected mesh with one boundary loop and genus 0,
  //! without degenerate or duplicate faces and without unreferenced vertices (which would make the
  //! linear systems of every planar method singular).
  [[nodiscard]] bool is_disk() const;
  //! True for a manifold, connected, closed mesh.
  [[nodiscard]] bool is_closed_manifold() const;
  //! Empty if is_disk(); otherwise one sentence saying what is wrong and how to fix it, naming
  //! counts and (0-based) indices, e.g. "closed mesh (no boundary loop): cut it open with
  //! `harmonia cut`" or "non-manifold edge (v12, v40) used by 3 faces: repair the mesh first".
  [[nodiscard]] std::string disk_problem() const;
  //! True for a mesh a spherical map accepts: what is_disk() asks of the structure (manifold,
  //! consistently oriented, connected, no degenerate, duplicate or unreferenced elements), closed
  //! and of genus 0.
  [[nodiscard]] bool is_sphere() const;
  //! Empty if is_sphere(); otherwise one sentence saying what the mesh is and what to do, e.g.
  //! "closed mesh of genus 1: a spherical map needs genus 0; ...".
  [[nodiscard]] std::string sphere_problem() const;
};

//! Analyzes the mesh. Indices out of range are reported through invalid_input in `check_indices`;
//! this function assumes valid indices.
[[nodiscard]] TopologyReport analyze_topology(const Mesh& mesh);

//! Status::ok, or invalid_input with a message naming the first face with an index out of range
//! or the first vertex with a non-finite coordinate.
[[nodiscard]] Status check_indices_and_coordinates(const Mesh& mesh, std::string* message);

//! Boundary loops as vertex sequences, each oriented so that the mesh lies to its left
//! (counter-clockwise for a disk drawn with outward-facing normals). Longest loop first (equal
//! lengths: smaller start vertex first); each loop starts at its smallest vertex index.
//! Requires an edge-manifold, consistently oriented mesh.
[[nodiscard]] std::vector<std::vector<int>> boundary_loops(const Mesh& mesh);

//! Undirected unique edges, #E by 2 (first < second), sorted by (first, second).
[[nodiscard]] Eigen::MatrixX2i unique_edges(const Mesh& mesh);

//! Status::ok if the mesh is a disk; otherwise not_a_disk / non_manifold / invalid_input with a
//! message that says what is wrong and how to fix it (`harmonia cut`, cleanup).
[[nodiscard]] Status check_disk(const Mesh& mesh, std::string* message);

//! Status::ok if the mesh is a closed genus-0 surface (TopologyReport::is_sphere); otherwise
//! not_a_sphere / non_manifold / invalid_input with sphere_problem()'s message.
[[nodiscard]] Status check_sphere(const Mesh& mesh, std::string* message);

}  // namespace harmonia
