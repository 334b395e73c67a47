#pragma once
//! \file atlas_picture.h
//! \brief The picture of a texture atlas (`harmonia atlas --picture`): on the left the atlas
//! square with every UV triangle coloured by its distortion and the chart boundaries drawn dark;
//! on the right the mesh seen from its front, flat shaded, wearing a checker texture looked up
//! through the atlas, so that a seamless, undistorted atlas shows even squares all over the
//! surface. A legend of the colours below, an optional title on top. PNG, rasterized in-house
//! with a depth buffer (no display needed), its text drawn with the DejaVu Sans font embedded in
//! the library; the look of harmonia/deform_picture.h.
//!
//! \code
//!   const harmonia::TextureAtlas atlas = harmonia::texture_atlas(mesh);
//!   harmonia::AtlasPictureOptions picture;
//!   picture.title = "spot.obj - 1024 x 1024 texels";
//!   harmonia::write_atlas_picture("atlas.png", mesh, atlas, picture);
//! \endcode

#include <filesystem>
#include <string>

#include "harmonia/mesh.h"
#include "harmonia/texture_atlas.h"

namespace harmonia {

struct AtlasPictureOptions {
  int width = 1600;  //!< The whole picture in pixels, 320..16384.
  int height = 800;  //!< Pixels, 240..16384.
  //! The line on top, e.g. "spot.obj - 1024 x 1024 texels"; empty: no title line (the views
  //! grow). Shrunk to fit the width when too long.
  std::string title{};
};

//! Squares of the checker texture along the atlas' width (as many along its height as fit there at
//! the same size in texels).
inline constexpr int kAtlasCheckerSquares = 32;

//! Writes the atlas picture as PNG (the extension must be .png, any case; checked before any
//! work).
//!
//! Left, "atlas": the whole [0, 1]^2 square of the atlas (v up) with its outline, drawn in the
//! atlas' proportions (resolution x height texels). Every UV
//! triangle of a face in a chart is filled with the conformal distortion sigma1/sigma2 of the map
//! from its 3D triangle to its UV triangle (the colours of harmonia/picture.h: white at 1, towards
//! red on a log scale, saturated at 4; red for a triangle of zero area). Per triangle rather than
//! the chart's mean, so that a chart that is good on average still shows where its distortion
//! lies. Triangles clockwise or of zero area in UV are filled black with a magenta outline and
//! drawn last. The chart boundaries, the edges of the UV layout used by one triangle (where the
//! face across is in another chart, or there is none), are drawn dark. The caption gives the
//! chart count, and the coverage of atlas.metrics when it has one.
//!
//! Right, "checker through the atlas": the mesh looking along -z at its +z side (its front), y up,
//! fitted to its bounding box, flat shaded, depth-tested. At each pixel the face seen gives the UV
//! of the pixel's centre (its barycentric coordinates in the face's projected triangle, applied to
//! the face's corner UVs), and the UV a square of a checker of kAtlasCheckerSquares columns over
//! the atlas, light or dark. A face of no chart (chart_of_face -1) is grey.
//!
//! Below: a legend of the distortion colours (sigma1/sigma2 = 1, 1.5, 2, 3, >=4), the chart
//! boundary, and the triangles flipped or of zero area and the faces of no chart, counted, when
//! there are any. The same
//! arguments give the same bytes. Atomic write (temporary file beside the target, then rename;
//! removed on failure).
//!
//! Throws Error(io_error) for another extension or a failed write; Error(invalid_input), naming
//! the problem, for a size out of range, an atlas that does not fit the mesh (chart_of_face or
//! corner_uv without one row per face, a chart id that is not a chart of atlas.charts or -1, a
//! chart that does not list exactly its faces, a resolution outside 1..32768), a face naming a
//! vertex that does not exist, a position that is not finite, or a corner UV that is not finite
//! or lies outside [0, 1].
void write_atlas_picture(const std::filesystem::path& png, const Mesh& mesh,
                         const TextureAtlas& atlas, const AtlasPictureOptions& options = {});

}  // namespace harmonia
