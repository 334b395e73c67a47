#pragma once
//! \file picture.h
//! \brief A picture of a parameterization: the UV layout with triangles coloured by distortion and
//! flipped triangles marked, as SVG (vector) or PNG (raster, via stb_image_write).

#include <filesystem>

#include <Eigen/Core>

#include "harmonia/mesh.h"
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
                                 //!< fitted inside, aspect ratio kept).
  bool draw_edges = true;        //!< Thin triangle edges (skipped automatically above 200K faces in
                                 //!< SVG, and in PNG when triangles average under 40 pixels).
};

//! Writes the picture; the format comes from the extension (.svg or .png, any case). Flipped
//! triangles are filled black with a magenta outline and drawn last (on top of any overlap); the
//! background is light grey. The SVG has one <polygon> per triangle and a legend line with the
//! mean distortion and the flip count; the PNG (no text) is rasterized in-house, deterministically.
//! Triangles with non-finite UVs are left out. Atomic write (temporary file beside the target,
//! then rename; removed on failure). Throws Error(io_error) for an unknown extension or a failed
//! write, Error(invalid_input) for a size outside 16..16384 or bad indices (see evaluate_map).
void write_picture(const std::filesystem::path& path, const Mesh& mesh3d,
                   const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& uv_faces,
                   const PictureOptions& options = {});

}  // namespace harmonia
