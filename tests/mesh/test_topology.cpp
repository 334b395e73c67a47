// Topology analysis on meshes of known topology: counts, genus, boundary loops, manifoldness,
// orientation, dirt, and the messages that say what is wrong.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "harmonia/io.h"
#include "harmonia/procedural.h"
#include "harmonia/topology.h"
#include "support/test_support.h"
#include "support/topology_meshes.h"

namespace harmonia {
namespace {

using testing::annulus;
using testing::grid_disk;
using testing::make_mesh;
using testing::moebius_strip;
using testing::octahedron;
using testing::tetrahedron;
using testing::torus;
using testing::voxel_slab;
using testing::without_faces;

//! Twice the signed area of a loop's projection on the xy plane (shoelace formula).
double signed_area_xy(const Mesh& mesh, const std::vector<int>& loop) {
  double twice_area = 0.0;
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const int a = loop[k];
    const int b = loop[(k + 1) % loop.size()];
    twice_area +=
        mesh.vertices(a, 0) * mesh.vertices(b, 1) - mesh.vertices(b, 0) * mesh.vertices(a, 1);
  }
  return twice_area;
}

TEST(Topology, TetrahedronIsAClosedSphere) {
  const TopologyReport report = analyze_topology(tetrahedron());
  EXPECT_EQ(report.vertices, 4);
  EXPECT_EQ(report.edges, 6);
  EXPECT_EQ(report.faces, 4);
  EXPECT_EQ(report.components, 1);
  EXPECT_EQ(report.boundary_loops, 0);
  EXPECT_EQ(report.boundary_edges, 0);
  EXPECT_EQ(report.euler_characteristic, 2);
  EXPECT_EQ(report.genus, 0);
  EXPECT_TRUE(report.orientable);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_TRUE(report.is_closed_manifold());
  EXPECT_FALSE(report.is_disk());
  EXPECT_EQ(report.disk_problem(),
            "closed mesh (no boundary loop): cut it open with `harmonia cut`");
  std::string message;
  EXPECT_EQ(check_disk(tetrahedron(), &message), Status::not_a_disk);
  EXPECT_EQ(message, report.disk_problem());
}

TEST(Topology, OctahedronCounts) {
  const TopologyReport report = analyze_topology(octahedron());
  EXPECT_EQ(report.vertices, 6);
  EXPECT_EQ(report.edges, 12);
  EXPECT_EQ(report.faces, 8);
  EXPECT_EQ(report.euler_characteristic, 2);
  EXPECT_EQ(report.genus, 0);
  EXPECT_TRUE(report.non_manifold_vertices.empty());
  EXPECT_TRUE(report.is_closed_manifold());
}

TEST(Topology, PlanarDiskIsADiskWithACounterClockwiseBoundary) {
  const Mesh disk = planar_disk(3);  // 1 + 6 + 12 + 18 vertices, 54 faces
  const TopologyReport report = analyze_topology(disk);
  EXPECT_EQ(report.vertices, 37);
  EXPECT_EQ(report.faces, 54);
  EXPECT_EQ(report.edges, 37 + 54 - 1);  // chi = 1
  EXPECT_EQ(report.boundary_edges, 18);
  EXPECT_EQ(report.boundary_loops, 1);
  EXPECT_EQ(report.euler_characteristic, 1);
  EXPECT_TRUE(report.is_disk());
  EXPECT_EQ(report.disk_problem(), "");
  std::string message = "stale";
  EXPECT_EQ(check_disk(disk, &message), Status::ok);
  EXPECT_EQ(message, "");

  const auto loops = boundary_loops(disk);
  ASSERT_EQ(loops.size(), 1u);
  ASSERT_EQ(loops[0].size(), 18u);
  EXPECT_EQ(loops[0][0], 19);  // the smallest index of the outer ring (1 + 6 + 12 = 19)
  EXPECT_GT(signed_area_xy(disk, loops[0]), 0.0);  // counter-clockwise: mesh on the left
  for (std::size_t k = 0; k < loops[0].size(); ++k) EXPECT_GE(loops[0][k], 19);
}

TEST(Topology, AnnulusHasTwoLoopsOrientedWithTheMeshOnTheLeft) {
  const Mesh ring = annulus(12, 3);  // 48 vertices, 72 faces
  const TopologyReport report = analyze_topology(ring);
  EXPECT_EQ(report.boundary_loops, 2);
  EXPECT_EQ(report.boundary_edges, 24);
  EXPECT_EQ(report.euler_characteristic, 0);
  EXPECT_EQ(report.genus, 0);
  EXPECT_EQ(report.components, 1);
  EXPECT_EQ(report.disk_problem(),
            "2 boundary loops (genus 0): join the holes with `harmonia cut`");
  std::string message;
  EXPECT_EQ(check_disk(ring, &message), Status::not_a_disk);

  const auto loops = boundary_loops(ring);
  ASSERT_EQ(loops.size(), 2u);
  // Equal lengths: the loop with the smaller start vertex (the inner circle, 0..11) comes first.
  EXPECT_EQ(loops[0][0], 0);
  EXPECT_EQ(loops[1][0], 36);
  EXPECT_LT(signed_area_xy(ring, loops[0]), 0.0);  // inner circle runs clockwise
  EXPECT_GT(signed_area_xy(ring, loops[1]), 0.0);  // outer circle counter-clockwise
}

TEST(Topology, LongestLoopComesFirst) {
  // A 6 x 6 grid with one interior triangle removed: outer loop of 24 edges, hole of 3.
  const Mesh holed = without_faces(grid_disk(6, 6), {2 * (3 * 6 + 3)});
  const auto loops = boundary_loops(holed);
  ASSERT_EQ(loops.size(), 2u);
  EXPECT_EQ(loops[0].size(), 24u);
  EXPECT_EQ(loops[1].size(), 3u);
  EXPECT_EQ(loops[0][0], 0);
  EXPECT_LT(signed_area_xy(holed, loops[1]), 0.0);
}

TEST(Topology, TorusHasGenusOne) {
  const TopologyReport report = analyze_topology(torus(8, 6));
  EXPECT_EQ(report.vertices, 48);
  EXPECT_EQ(report.faces, 96);
  EXPECT_EQ(report.edges, 144);
  EXPECT_EQ(report.euler_characteristic, 0);
  EXPECT_EQ(report.genus, 1);
  EXPECT_EQ(report.boundary_loops, 0);
  EXPECT_TRUE(report.is_closed_manifold());
  EXPECT_EQ(report.disk_problem(),
            "closed mesh of genus 1 (no boundary loop): cut it open with `harmonia cut`");
}

TEST(Topology, VoxelSlabsHaveOneGenusPerHole) {
  const TopologyReport one = analyze_topology(voxel_slab(3, 3, {{1, 1}}));
  EXPECT_EQ(one.genus, 1);
  EXPECT_EQ(one.euler_characteristic, 0);
  const TopologyReport two = analyze_topology(voxel_slab(5, 3, {{1, 1}, {3, 1}}));
  EXPECT_EQ(two.genus, 2);
  EXPECT_EQ(two.euler_characteristic, -2);
  EXPECT_TRUE(two.non_manifold_vertices.empty());
  EXPECT_TRUE(two.consistently_oriented);
  EXPECT_TRUE(two.is_closed_manifold());
}

TEST(Topology, TorusWithAHoleNamesGenusAndLoops) {
  const TopologyReport report = analyze_topology(without_faces(torus(8, 6), {0}));
  EXPECT_EQ(report.boundary_loops, 1);
  EXPECT_EQ(report.genus, 1);
  EXPECT_EQ(report.euler_characteristic, -1);
  EXPECT_EQ(report.disk_problem(),
            "genus 1 with 1 boundary loop: cut it to a disk with `harmonia cut`");
}

TEST(Topology, TwoDisjointTrianglesAreTwoComponents) {
  const Mesh mesh = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}},
                              {{0, 1, 2}, {3, 4, 5}});
  const TopologyReport report = analyze_topology(mesh);
  EXPECT_EQ(report.components, 2);
  EXPECT_EQ(report.boundary_loops, 2);
  EXPECT_EQ(report.genus, 0);
  EXPECT_EQ(report.disk_problem(), "2 connected components: split it into parts and flatten each");
  std::string message;
  EXPECT_EQ(check_disk(mesh, &message), Status::not_a_disk);
}

