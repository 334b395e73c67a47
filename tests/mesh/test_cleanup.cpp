// Cleanup: strict mode refuses and names the problem without changing anything; repair mode fixes
// duplicate vertices, degenerate/duplicate faces, unreferenced vertices and orientation, and its
// maps let per-vertex and per-face attributes follow the changes.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "harmonia/cleanup.h"
#include "harmonia/topology.h"
#include "support/topology_meshes.h"

namespace harmonia {
namespace {

using testing::grid_disk;
using testing::make_mesh;
using testing::moebius_strip;
using testing::octahedron;
using testing::tetrahedron;

CleanupOptions repair_options(double tolerance = 0.0) {
  CleanupOptions options;
  options.mode = CleanupMode::repair;
  options.merge_tolerance = tolerance;
  return options;
}

double signed_volume(const Mesh& mesh) {
  double volume = 0.0;
  for (int f = 0; f < mesh.face_count(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(f, 1));
    const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(f, 2));
    volume += a.dot(b.cross(c)) / 6.0;
  }
  return volume;
}

//! The same grid with every face using its own three vertices (a triangle soup).
Mesh soup_of(const Mesh& mesh) {
  Mesh soup;
  soup.vertices.resize(mesh.face_count() * 3, 3);
  soup.faces.resize(mesh.face_count(), 3);
  for (int f = 0; f < mesh.face_count(); ++f) {
    for (int k = 0; k < 3; ++k) {
      soup.vertices.row(3 * f + k) = mesh.vertices.row(mesh.faces(f, k));
      soup.faces(f, k) = 3 * f + k;
    }
  }
  return soup;
}

//! True if face f of a and of b list the same corners in the same cyclic order.
bool same_cyclic_order(const Mesh& a, const Mesh& b, int f) {
  for (int shift = 0; shift < 3; ++shift) {
    if (a.faces(f, 0) == b.faces(f, shift) && a.faces(f, 1) == b.faces(f, (shift + 1) % 3) &&
        a.faces(f, 2) == b.faces(f, (shift + 2) % 3)) {
      return true;
    }
  }
  return false;
}

void expect_identity_maps(const CleanupResult& result, const Mesh& mesh) {
  ASSERT_EQ(result.vertex_map.size(), mesh.vertex_count());
  ASSERT_EQ(result.original_vertex.size(), mesh.vertex_count());
  ASSERT_EQ(result.original_face.size(), mesh.face_count());
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    EXPECT_EQ(result.vertex_map(v), v);
    EXPECT_EQ(result.original_vertex(v), v);
  }
  for (int f = 0; f < mesh.face_count(); ++f) EXPECT_EQ(result.original_face(f), f);
}

TEST(Cleanup, StrictAcceptsACleanMeshUnchanged) {
  const Mesh mesh = grid_disk(3, 2);
  const CleanupResult result = cleanup(mesh);
  EXPECT_EQ(result.status, Status::ok);
  EXPECT_EQ(result.message, "");
  EXPECT_FALSE(result.changed());
  EXPECT_TRUE(result.changes.empty());
  EXPECT_EQ(result.mesh.vertices, mesh.vertices);
  EXPECT_EQ(result.mesh.faces, mesh.faces);
  expect_identity_maps(result, mesh);
}

TEST(Cleanup, RepairOfACleanMeshChangesNothing) {
  const Mesh mesh = octahedron();
  const CleanupResult result = cleanup(mesh, repair_options(1e-6));
  EXPECT_EQ(result.status, Status::ok);
  EXPECT_FALSE(result.changed());
  EXPECT_TRUE(result.changes.empty());
  EXPECT_EQ(result.mesh.faces, mesh.faces);
  expect_identity_maps(result, mesh);
}

