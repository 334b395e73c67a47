#pragma once
//! \file cut.h
//! \brief Cutting a mesh into a disk. Closed genus-0: the shortest edge path (Dijkstra, Euclidean
//! edge lengths) between two far-apart vertices (double sweep: the farthest vertex A from vertex 0,
//! then the farthest B from A) or two given vertices, the thesis' own way of cutting; if the end
//! points are neighbours the path goes through their nearest common neighbour (one cut edge would
//! open nothing). Genus 0 with several holes: the holes are joined to the first (longest) by
//! shortest paths through the interior, grown from the holes already joined. Higher genus: a cut
//! graph (tree-cotree) joined to the boundary if there is one.
//!
//! Numbering (the convention of the corpus' disk/X-cut.obj): the first #V vertices of the disk are
//! the input's, in order; copies are appended; faces keep their order and only the indices of
//! copied corners change. Along a path cut from A to B, the faces on the right of the path keep
//! the original vertices, those on the left use the copies, appended in path order; A and B stay
//! single.

#include <optional>
#include <string>

#include "harmonia/mesh.h"
#include "harmonia/types.h"

namespace harmonia {

struct CutOptions {
  std::optional<int> from_vertex;  //!< First end of the cut path (closed genus-0 only).
  std::optional<int> to_vertex;    //!< Second end of the cut path (closed genus-0 only).
};

//! A disk made by cutting, with the seams recorded.
struct CutResult {
  Mesh disk;                       //!< Cut mesh: vertices on the cut are duplicated; faces keep order.
  Eigen::VectorXi original_vertex; //!< #disk.V: the input vertex each disk vertex copies.
  int seam_edges = 0;              //!< Number of input edges that were cut open (each becomes two
                                   //!< boundary edges of the disk).
  Status status = Status::ok;
  std::string message;
};

//! Cuts `mesh` into a disk. A mesh that already is a disk is returned unchanged (identity map).
//! Non-manifold or disconnected input gives a status with a message naming the problem; from/to
//! out of range, equal, only one of them, or given for a mesh that is not closed genus-0 give
//! invalid_input. The result is verified with check_disk before it is returned with Status::ok.
[[nodiscard]] CutResult cut_to_disk(const Mesh& mesh, const CutOptions& options = {});

//! The layout a cut implies for writing: the input mesh plus per-corner UV indices = disk faces.
//! Throws Error(invalid_input) if disk_uv does not have one row per disk vertex.
[[nodiscard]] TexturedMesh textured_from_cut(const Mesh& input, const CutResult& cut,
                                             const Eigen::MatrixX2d& disk_uv);

}  // namespace harmonia
