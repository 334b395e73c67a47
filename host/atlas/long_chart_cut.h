#pragma once
// Internal: the charts of a texture atlas that are too long for its square, cut across their
// length.
//
// The atlas' density is capped by
// its longest chart (no chart wider than the atlas), so a chart longer than the side of a square
// that the charts' whole area would fill at kCompactFill may keep every chart smaller than it
// needs to be: a rod's strips, a snake, a cable. Such a chart is split between the faces at the
// two ends of its long axis, and each piece keeps its part of the layout (no new solve) when both
// are disks with valid layouts within the limit; the pieces are looked at again. Charts that
// cannot be split so stay whole. Nothing when no chart was split; the caller packs both sets and
// keeps the pieces only where their atlas is denser by enough to pay for the charts they add
// (cut_worth_its_charts): a long chart of sprawling shape may pack no better in pieces, and every
// chart added is a seam more in the texture.

#include <cstddef>
#include <optional>
#include <vector>

#include "atlas/chart_flattening.h"
#include "atlas/face_geometry.h"
#include "harmonia/mesh.h"

namespace harmonia::detail {

[[nodiscard]] std::optional<std::vector<FinishedChart>> long_charts_split(const Mesh& surface,
                                                                          const FaceGeometry& geometry,
                                                                          double max_stretch, int width,
                                                                          int height, int padding,
                                                                          const std::vector<FinishedChart>& whole);

//! The least gain in coverage, relative, that each relative increase of the chart count must buy
//! for an atlas of cut charts to be kept: doubling the charts must fill at least a quarter more
//! of the atlas (about 12 % more texels per unit length). A few percent of coverage is not worth
//! a third more seams; a long rod that left most of the atlas empty is.
inline constexpr double kCoverageGainPerChartGain = 0.25;

//! Whether the atlas of `cut_charts` charts at coverage `cut_coverage` is worth keeping over the
//! one of `whole_charts` at `whole_coverage` (kCoverageGainPerChartGain).
[[nodiscard]] bool cut_worth_its_charts(std::size_t whole_charts, double whole_coverage, std::size_t cut_charts,
                                        double cut_coverage);

}  // namespace harmonia::detail
