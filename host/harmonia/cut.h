#pragma once
//! \file cut.h
//! \brief Cutting a mesh into a disk. Closed genus-0: the shortest edge path (Dijkstra, Euclidean
//! edge lengths) between two far-apart vertices (double sweep) or two given vertices, the thesis'
//! own way of cutting. Genus 0 with several holes: the holes are joined to the first by shortest
//! paths. Higher genus: a cut graph (tree-cotree) joined to the boundary if there is one.

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
  int seam_edges = 0;              //!< Number of input edges that were cut open.
  Status status = Status::ok;
  std::string message;
};

//! Cuts `mesh` into a disk. A mesh that already is a disk is returned unchanged (identity map).
//! Non-manifold or disconnected input gives a status with a message naming the problem.
[[nodiscard]] CutResult cut_to_disk(const Mesh& mesh, const CutOptions& options = {});

//! The layout a cut implies for writing: the input mesh plus per-corner UV indices = disk faces.
[[nodiscard]] TexturedMesh textured_from_cut(const Mesh& input, const CutResult& cut,
                                             const Eigen::MatrixX2d& disk_uv);

}  // namespace harmonia
