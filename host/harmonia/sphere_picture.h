#pragma once
//! \file sphere_picture.h
//! \brief A picture of a spherical map (`harmonia sphere --picture`): the sphere seen from two
//! opposite sides, side by side, every triangle coloured by its area distortion and shaded, the
//! triangles turned over on the sphere marked, the date line and the poles drawn; under a title and
//! above a colour bar that says what each colour means. PNG, rasterized in-house with a depth
//! buffer (no display needed), its text drawn with the DejaVu Sans font embedded in the library.
//!
//! \code
//!   const harmonia::SphericalMapResult map = harmonia::spherical_map(mesh);
//!   harmonia::SpherePictureOptions picture;
//!   picture.north_pole = map.north_pole;
//!   picture.south_pole = map.south_pole;
//!   picture.date_line = map.date_line;
//!   harmonia::write_sphere_picture("sphere.png", mesh, map.positions, picture);
//! \endcode

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "harmonia/mesh.h"
#include "harmonia/spherical_metrics.h"

namespace harmonia {

struct SpherePictureOptions {
  //! The line on top, e.g. "spot.obj - sphere (mean-value) - " + sphere_picture_headline(metrics).
  //! Empty: sphere_picture_headline of the map drawn. Shrunk to fit the width when too long.
  std::string title{};
  int width = 1600;  //!< Pixels, 320..16384.
  int height = 900;  //!< Pixels, 240..16384.
  //! The poles (vertex indices; -1: none). They fix the views: the first looks at the sphere from
  //! 30 degrees beside the north pole towards the date line, the second from the opposite side,
  //! both with the north pole up. Without poles the views look along +z and -z.
  int north_pole = -1;
  int south_pole = -1;
  //! The date line's vertices from pole to pole (may be empty), drawn as great-circle arcs.
  std::vector<int> date_line{};
};

//! The headline numbers of a spherical map as picture titles show them: flipped triangles (and
//! degenerate ones, when there are any) and the mean area distortion (two decimals), e.g.
//! "0 flipped, area distortion 0.24".
[[nodiscard]] std::string sphere_picture_headline(const SphericalMetrics& metrics);

//! Writes the picture as PNG (the extension must be .png, any case; checked before any work).
//! Each half shows one side of the sphere (orthographic, depth-tested, flat Lambert shading): the
//! chord triangles of `sphere_points` (#V by 3, scaled to unit length, as spherical_metrics does)
//! filled with the area colour of their log area ratio (blue shrunk, white kept, red enlarged,
//! saturated at a factor of 4), triangles turned over or degenerate on the sphere filled black with
//! a magenta outline, pulled slightly forward so that a fold does not hide them, and ringed in
//! magenta in the view that faces them (so that even a sub-pixel one shows); edges where triangles
//! are large enough to show them; the date line as a yellow line with a dark edge, and the poles as
//! dots labelled N and S, where they are not hidden. Below: the colour bar with labelled ticks and
//! a legend with the count of marked triangles. Faces with non-finite points are left out. The
//! same arguments give the same bytes. Atomic write (temporary file beside the target, then
//! rename; removed on failure).
//! Throws Error(io_error) for another extension or a failed write, Error(invalid_input) for a size
//! out of range, a row count other than #V, or a pole or date-line index that is not a vertex.
void write_sphere_picture(const std::filesystem::path& png, const Mesh& mesh,
                          const Eigen::MatrixX3d& sphere_points,
                          const SpherePictureOptions& options = {});

}  // namespace harmonia
