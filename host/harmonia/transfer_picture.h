#pragma once
//! \file transfer_picture.h
//! \brief The pictures of a deformation transfer (`harmonia transfer --picture`; thesis 8.4,
//! figure 8.5): the correspondence as colours on both meshes, and each transferred pose beside
//! its source pose. Every marker has a colour; a source triangle takes the blend of the markers'
//! colours weighted by its marker fields (harmonia/deformation_transfer.h), so that the regions
//! near each marker show its colour and the fields' partition of unity shows as smooth
//! transitions. A target triangle takes the colour of the source triangle it was matched to
//! (TransferMethod::correspondence), so that a good correspondence shows as the same colours in
//! the same places on both animals, or, without a correspondence (TransferMethod::quaternion),
//! the blend of its own marker fields. Two views side by side, each fitted to its own mesh,
//! flat shaded, with the look and the PNG rasterization of harmonia/deform_picture.h.
//!
//! \code
//!   harmonia::DeformationTransfer transfer(lion, cat, markers);
//!   harmonia::TransferPictureOptions picture;
//!   picture.title = "lion -> cat";
//!   harmonia::write_transfer_correspondence_picture("correspondence.png", lion, cat, transfer,
//!                                                   picture);
//!   const harmonia::TransferResult result = transfer.transfer(lion_pose.vertices);
//!   harmonia::write_transfer_pose_picture("pose.png", lion, lion_pose.vertices, cat,
//!                                         result.positions, transfer, picture);
//! \endcode

#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "harmonia/deformation_transfer.h"
#include "harmonia/mesh.h"

namespace harmonia {

//! The colour of marker `marker` (0-based, the marker file's order) as RGB in [0, 1]: hues a
//! golden angle (137.5 degrees) apart, so that any number of markers spread round the colour
//! circle, each in one of six shades (saturation by marker % 2, brightness by marker % 3): hues
//! come close between markers 21, 34, 55 or 89 apart, which fall on different shades, and among
//! the first 144 markers two of the same shade are at least 14 degrees of hue apart. A marker's
//! colour does not depend on how many markers there are. Throws Error(invalid_input) for a
//! negative index.
[[nodiscard]] Eigen::Vector3d marker_color(int marker);

//! One colour per face (#F by 3, RGB in [0, 1]): the blend sum_i h_i marker_color(i) of the
//! marker fields `fields` (#V by k, as DeformationTransfer::source_fields()) at the face's
//! barycentre, clamped to [0, 1]. Where the fields are a partition of unity, a face whose
//! corners all have field i at 1 takes marker i's colour exactly.
//! Throws Error(invalid_input) when `fields` has no column, a row count other than #V, or a value
//! that is not finite, or when a face names a vertex that does not exist.
[[nodiscard]] Eigen::MatrixX3d marker_face_colors(const Mesh& mesh, const Eigen::MatrixXd& fields);

struct TransferPictureOptions {
  int width = 1600;  //!< The whole picture in pixels, 320..16384.
  int height = 800;  //!< Pixels, 240..16384.
  //! The line on top, e.g. "lion.obj -> cat.obj"; empty: no title line (the views grow). Shrunk to
  //! fit the width when too long.
  std::string title{};
};

//! Writes the correspondence picture as PNG (the extension must be .png, any case; checked before
//! any work). Left the source at rest, its faces in their marker colours (marker_face_colors of
//! the source fields); right the target at rest, each face in the colour of its matched source
//! face, or in the marker colours of its own fields when `transfer` has no matches (the quaternion
//! method). A target face without a match (DeformationTransfer::matches() -1) is grey, and the
//! legend row then explains it. Both views look along -z at the models' +z side (their front),
//! y up, each centred on and fitted to its own mesh's bounding box; "source" and "target" under
//! them. A source and target that are the same mesh with markers on the same vertices give
//! identical halves. The same arguments give the same bytes. Atomic write (temporary file beside
//! the target, then rename; removed on failure).
//! Throws Error(io_error) for another extension or a failed write; Error(invalid_input) for a size
//! out of range, a transfer whose set-up failed or whose fields or matches do not fit the meshes'
//! vertex and face counts, a face naming a vertex that does not exist, or a position that is not
//! finite.
void write_transfer_correspondence_picture(const std::filesystem::path& png,
                                           const Mesh& source_rest, const Mesh& target_rest,
                                           const DeformationTransfer& transfer,
                                           const TransferPictureOptions& options = {});

//! Writes one pose's picture as PNG, as write_transfer_correspondence_picture but with the source
//! at `source_pose` (#V_source by 3, the source rest's faces) on the left and the target at
//! `transferred` (#V_target by 3, e.g. TransferResult::positions) on the right, in the same
//! colours, "source pose" and "transferred" under them. Throws as
//! write_transfer_correspondence_picture, and Error(invalid_input) for a row count of either
//! positions other than its mesh's vertex count.
void write_transfer_pose_picture(const std::filesystem::path& png, const Mesh& source_rest,
                                 const Eigen::MatrixX3d& source_pose, const Mesh& target_rest,
                                 const Eigen::MatrixX3d& transferred,
                                 const DeformationTransfer& transfer,
                                 const TransferPictureOptions& options = {});

}  // namespace harmonia