TEST(Topology, BowTieHasANonManifoldVertex) {
  const Mesh mesh =
      make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 0, 0}, {2, 1, 0}}, {{0, 1, 2}, {1, 3, 4}});
  const TopologyReport report = analyze_topology(mesh);
  EXPECT_EQ(report.non_manifold_vertices, std::vector<int>({1}));
  EXPECT_TRUE(report.non_manifold_edges.empty());
  EXPECT_EQ(report.boundary_loops, 0);  // the boundary passes twice through v1
  EXPECT_EQ(report.components, 1);
  std::string message;
  EXPECT_EQ(check_disk(mesh, &message), Status::non_manifold);
  EXPECT_NE(message.find("non-manifold vertex v1"), std::string::npos) << message;
}

TEST(Topology, ThreeFacesOnOneEdge) {
  const Mesh mesh = make_mesh({{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}},
                              {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  const TopologyReport report = analyze_topology(mesh);
  ASSERT_EQ(report.non_manifold_edges.size(), 1u);
  EXPECT_EQ(report.non_manifold_edges[0], (EdgeKey{0, 1}));
  EXPECT_EQ(report.non_manifold_edge_faces, std::vector<int>({3}));
  EXPECT_EQ(report.non_manifold_vertices, std::vector<int>({0, 1}));
  EXPECT_EQ(report.genus, 0);
  EXPECT_EQ(report.disk_problem(),
            "non-manifold edge (v0, v1) used by 3 faces: repair the mesh first");
  std::string message;
  EXPECT_EQ(check_disk(mesh, &message), Status::non_manifold);
}

TEST(Topology, OneFlippedFaceIsInconsistentButOrientable) {
  Mesh mesh = grid_disk(3, 3);
  const int flipped = 8;  // cell (1, 1), first triangle
  std::swap(mesh.faces(flipped, 1), mesh.faces(flipped, 2));
  const TopologyReport report = analyze_topology(mesh);
  EXPECT_TRUE(report.orientable);
  EXPECT_FALSE(report.consistently_oriented);
  // The flipped face and its three neighbours: 7 (left of it in the cell... ) etc.
  ASSERT_EQ(report.inconsistent_edges_faces.size(), 4u);
  EXPECT_NE(std::find(report.inconsistent_edges_faces.begin(),
                      report.inconsistent_edges_faces.end(), flipped),
            report.inconsistent_edges_faces.end());
  std::string message;
  EXPECT_EQ(check_disk(mesh, &message), Status::non_manifold);
  EXPECT_NE(message.find("inconsistent orientation at faces f"), std::string::npos) << message;
  EXPECT_NE(message.find("repair mode"), std::string::npos) << message;
}

TEST(Topology, MoebiusStripIsNotOrientable) {
  const TopologyReport report = analyze_topology(moebius_strip(10));
  EXPECT_FALSE(report.orientable);
  EXPECT_FALSE(report.consistently_oriented);
  EXPECT_EQ(report.boundary_loops, 1);  // the single edge of a Moebius band
  EXPECT_EQ(report.euler_characteristic, 0);
  EXPECT_EQ(report.genus, 0);  // undefined for non-orientable surfaces: left at 0
  std::string message;
  EXPECT_EQ(check_disk(moebius_strip(10), &message), Status::non_manifold);
  EXPECT_NE(message.find("not orientable"), std::string::npos) << message;
}

// Whether a face is degenerate does not depend on the model's units: the same square and sliver
// at 1e-103 (whose cross products' squares underflow) and with legs of 1e300 (whose squares
// overflow) give the same list as at 1.
TEST(Topology, DegenerateFacesAreTheSameAtEveryScale) {
  const Mesh unit = make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}},
                              {{0, 1, 2}, {0, 2, 3}, {0, 1, 4}});
  for (const double scale : {1e-103, 1.0, 1e300}) {
    Mesh mesh = unit;
    mesh.vertices *= scale;
    EXPECT_EQ(analyze_topology(mesh).degenerate_faces, std::vector<int>({2})) << scale;
  }
}

