#pragma once
//! \file deform_picture.h
//! \brief The "before and after" picture of a surface edit (`harmonia deform --picture`): the rest
//! mesh and the deformed mesh side by side, seen from the same camera, flat shaded, with the
//! vertices' roles in the edit coloured (fixed blue, each handle its own warm tint, the rest
//! grey); "before" and "after" under the views, a legend of the roles below, and an optional
//! title on top. PNG, rasterized in-house with a depth buffer (no display needed), its text drawn
//! with the DejaVu Sans font embedded in the library.
//!
//! \code
//!   const harmonia::SurfaceEditResult result = harmonia::edit_surface(mesh, regions, transforms);
//!   std::vector<int> roles(mesh.vertex_count(), harmonia::kDeformRoleFree);
//!   for (const int v : regions.fixed) roles[v] = harmonia::kDeformRoleFixed;
//!   for (int i = 0; i < static_cast<int>(regions.handles.size()); ++i)
//!     for (const int v : regions.handles[i]) roles[v] = i;
//!   harmonia::DeformPictureOptions picture;
//!   picture.title = "elephant.obj - trunk raised";
//!   harmonia::write_deform_picture("edit.png", mesh, result.positions, roles, picture);
//! \endcode

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "harmonia/mesh.h"

namespace harmonia {

//! The role of a vertex in an edit, as write_deform_picture's `vertex_roles` gives it; a handle's
//! role is its index (0, 1, ...).
inline constexpr int kDeformRoleFree = -1;   //!< Moved by the edit as it sees fit.
inline constexpr int kDeformRoleFixed = -2;  //!< Stays where it is.

struct DeformPictureOptions {
  int width = 1600;  //!< The whole picture in pixels, 320..16384.
  int height = 800;  //!< Pixels, 240..16384.
  //! The line on top, e.g. "elephant.obj - trunk raised"; empty: no title line (the views grow).
  //! Shrunk to fit the width when too long.
  std::string title{};
};

//! Writes the picture as PNG (the extension must be .png, any case; checked before any work).
//! Left the rest mesh `rest`, right the same faces at `deformed` (#V by 3), both orthographic and
//! depth-tested with the same camera: looking along -z at the models' +z side (their front), y up,
//! centred on and fitted to the union of the two shapes' bounding boxes, so that both are drawn at
//! the same scale and in the same place of their halves. Each face is flat shaded (lit alike from
//! either side) in the colour of its corners' role when all three share one (`vertex_roles`, #V
//! entries: kDeformRoleFree grey, kDeformRoleFixed blue, handle i >= 0 the i-th of a cycle of warm
//! tints), else grey; edges are drawn where faces are large enough to show them. The two halves
//! are translates of each other: a `deformed` equal to the rest positions gives identical views.
//! Below the views "before" and "after", then a legend of the roles that occur. The same arguments
//! give the same bytes. Atomic write (temporary file beside the target, then rename; removed on
//! failure).
//! Throws Error(io_error) for another extension or a failed write, Error(invalid_input) for a size
//! out of range, a row count of `deformed` or an entry count of `vertex_roles` other than #V, a
//! role below kDeformRoleFixed, a face naming a vertex that does not exist, or a position that is
//! not finite.
void write_deform_picture(const std::filesystem::path& png, const Mesh& rest,
                          const Eigen::MatrixX3d& deformed, const std::vector<int>& vertex_roles,
                          const DeformPictureOptions& options = {});

}  // namespace harmonia