TEST(Cleanup, StrictNamesTheFirstProblemAndChangesNothing) {
  struct Case {
    Mesh mesh;
    Status status;
    std::string message;
  };
  Mesh flipped = grid_disk(2, 2);
  std::swap(flipped.faces(3, 1), flipped.faces(3, 2));
  const std::vector<Case> cases = {
      {make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, {{0, 1, 2}, {0, 1, 1}}), Status::invalid_input,
       "1 degenerate face (repeated vertex or zero area), first f1: run cleanup in repair mode to "
       "drop them"},
      {make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, {{0, 1, 2}, {2, 0, 1}}), Status::invalid_input,
       "1 duplicate face, first f1: run cleanup in repair mode to drop them"},
      {make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {3, 3, 3}}, {{0, 1, 2}}), Status::invalid_input,
       "1 unreferenced vertex, first v3: run cleanup in repair mode to drop them"},
      {make_mesh({{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}},
                 {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}),
       Status::non_manifold,
       "non-manifold edge (v0, v1) used by 3 faces: repair the mesh first (cleanup cannot decide "
       "which faces to keep)"},
      {make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 0, 0}, {2, 1, 0}}, {{0, 1, 2}, {1, 3, 4}}),
       Status::non_manifold,
       "non-manifold vertex v1 (separate fans of faces meet there): repair the mesh first"},
      {moebius_strip(8), Status::non_manifold,
       "not orientable (like a Moebius strip): no orientation of the faces is consistent"},
      {flipped, Status::non_manifold,
       "inconsistent orientation (first at f0, 4 faces involved): run cleanup in repair mode to "
       "orient the faces consistently"},
  };
  for (const Case& c : cases) {
    const CleanupResult result = cleanup(c.mesh);
    EXPECT_EQ(result.status, c.status) << c.message;
    EXPECT_EQ(result.message, c.message);
    EXPECT_FALSE(result.changed());
    EXPECT_EQ(result.mesh.faces, c.mesh.faces);
    expect_identity_maps(result, c.mesh);
  }
}

TEST(Cleanup, StrictAcceptsCoincidentVerticesOfASeam) {
  // Two squares side by side whose shared edge is split (as along the seam of a cut mesh):
  // legal, a disk, nothing to refuse.
  const Mesh seam = make_mesh(
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}},
      {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}});
  const CleanupResult result = cleanup(seam);
  EXPECT_EQ(result.status, Status::ok);
  EXPECT_FALSE(result.changed());
}

TEST(Cleanup, IndexErrorsAreRefusedInBothModes) {
  Mesh mesh = grid_disk(1, 1);
  mesh.faces(1, 2) = 7;
  for (const CleanupMode mode : {CleanupMode::strict, CleanupMode::repair}) {
    CleanupOptions options;
    options.mode = mode;
    const CleanupResult result = cleanup(mesh, options);
    EXPECT_EQ(result.status, Status::invalid_input);
    EXPECT_EQ(result.message, "face f1 uses vertex index 7, out of range for 4 vertices");
  }
  CleanupOptions negative = repair_options(-1.0);
  EXPECT_EQ(cleanup(grid_disk(1, 1), negative).status, Status::invalid_input);
}

TEST(Cleanup, RepairWeldsATriangleSoup) {
  const Mesh grid = grid_disk(3, 2);  // 12 vertices, 12 faces
  const Mesh soup = soup_of(grid);    // 36 vertices
  ASSERT_EQ(analyze_topology(soup).components, 12);

  const CleanupResult result = cleanup(soup, repair_options());
  EXPECT_EQ(result.status, Status::ok) << result.message;
  EXPECT_EQ(result.merged_vertices, 36 - 12);
  EXPECT_EQ(result.removed_degenerate_faces, 0);
  EXPECT_EQ(result.removed_duplicate_faces, 0);
  EXPECT_EQ(result.removed_unreferenced_vertices, 0);
  EXPECT_EQ(result.flipped_faces, 0);
  ASSERT_EQ(result.changes.size(), 1u);
  EXPECT_EQ(result.changes[0], "merged 24 duplicate vertices (same position as an earlier vertex)");
  EXPECT_EQ(result.mesh.vertex_count(), 12);
  EXPECT_EQ(result.mesh.face_count(), 12);

  // Every input vertex maps to an output vertex at the same position; outputs come from the
  // first of their group.
  for (int v = 0; v < soup.vertex_count(); ++v) {
    const int out = result.vertex_map(v);
    ASSERT_GE(out, 0);
    EXPECT_EQ(result.mesh.vertices.row(out), soup.vertices.row(v));
    EXPECT_LE(result.original_vertex(out), v);
  }
  for (int f = 0; f < result.mesh.face_count(); ++f) {
    EXPECT_EQ(result.original_face(f), f);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(result.mesh.faces(f, k), result.vertex_map(soup.faces(f, k)));
    }
  }
  const CleanupResult again = cleanup(result.mesh);
  EXPECT_EQ(again.status, Status::ok) << again.message;
  EXPECT_TRUE(analyze_topology(result.mesh).is_disk());
}