TEST(Topology, DegenerateDuplicateAndUnreferencedAreListed) {
  // Square of two faces, plus: a repeated-index face (2), a collinear face (3), a duplicate of
  // face 0 written in another rotation (4), and an unreferenced vertex 5.
  const Mesh mesh = make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {9, 9, 9}},
                              {{0, 1, 2}, {0, 2, 3}, {0, 0, 1}, {0, 1, 4}, {1, 2, 0}});
  const TopologyReport report = analyze_topology(mesh);
  EXPECT_EQ(report.degenerate_faces, std::vector<int>({2, 3}));
  EXPECT_EQ(report.duplicate_faces, std::vector<int>({4}));
  EXPECT_EQ(report.unreferenced_vertices, std::vector<int>({5}));
  std::string message;
  EXPECT_EQ(check_disk(mesh, &message), Status::invalid_input);
  EXPECT_EQ(message,
            "2 degenerate faces (repeated vertex or zero area), first f2: run cleanup in repair "
            "mode to drop them");

  // Only the unreferenced vertex left: chi counts referenced vertices only.
  const Mesh lonely = make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {7, 7, 7}}, {{0, 1, 2}});
  const TopologyReport lonely_report = analyze_topology(lonely);
  EXPECT_EQ(lonely_report.euler_characteristic, 1);
  EXPECT_EQ(lonely_report.unreferenced_vertices, std::vector<int>({3}));
  EXPECT_EQ(check_disk(lonely, &message), Status::invalid_input);
  EXPECT_EQ(message, "1 unreferenced vertex, first v3: run cleanup in repair mode to drop them");
}

