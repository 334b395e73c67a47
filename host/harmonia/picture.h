#pragma once
//! \file picture.h
//! \brief A picture of a parameterization: the UV layout with triangles coloured by distortion and
//! flipped triangles marked, under a title and above a colour bar that says what each colour
//! means, as SVG (vector) or PNG (raster, via stb_image_write, its text drawn with the DejaVu Sans
//! font embedded in the library).

#include <filesystem>
#include <string>

#include <Eigen/Core>

#include "harmonia/mesh.h"
#include "harmonia/metrics.h"
#include "harmonia/types.h"

namespace harmonia {

enum class PictureColoring {
  conformal_distortion,  //!< sigma1/sigma2: white at 1, towards red (saturated at 4, log scale).
  area_distortion,       //!< log area ratio: blue (shrunk) - white - red (enlarged), saturated
                         //!< at a factor of 4 either way.
};

struct PictureOptions {
  PictureColoring coloring = PictureColoring::conformal_distortion;
  int size_pixels = 1024;        //!< Width and height of the picture, 16..16384 (the layout is
                                 //!< fitted between the title and the legend, aspect ratio kept).
  bool draw_edges = true;        //!< Thin triangle edges (skipped automatically above 200K faces in
                                 //!< SVG, and in PNG when triangles average under 40 pixels).
  //! The line above the layout, e.g. "face.obj - free (cotangent) - " + picture_headline(metrics).
  //! Empty: picture_headline of the layout drawn. Shrunk to fit the width when too long.
  std::string title{};
};

//! The headline numbers of a layout as picture titles show them: flipped triangles, mean conformal
//! distortion and mean area distortion (DistortionMetrics' means, two decimals), e.g.
//! "0 flipped, conformal 1.91, area 0.95".
[[nodiscard]] std::string picture_headline(const DistortionMetrics& metrics);

//! Writes the picture; the format comes from the extension (.svg or .png, any case). Both formats
//! show the same things in the same places: the title on top; the layout, flipped triangles
//! filled black with a magenta outline and drawn last (on top of any overlap), on a light grey
//! background; below it the colour bar of the colouring in use with its ticks labelled
//! (conformal: sigma1/sigma2 = 1, 1.5, 2, 3, >=4 on a log scale; area: the normalized area factor
//! <=1/4, 1/2, 1, 2, >=4) and the flipped-triangle swatch with their count. The SVG has one
//! <polygon> per triangle and its text as <text> elements; the PNG is rasterized in-house,
//! deterministically (the same arguments give the same bytes). Triangles with non-finite UVs are
//! left out. Atomic write (temporary file beside the target, then rename; removed on failure).
//! Throws Error(io_error) for an unknown extension or a failed write, Error(invalid_input) for a
//! size outside 16..16384 or bad indices (see evaluate_map).
void write_picture(const std::filesystem::path& path, const Mesh& mesh3d,
                   const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& uv_faces,
                   const PictureOptions& options = {});

}  // namespace harmonia
