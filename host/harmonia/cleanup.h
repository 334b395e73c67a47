#pragma once
//! \file cleanup.h
//! \brief Dirty-input handling: merge duplicate vertices, drop degenerate/duplicate faces and
//! unreferenced vertices, make orientation consistent. Strict mode refuses and says what is wrong;
//! repair mode does it and reports exactly what it changed. The default is strict (docs/cli.md,
//! "Dirty input"): a library should not silently change a user's mesh.

#include <string>
#include <vector>

#include "harmonia/mesh.h"
#include "harmonia/types.h"

namespace harmonia {

enum class CleanupMode {
  strict,  //!< Change nothing; return non_manifold/invalid_input naming the first problem.
  repair,  //!< Fix what can be fixed and list every change.
};

struct CleanupOptions {
  CleanupMode mode = CleanupMode::strict;  //!< Default: strict.
  //! Vertices closer than this (relative to the bounding-box diagonal) are merged in repair mode.
  //! 0 merges only exactly equal positions.
  double merge_tolerance = 0.0;
  //! Repair mode: keep what repair cannot fix (non-manifold edges and vertices, a surface that is
  //! not orientable) and report it in `changes`, instead of refusing the mesh. For consumers that
  //! cut the surface there: the texture atlas, whose charts never cross such an edge. Welding the
  //! split vertices of a real asset makes such elements (a hard edge shared by several surfaces,
  //! parts that touch): normal there, not an error.
  bool keep_non_manifold = false;
};

struct CleanupResult {
  Mesh mesh;  //!< The cleaned mesh (equal to the input in strict mode or when nothing changed).
  //! For each input vertex, its index in `mesh`, or -1 if it was removed. #V_in entries.
  Eigen::VectorXi vertex_map;
  //! For each output vertex, the input vertex it came from (the first of a merged group).
  Eigen::VectorXi original_vertex;
  //! For each output face, the input face it came from.
  Eigen::VectorXi original_face;
  int merged_vertices = 0;
  int removed_unreferenced_vertices = 0;
  int removed_degenerate_faces = 0;
  int removed_duplicate_faces = 0;
  int flipped_faces = 0;               //!< Faces reversed to make orientation consistent.
  std::vector<std::string> changes;    //!< One line per kind of change, for the report.
  Status status = Status::ok;
  std::string message;                 //!< In strict mode: the first problem and how to fix it.
  [[nodiscard]] bool changed() const;
};

[[nodiscard]] CleanupResult cleanup(const Mesh& mesh, const CleanupOptions& options = {});

}  // namespace harmonia
