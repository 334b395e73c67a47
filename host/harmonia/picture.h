#pragma once
//! \file picture.h
//! \brief A picture of a parameterization: the UV layout with triangles coloured by distortion and
//! flipped triangles marked, as SVG (vector) or PNG (raster, via stb_image_write).

#include <filesystem>

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia {

enum class PictureColoring {
  conformal_distortion,  //!< sigma1/sigma2: white at 1, towards red as it grows.
  area_distortion,       //!< log area ratio: blue (shrunk) - white - red (enlarged).
};

struct PictureOptions {
  PictureColoring coloring = PictureColoring::conformal_distortion;
  int size_pixels = 1024;        //!< Width and height of the picture (the layout is fitted inside).
  bool draw_edges = true;        //!< Thin triangle edges (skipped automatically above 200K faces in SVG).
};

//! Writes the picture; the format comes from the extension (.svg or .png). Flipped triangles are
//! filled black with a magenta outline. Atomic write (temp file + rename); throws Error(io_error).
void write_picture(const std::filesystem::path& path, const Mesh& mesh3d, const Eigen::MatrixX2d& uv,
                   const Eigen::MatrixX3i& uv_faces, const PictureOptions& options = {});

}  // namespace harmonia
