#pragma once
//! \file view_page.h
//! \brief A page to look at UV layouts in a browser (`harmonia view`): one self-contained HTML
//! file, no network and no server, holding the meshes and the scripts that draw them (three.js,
//! embedded in the library). Each layout shows the 3D model, turnable and zoomable, wearing a
//! checker through its UVs or coloured per triangle by angle distortion, area distortion or L2
//! stretch (with a colour bar and its values), chart boundaries and seams drawn and turned-over
//! triangles marked; beside it the UV square, linked: hovering a triangle in either highlights it
//! and its chart in both and shows its figures. Several layouts of one mesh are shown side by
//! side on one camera.
//!
//! \code
//!   harmonia::ViewLayout layout{"atlas", "texture atlas", mesh, atlas.uv, atlas.uv_faces};
//!   harmonia::write_view_page("atlas.html", {layout}, {.title = "spot.obj"});
//! \endcode

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia {

//! One layout on the page: a 3D mesh and its per-corner UVs.
struct ViewLayout {
  std::string name;    //!< Its label on the page, e.g. the file name.
  std::string method;  //!< What made it, shown when hovering, e.g. "texture atlas".
  Mesh mesh3d;
  Eigen::MatrixX2d uv;        //!< #UV by 2.
  Eigen::MatrixX3i uv_faces;  //!< One row per face of mesh3d, indexing uv (its corners in the same order).
  //! The chart of each face (an atlas' own ids, 0 and up); empty: the charts are the faces
  //! connected through shared UV vertices, numbered in the order of their first face.
  std::vector<int> chart_of_face{};
};

struct ViewPageOptions {
  std::string title{};  //!< The page's headline, e.g. the mesh's name.
  //! Label and value pairs shown beside the title, e.g. {"coverage", "0.691"}.
  std::vector<std::pair<std::string, std::string>> headline{};
};

//! Writes the page (atomically: a failed write leaves nothing behind). Per layout the page holds
//! its charts (chart_of_face), per triangle its angle distortion
//! (face_angle_distortion), log area ratio and L2 stretch (DistortionMetrics) and whether it is
//! turned over or of zero area, per chart its face count and L2 stretch. The colour bar of each
//! field spans its values over all the layouts, from the 2nd to the 98th percentile and always
//! including an isometry's value (0; 1 for the stretch), symmetric about 0 for the log area ratio.
//! Throws Error(invalid_input) for no layout, a layout whose uv_faces do not match its mesh (as
//! evaluate_map) or whose chart_of_face is neither empty nor one id >= 0 per face, and
//! Error(io_error) for a path that does not end in .html or .htm or cannot be written.
void write_view_page(const std::filesystem::path& path, const std::vector<ViewLayout>& layouts,
                     const ViewPageOptions& options = {});

}  // namespace harmonia
