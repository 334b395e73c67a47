#pragma once
//! \file edit_file.h
//! \brief Edit files: the JSON description of a surface edit (the format of
//! ../shared/data/edit/README.md), read against the mesh it is applied to.
//!
//!   {"fixed":   {"vertices": [i, ...]},
//!    "handles": [{"vertices": [i, ...],
//!                 "translate": [tx, ty, tz],
//!                 "rotate": {"axis": [ax, ay, az], "degrees": d, "center": [cx, cy, cz]},
//!                 "scale": s}],
//!    "region_of_interest": {"vertices": [...]}}
//!
//! A handle's target for a rest point p is center + R(axis, degrees) (s (p - center)) + t
//! (harmonia::SimilarityTransform); `center` defaults to the mean of the handle's rest positions,
//! `scale` to 1, `translate` to 0, a missing `rotate` to the identity. Any vertex set may be given
//! instead by a ball, {"sphere": {"center": [x, y, z], "radius": r}}: the vertices within distance r
//! of the centre. `fixed` and `region_of_interest` are optional (no fixed vertex; the whole mesh).
//! `mesh`, `description`, each set's `selection` and any other key are informational and ignored.

#include <filesystem>
#include <string>
#include <vector>

#include "harmonia/mesh.h"
#include "harmonia/surface_editor.h"

namespace harmonia {

struct EditDescription {
  EditRegions regions;
  std::vector<SimilarityTransform> transforms;  //!< One per handle.
  std::string mesh_name;                        //!< The informational `mesh` key, if any.
  std::string description;                      //!< The informational `description`, if any.
};

//! Parses an edit from JSON text for `mesh`. Throws harmonia::Error: parse_error for malformed JSON
//! (naming `source`, line and column), invalid_input for a missing or mistyped field (naming it,
//! e.g. "handles[1].rotate.axis"), a vertex index outside the mesh (naming the set and the index), a
//! zero rotation axis, a non-positive scale, a ball that selects no vertex.
[[nodiscard]] EditDescription parse_edit(const std::string& json_text, const Mesh& mesh,
                                         const std::string& source = "edit");

//! Reads and parses an edit file; io_error if it cannot be read.
[[nodiscard]] EditDescription read_edit_file(const std::filesystem::path& path, const Mesh& mesh);

}  // namespace harmonia