TEST(Cleanup, ToleranceMergesNearbyVerticesOnlyWhenAsked) {
  Mesh soup = soup_of(grid_disk(2, 2));
  // Nudge every vertex by a different amount below 1e-9, so that no two positions are equal; the
  // bounding-box diagonal is about sqrt(8).
  for (int v = 0; v < soup.vertex_count(); ++v) {
    soup.vertices(v, 0) += 1e-9 * (v + 1) / 24.0;
    soup.vertices(v, 1) -= 1e-9 * (v % 5) / 5.0;
  }
  const CleanupResult exact = cleanup(soup, repair_options(0.0));
  EXPECT_EQ(exact.merged_vertices, 0);
  EXPECT_EQ(analyze_topology(exact.mesh).components, 8);

  const CleanupResult welded = cleanup(soup, repair_options(1e-6));
  EXPECT_EQ(welded.status, Status::ok) << welded.message;
  EXPECT_EQ(welded.mesh.vertex_count(), 9);
  EXPECT_EQ(welded.merged_vertices, 24 - 9);
  EXPECT_TRUE(analyze_topology(welded.mesh).is_disk());
  // The survivor of each group is its smallest input index.
  for (int v = 0; v < soup.vertex_count(); ++v) {
    EXPECT_LE(welded.original_vertex(welded.vertex_map(v)), v);
    EXPECT_LT((soup.vertices.row(v) - welded.mesh.vertices.row(welded.vertex_map(v))).norm(), 1e-8);
  }
}

// Merging is relative to the model's size: the same soup at 1e-100, 1 and 1e200 units welds the
// same vertices (the tolerance is a share of the bounding box's diagonal, which at 1e200 does not
// fit in a double), and a tolerance of 1e-20 of the diagonal merges only equal positions instead of
// overflowing its grid.
TEST(Cleanup, MergingIsTheSameAtEveryScale) {
  Mesh soup = soup_of(grid_disk(2, 2));
  for (int v = 0; v < soup.vertex_count(); ++v) {
    soup.vertices(v, 0) += 1e-9 * (v + 1) / 24.0;
    soup.vertices(v, 1) -= 1e-9 * (v % 5) / 5.0;
  }
  for (const double scale : {1e-100, 1.0, 1e200}) {
    Mesh scaled = soup;
    scaled.vertices *= scale;
    const CleanupResult welded = cleanup(scaled, repair_options(1e-6));
    EXPECT_EQ(welded.status, Status::ok) << scale << ": " << welded.message;
    EXPECT_EQ(welded.merged_vertices, 24 - 9) << scale;
    EXPECT_TRUE(analyze_topology(welded.mesh).is_disk()) << scale;
    const CleanupResult exact = cleanup(scaled, repair_options(1e-20));
    EXPECT_EQ(exact.status, Status::ok) << scale << ": " << exact.message;
    EXPECT_EQ(exact.merged_vertices, 0) << scale;
    EXPECT_EQ(exact.mesh.vertex_count(), 24) << scale;
  }
  // Exact duplicates are merged under the tiny tolerance too.
  const CleanupResult equal = cleanup(soup_of(grid_disk(2, 2)), repair_options(1e-20));
  EXPECT_EQ(equal.merged_vertices, 24 - 9);
}

