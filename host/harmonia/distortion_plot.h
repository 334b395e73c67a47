#pragma once
//! \file distortion_plot.h
//! \brief Several layouts of one mesh compared triangle by triangle (thesis figure 6.4): the
//! per-triangle angle distortion and log area ratio of each layout, sorted, as curves over the
//! fraction of triangles, drawn as SVG or PNG (`harmonia compare --picture`).
//!
//! \code
//!   std::vector<harmonia::LayoutDistortion> layouts;
//!   for (each layout uv, uv_faces of mesh, with its name) {
//!     const harmonia::DistortionMetrics metrics = harmonia::evaluate_map(mesh, uv, uv_faces);
//!     layouts.push_back({name, harmonia::face_angle_distortion(mesh, uv, uv_faces),
//!                        metrics.face_area_log_ratio});
//!   }
//!   harmonia::write_distortion_plot("compare.png", layouts, {"face.obj"});
//! \endcode

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "harmonia/mesh.h"

namespace harmonia {

//! #F per-triangle angle distortion of a layout: the mean over the triangle's three corners of
//! |UV angle - 3D angle| / 3D angle (0: the triangle keeps its shape; UV angles unsigned, so a
//! mirrored triangle scores 0 and is counted by the flip counts instead). NaN where it is not
//! defined, exactly where DistortionMetrics leaves a face out of its angle figures: a degenerate 3D
//! triangle (area at most 1e-14 of the total, or non-finite) or non-finite UVs. uv_faces (#F by 3)
//! indexes uv, as for evaluate_map. Throws Error(invalid_input) naming the first bad index or a
//! face count that differs from the mesh's.
[[nodiscard]] Eigen::VectorXd face_angle_distortion(const Mesh& mesh3d, const Eigen::MatrixX2d& uv,
                                                    const Eigen::MatrixX3i& uv_faces);

//! One layout's curves: per-triangle values in any order (the plot sorts them). NaN entries are
//! left out; infinite ones (a zero-area UV triangle's log area ratio is -inf) are drawn at the
//! panel's edge.
struct LayoutDistortion {
  std::string label;                      //!< The legend's name for the layout, not empty.
  Eigen::VectorXd face_angle_distortion;  //!< As face_angle_distortion.
  Eigen::VectorXd face_area_log_ratio;    //!< As DistortionMetrics::face_area_log_ratio.
};

struct DistortionPlotOptions {
  std::string title{};      //!< The line on top, e.g. the mesh's name; shrunk to fit if long.
  int width_pixels = 1600;  //!< 320..16384.
  int height_pixels = 800;  //!< 240..16384.
};

//! Most layouts one plot tells apart: one colour each.
inline constexpr int kMostPlottedLayouts = 10;

//! Writes the plot; the format comes from the extension (.svg or .png, any case). Two panels side
//! by side: left the angle distortion (y from 0 up to the largest value over all layouts, rounded
//! up to a tick), right the log area ratio (y symmetric about 0, the larger |value| rounded up to
//! a tick); in each, one curve per layout of its sorted values against the fraction of triangles
//! (x: 0..1; the k-th smallest of n values spans [k/n, (k+1)/n], sampled at two points per pixel
//! column where there are more values than that), with labelled axes, tick values
//! and grid lines, and a legend below naming each layout in its colour. The PNG's text uses the
//! embedded DejaVu Sans; the same arguments give the same bytes. Atomic write, as write_picture.
//! Throws Error(io_error) for an unknown extension or a failed write, Error(invalid_input) for no
//! layouts, more than kMostPlottedLayouts, an empty label, or a size out of range.
void write_distortion_plot(const std::filesystem::path& path,
                           const std::vector<LayoutDistortion>& layouts,
                           const DistortionPlotOptions& options = {});

}  // namespace harmonia
