#pragma once
// Internal: joining neighbouring charts of a segmentation (chart_segmentation.h) across folds that
// unfold without stretch.
//
// The segmentation bounds each chart's normals by a cone, so two faces of a box that meet at a
// right angle fall into two charts, although together they unfold into the plane exactly (the
// fold is a hinge). What a chart cannot flatten without stretch is curvature inside it: in the
// plane the angles around an interior vertex sum to 2 pi (the thesis' vertex condition, section
// 2.2), and only a developable surface maps to the plane keeping its lengths (chapter 1), so the
// angle defect 2 pi - (sum of the 3D angles around a vertex) of its interior vertices is what a
// chart must absorb as stretch. Two neighbouring charts are joined when
//   - the vertices their union makes interior (the inner vertices of their common border, where
//     every face around lies in one of the two) have angle defects summing, in absolute value, to
//     at most kFlatFoldDefect: the union flattens as well as its two halves;
//   - their common border is one path, so that two disks join into a disk (never an annulus),
//     and at least kLeastBorderShare of the shorter perimeter of the two: a join saves a seam
//     worth having, not a hinge at a corner that leaves an awkward shape to pack;
//   - their union is about as compact as its parts (kCompactnessKept);
//   - every face of the union has its normal within `cone` of the union's mean normal, so that the
//     union stays a height field over one plane, as the segmentation's charts are, and unfolds
//     without lapping over itself (a strip wrapped around the four sides of a box is not joined);
//     but a single face hinged to a chart by one edge joins at any angle: it unfolds about the
//     edge without stretch (a flap a scan left folded back at a hole's rim), and the flattening
//     checks every layout for lapping over anyway.
// Two charts that each flatten without stretch (developable: a box's sides, a cylinder's strips)
// but whose whole common border would bring curvature inside (the third side of a box at its
// corner) join along the longest stretch of that border that brings none, and the rest of it is
// cut: the corner stays on the union's boundary, the union still unfolds exactly (three sides of
// a box around a corner make one chart of three squares in an L, not two charts). The same border
// share, compactness (counted with the cut on the boundary twice) and cone hold.
// Pairs are taken longest common border first, rounds repeated until none joins; ties are broken
// by the charts' seed ranks, so the charts do not depend on the face order.

#include "atlas/chart_borders.h"
#include "atlas/chart_segmentation.h"
#include "atlas/face_geometry.h"
#include "harmonia/mesh.h"

namespace harmonia::detail {

//! The most curvature, in radians of summed angle defect, that a join may bring inside a chart:
//! about a hundred times what float32 coordinates leave in the angle sums of a flat fold (~1e-6),
//! and a stretch far below the atlas' default limit (a cone of defect d flattened stretches its
//! neighbourhood by about d / 2 pi).
inline constexpr double kFlatFoldDefect = 1e-4;

//! Joins charts of `segmentation` (of `mesh`, whose faces `geometry` describes) as above. Charts
//! keep their order, a joined chart the place of the one of the two whose seed ranks first. The
//! cuts are made in `geometry`: across each, `across` is -1 on both sides, so that every chart
//! mesh made from it is cut open there.
void merge_across_flat_folds(const Mesh& mesh, FaceGeometry& geometry, double cone,
                             Segmentation& segmentation);

}  // namespace harmonia::detail