// A mesh whose every coordinate is subnormal (below 2^-1022) merges like the same mesh at unit
// scale. Found by fuzzing (tests/fuzz/regressions/ply_binary/subnormal_coordinates_merge_nan): the
// power of two that brings such coordinates to unit size does not fit in a double, the scale came
// out infinite, every zero coordinate became NaN, and the merge grid converted NaN to an integer.
TEST(Cleanup, MergingOfSubnormalCoordinatesIsTheSameAsAtUnitScale) {
  const Mesh soup = soup_of(grid_disk(2, 2));  // Coordinates on a unit grid: exact at any scale.
  Mesh subnormal = soup;
  subnormal.vertices *= std::ldexp(1.0, -1060);
  ASSERT_LT(subnormal.vertices.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
  for (const double tolerance : {0.0, 1e-6}) {
    const CleanupResult at_unit_scale = cleanup(soup, repair_options(tolerance));
    const CleanupResult welded = cleanup(subnormal, repair_options(tolerance));
    EXPECT_EQ(welded.status, Status::ok) << tolerance << ": " << welded.message;
    EXPECT_EQ(welded.merged_vertices, at_unit_scale.merged_vertices) << tolerance;
    EXPECT_EQ(welded.mesh.faces, at_unit_scale.mesh.faces) << tolerance;
    EXPECT_TRUE(welded.mesh.vertices.allFinite()) << tolerance;
    EXPECT_TRUE(analyze_topology(welded.mesh).is_disk()) << tolerance;
  }
}

// A valid quad at coordinates around 1e200 is kept whole by repair (it used to be emptied: the
// bounding-box diagonal overflowed and the merge grid's cells became NaN).
TEST(Cleanup, AQuadAtHugeCoordinatesIsRepairedUnchanged) {
  Mesh quad;
  quad.vertices.resize(4, 3);
  quad.vertices << 1e200, 1e200, 0.0, 3e200, 1e200, 0.0, 3e200, 2e200, 0.0, 1e200, 2e200, 1e199;
  quad.faces.resize(2, 3);
  quad.faces << 0, 1, 2, 0, 2, 3;
  for (const CleanupMode mode : {CleanupMode::strict, CleanupMode::repair}) {
    CleanupOptions options = repair_options();
    options.mode = mode;
    const CleanupResult result = cleanup(quad, options);
    EXPECT_EQ(result.status, Status::ok) << result.message;
    EXPECT_EQ(result.mesh.vertex_count(), 4);
    EXPECT_EQ(result.mesh.face_count(), 2);
    EXPECT_TRUE(result.changes.empty());
    EXPECT_EQ(result.mesh.vertices, quad.vertices);
  }
}

TEST(Cleanup, RepairDropsDegenerateDuplicateFacesAndUnreferencedVertices) {
  // Square (faces 0, 1) plus: repeated index (2), collinear (3), duplicate of 0 (4), the same face
  // reversed (5); vertices 4 (only in the collinear face) and 5 (in no face) end up unused.
  const Mesh mesh = make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {9, 9, 9}},
                              {{0, 1, 2}, {0, 2, 3}, {0, 0, 1}, {0, 1, 4}, {1, 2, 0}, {2, 1, 0}});
  const CleanupResult result = cleanup(mesh, repair_options());
  EXPECT_EQ(result.status, Status::ok) << result.message;
  EXPECT_EQ(result.removed_degenerate_faces, 2);
  EXPECT_EQ(result.removed_duplicate_faces, 2);
  EXPECT_EQ(result.removed_unreferenced_vertices, 2);
  EXPECT_EQ(result.merged_vertices, 0);
  EXPECT_EQ(result.flipped_faces, 0);
  EXPECT_EQ(result.mesh.vertex_count(), 4);
  EXPECT_EQ(result.mesh.face_count(), 2);
  EXPECT_EQ(result.original_face, Eigen::Vector2i(0, 1));
  EXPECT_EQ(result.original_vertex, Eigen::Vector4i(0, 1, 2, 3));
  Eigen::VectorXi expected_map(6);
  expected_map << 0, 1, 2, 3, -1, -1;
  EXPECT_EQ(result.vertex_map, expected_map);
  const std::vector<std::string> expected_changes = {
      "removed 2 degenerate faces (first: input f2)", "removed 2 duplicate faces (first: input f4)",
      "removed 2 unreferenced vertices (first: input v4)"};
  EXPECT_EQ(result.changes, expected_changes);
  EXPECT_EQ(cleanup(result.mesh).status, Status::ok);
}

