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
// keeps the denser atlas (a long chart of sprawling shape may pack no better in pieces).

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

}  // namespace harmonia::detail