TEST(Topology, IndicesAndCoordinatesAreChecked) {
  std::string message;
  Mesh mesh = grid_disk(2, 2);
  EXPECT_EQ(check_indices_and_coordinates(mesh, &message), Status::ok);
  mesh.faces(5, 1) = 9;
  EXPECT_EQ(check_indices_and_coordinates(mesh, &message), Status::invalid_input);
  EXPECT_EQ(message, "face f5 uses vertex index 9, out of range for 9 vertices");
  EXPECT_EQ(check_disk(mesh, &message), Status::invalid_input);
  mesh.faces(5, 1) = -1;
  EXPECT_EQ(check_indices_and_coordinates(mesh, &message), Status::invalid_input);
  EXPECT_NE(message.find("index -1"), std::string::npos);

  Mesh nan_mesh = grid_disk(2, 2);
  nan_mesh.vertices(4, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(check_indices_and_coordinates(nan_mesh, &message), Status::invalid_input);
  EXPECT_EQ(message, "vertex v4 has a non-finite coordinate (NaN or infinity)");

  EXPECT_EQ(check_disk(Mesh{}, &message), Status::invalid_input);
  EXPECT_EQ(message, "empty mesh (no faces): nothing to flatten");
}

TEST(Topology, UniqueEdgesAreSortedAndComplete) {
  const Eigen::MatrixX2i edges = unique_edges(tetrahedron());
  ASSERT_EQ(edges.rows(), 6);
  const int expected[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  for (int e = 0; e < 6; ++e) {
    EXPECT_EQ(edges(e, 0), expected[e][0]);
    EXPECT_EQ(edges(e, 1), expected[e][1]);
  }
  const Eigen::MatrixX2i torus_edges = unique_edges(torus(8, 6));
  EXPECT_EQ(torus_edges.rows(), 144);
  for (Eigen::Index e = 1; e < torus_edges.rows(); ++e) {
    EXPECT_TRUE(
        torus_edges(e - 1, 0) < torus_edges(e, 0) ||
        (torus_edges(e - 1, 0) == torus_edges(e, 0) && torus_edges(e - 1, 1) < torus_edges(e, 1)));
    EXPECT_LT(torus_edges(e, 0), torus_edges(e, 1));
  }
}

TEST(Topology, ReportIsDeterministic) {
  Mesh mesh = voxel_slab(5, 3, {{1, 1}, {3, 1}});
  std::swap(mesh.faces(3, 1), mesh.faces(3, 2));
  const TopologyReport a = analyze_topology(mesh);
  const TopologyReport b = analyze_topology(mesh);
  EXPECT_EQ(a.inconsistent_edges_faces, b.inconsistent_edges_faces);
  EXPECT_EQ(a.disk_problem(), b.disk_problem());
  EXPECT_EQ(boundary_loops(annulus(9, 2)), boundary_loops(annulus(9, 2)));
}

TEST(Topology, CorpusMeshesMatchTheManifest) {
  const std::filesystem::path data = harmonia::testing::shared_data_dir();
  std::ifstream manifest(data / "MANIFEST.tsv");
  if (!manifest) HARMONIA_SKIP_WITHOUT_CORPUS("corpus not found at " << data << " (set HARMONIA_SHARED_DATA)");
  std::string line;
  std::getline(manifest, line);  // header: name path V F boundary_loops genus ...
  int checked = 0;
  while (std::getline(manifest, line)) {
    std::istringstream fields(line);
    std::string name, path;
    int vertices = 0, faces = 0, loops = 0, genus = 0;
    fields >> name >> path >> vertices >> faces >> loops >> genus;
    SCOPED_TRACE(name);
    const Mesh mesh = read_obj(data / path);
    const TopologyReport report = analyze_topology(mesh);
    EXPECT_EQ(report.vertices, vertices);
    EXPECT_EQ(report.faces, faces);
    EXPECT_EQ(report.boundary_loops, loops);
    EXPECT_EQ(report.genus, genus);
    EXPECT_EQ(report.components, 1);
    EXPECT_TRUE(report.non_manifold_edges.empty());
    EXPECT_TRUE(report.non_manifold_vertices.empty());
    EXPECT_TRUE(report.consistently_oriented);
    EXPECT_TRUE(report.degenerate_faces.empty());
    EXPECT_TRUE(report.duplicate_faces.empty());
    EXPECT_TRUE(report.unreferenced_vertices.empty());
    EXPECT_EQ(report.is_disk(), loops == 1) << report.disk_problem();
    ++checked;
  }
  EXPECT_GE(checked, 30);
}

}  // namespace
}  // namespace harmonia