TEST(Cleanup, RepairOrientsAgainstTheFirstFace) {
  Mesh mesh = grid_disk(3, 3);
  for (const int f : {4, 9, 10}) std::swap(mesh.faces(f, 1), mesh.faces(f, 2));
  const CleanupResult result = cleanup(mesh, repair_options());
  EXPECT_EQ(result.status, Status::ok) << result.message;
  EXPECT_EQ(result.flipped_faces, 3);
  EXPECT_EQ(result.mesh.faces, grid_disk(3, 3).faces);
  EXPECT_EQ(result.changes.back(),
            "flipped 3 faces to orient each component consistently (closed components outward)");
  EXPECT_TRUE(analyze_topology(result.mesh).consistently_oriented);
}

TEST(Cleanup, RepairTurnsClosedSurfacesOutward) {
  // All faces inward: consistent, but the volume is negative; all four are flipped.
  Mesh inward = tetrahedron();
  for (int f = 0; f < 4; ++f) std::swap(inward.faces(f, 1), inward.faces(f, 2));
  ASSERT_LT(signed_volume(inward), 0.0);
  const CleanupResult all = cleanup(inward, repair_options());
  EXPECT_EQ(all.flipped_faces, 4);
  EXPECT_GT(signed_volume(all.mesh), 0.0);

  // Face 0 flipped: the others are first turned to agree with it, then everything is turned
  // outward, so in the end only face 0 has changed.
  Mesh first_wrong = octahedron();
  std::swap(first_wrong.faces(0, 1), first_wrong.faces(0, 2));
  const CleanupResult one = cleanup(first_wrong, repair_options());
  EXPECT_EQ(one.status, Status::ok);
  EXPECT_EQ(one.flipped_faces, 1);
  EXPECT_GT(signed_volume(one.mesh), 0.0);
  const Mesh original = octahedron();
  for (int f = 0; f < 8; ++f) EXPECT_TRUE(same_cyclic_order(one.mesh, original, f)) << "face " << f;
}

TEST(Cleanup, MoebiusStripCannotBeRepaired) {
  const CleanupResult result = cleanup(moebius_strip(12), repair_options());
  EXPECT_EQ(result.status, Status::non_manifold);
  EXPECT_NE(result.message.find("not orientable"), std::string::npos) << result.message;
  EXPECT_EQ(result.mesh.face_count(), 24);
  EXPECT_EQ(result.flipped_faces, 0);
}

TEST(Cleanup, RepairReportsWhatItCannotFix) {
  const Mesh fin = make_mesh({{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {5, 5, 5}},
                             {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  const CleanupResult result = cleanup(fin, repair_options());
  EXPECT_EQ(result.status, Status::non_manifold);
  EXPECT_NE(result.message.find("non-manifold edge (v0, v1) used by 3 faces"), std::string::npos)
      << result.message;
  EXPECT_EQ(result.removed_unreferenced_vertices, 1);  // vertex 5 was still dropped
}

// For a consumer that cuts there (the texture atlas), repair keeps what it cannot fix and says so.
TEST(Cleanup, RepairKeepsNonManifoldElementsWhenAsked) {
  const Mesh fin = make_mesh({{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {5, 5, 5}},
                             {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  CleanupOptions options = repair_options();
  options.keep_non_manifold = true;
  const CleanupResult result = cleanup(fin, options);
  EXPECT_EQ(result.status, Status::ok) << result.message;
  EXPECT_EQ(result.mesh.face_count(), 3);
  EXPECT_EQ(result.removed_unreferenced_vertices, 1);
  ASSERT_FALSE(result.changes.empty());
  EXPECT_NE(result.changes.back().find("kept 1 non-manifold edge"), std::string::npos) << result.changes.back();
  const CleanupResult moebius = cleanup(moebius_strip(12), options);
  EXPECT_EQ(moebius.status, Status::ok) << moebius.message;
  ASSERT_FALSE(moebius.changes.empty());
  EXPECT_NE(moebius.changes.back().find("not orientable"), std::string::npos) << moebius.changes.back();
}

}  // namespace
}  // namespace harmonia
