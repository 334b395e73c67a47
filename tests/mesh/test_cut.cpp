// Cutting into a disk: closed genus 0 along a shortest path (reproducing the corpus' cut meshes),
// several holes joined by shortest paths, handles cut by tree-cotree; the results are disks whose
// copies sit on their originals.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "harmonia/cut.h"
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
using testing::octahedron;
using testing::tetrahedron;
using testing::torus;
using testing::voxel_slab;
using testing::without_faces;

//! Checks everything a cut promises: a disk, the input's vertices first and in order, copies on
//! their originals, faces that map back to the input's faces, and the vertex count Euler's formula
//! demands (V' = V + seams + 1 - chi, since the disk has chi 1 and each seam edge becomes two).
void expect_valid_cut(const Mesh& mesh, const CutResult& cut) {
  ASSERT_EQ(cut.status, Status::ok) << cut.message;
  std::string message;
  EXPECT_EQ(check_disk(cut.disk, &message), Status::ok) << message;
  const TopologyReport before = analyze_topology(mesh);
  const TopologyReport after = analyze_topology(cut.disk);
  EXPECT_EQ(cut.disk.vertex_count(),
            mesh.vertex_count() + cut.seam_edges + 1 - before.euler_characteristic);
  EXPECT_EQ(after.boundary_edges, before.boundary_edges + 2 * cut.seam_edges);
  ASSERT_EQ(cut.original_vertex.size(), cut.disk.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v) EXPECT_EQ(cut.original_vertex(v), v);
  for (int v = 0; v < cut.disk.vertex_count(); ++v) {
    EXPECT_EQ(cut.disk.vertices.row(v), mesh.vertices.row(cut.original_vertex(v)));
  }
  ASSERT_EQ(cut.disk.face_count(), mesh.face_count());
  for (int f = 0; f < mesh.face_count(); ++f) {
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(cut.original_vertex(cut.disk.faces(f, k)), mesh.faces(f, k));
  }
}

TEST(Cut, DiskIsReturnedUnchanged) {
  const Mesh disk = planar_disk(4);
  const CutResult cut = cut_to_disk(disk);
  ASSERT_EQ(cut.status, Status::ok) << cut.message;
  EXPECT_EQ(cut.seam_edges, 0);
  EXPECT_EQ(cut.disk.vertices, disk.vertices);
  EXPECT_EQ(cut.disk.faces, disk.faces);
  EXPECT_EQ(cut.original_vertex,
            Eigen::VectorXi::LinSpaced(disk.vertex_count(), 0, disk.vertex_count() - 1));
}

TEST(Cut, TetrahedronAndOctahedronOpenAlongAPath) {
  for (const Mesh& mesh : {tetrahedron(), octahedron()}) {
    const CutResult cut = cut_to_disk(mesh);
    expect_valid_cut(mesh, cut);
    EXPECT_GE(cut.seam_edges, 1);
  }
  // Octahedron: opposite vertices are two edges apart; the double sweep finds such a pair, so the
  // cut has two edges and one inner vertex, copied once.
  const CutResult cut = cut_to_disk(octahedron());
  EXPECT_EQ(cut.seam_edges, 2);
  EXPECT_EQ(cut.disk.vertex_count(), 7);
  // Tetrahedron: all end points are neighbours; one cut edge would open nothing, so the path goes
  // through a common neighbour: two edges, one copy.
  const CutResult tetra = cut_to_disk(tetrahedron());
  EXPECT_EQ(tetra.seam_edges, 2);
  EXPECT_EQ(tetra.disk.vertex_count(), 5);
}

TEST(Cut, NeighbouringEndPointsGoThroughTheNearestCommonNeighbour) {
  // Octahedron v0 = (1,0,0) and v2 = (0,1,0) share an edge; faces on it have third vertices v4
  // and v5, equally far: the smaller index, v4, is the inner vertex.
  CutOptions options;
  options.from_vertex = 0;
  options.to_vertex = 2;
  const CutResult cut = cut_to_disk(octahedron(), options);
  expect_valid_cut(octahedron(), cut);
  EXPECT_EQ(cut.seam_edges, 2);
  ASSERT_EQ(cut.disk.vertex_count(), 7);
  EXPECT_EQ(cut.original_vertex(6), 4);
}

TEST(Cut, GivenEndPointsCutTheShortestPathBetweenThem) {
  // The closed surface of a 4 x 3 x 1 block of voxels: the grid path between two corners of the
  // top face runs along its border. From (0,0,1) to (4,0,1): 4 straight edges.
  const Mesh block = voxel_slab(4, 3, {});
  auto index_of = [&block](double x, double y, double z) {
    for (int v = 0; v < block.vertex_count(); ++v) {
      if (block.vertices.row(v) == Eigen::RowVector3d(x, y, z)) return v;
    }
    return -1;
  };
  CutOptions options;
  options.from_vertex = index_of(0, 0, 1);
  options.to_vertex = index_of(4, 0, 1);
  const CutResult cut = cut_to_disk(block, options);
  expect_valid_cut(block, cut);
  EXPECT_EQ(cut.seam_edges, 4);
  EXPECT_EQ(cut.disk.vertex_count(), block.vertex_count() + 3);  // three inner path vertices
  // The copies, in path order, sit at x = 1, 2, 3 on the edge y = 0, z = 1.
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(cut.disk.vertices.row(block.vertex_count() + k), Eigen::RowVector3d(k + 1, 0, 1));
  }
  // The end points stay single: each appears once in the disk.
  EXPECT_EQ((cut.original_vertex.array() == *options.from_vertex).count(), 1);
  EXPECT_EQ((cut.original_vertex.array() == *options.to_vertex).count(), 1);
}

TEST(Cut, InvalidEndPointsAreRejectedWithAMessage) {
  const Mesh mesh = octahedron();
  CutOptions options;
  options.from_vertex = 0;
  options.to_vertex = 6;
  CutResult cut = cut_to_disk(mesh, options);
  EXPECT_EQ(cut.status, Status::invalid_input);
  EXPECT_EQ(cut.message, "to vertex 6 is out of range (the mesh has 6 vertices, 0-based)");

  options.to_vertex = 0;
  cut = cut_to_disk(mesh, options);
  EXPECT_EQ(cut.status, Status::invalid_input);
  EXPECT_EQ(cut.message,
            "from and to are the same vertex (0): a cut needs two distinct end points");

  options.to_vertex.reset();
  cut = cut_to_disk(mesh, options);
  EXPECT_EQ(cut.status, Status::invalid_input);
  EXPECT_EQ(cut.message, "give both end points of the cut (from and to) or neither");

  options.from_vertex = 0;
  options.to_vertex = 3;
  cut = cut_to_disk(torus(6, 5), options);
  EXPECT_EQ(cut.status, Status::invalid_input);
  EXPECT_EQ(cut.message,
            "cut end points (from/to) apply to closed genus-0 meshes only; this mesh has 0 "
            "boundary loop(s) and genus 1");
}

TEST(Cut, AnnulusIsJoinedIntoADisk) {
  const Mesh ring = annulus(16, 3);
  const CutResult cut = cut_to_disk(ring);
  expect_valid_cut(ring, cut);
  // One path from the outer circle to the inner one: 3 radial steps at least.
  EXPECT_GE(cut.seam_edges, 3);
  EXPECT_EQ(cut.disk.vertex_count(), ring.vertex_count() + cut.seam_edges + 1);
}

TEST(Cut, SeveralHolesAreJoinedByATree) {
  // A 10 x 10 grid with three separate one-triangle holes: four loops.
  const Mesh holed =
      without_faces(grid_disk(10, 10), {2 * (2 * 10 + 2), 2 * (7 * 10 + 3), 2 * (4 * 10 + 7)});
  ASSERT_EQ(analyze_topology(holed).boundary_loops, 4);
  const CutResult cut = cut_to_disk(holed);
  expect_valid_cut(holed, cut);
}

TEST(Cut, TorusAndGenusTwoAreCutByTreeCotree) {
  const Mesh ring_torus = torus(10, 7);
  const CutResult torus_cut = cut_to_disk(ring_torus);
  expect_valid_cut(ring_torus, torus_cut);
  // Two loops around the handle, each at least as long as the shortest non-contractible loop (7).
  EXPECT_GE(torus_cut.seam_edges, 14);

  const Mesh pretzel = voxel_slab(5, 3, {{1, 1}, {3, 1}});
  ASSERT_EQ(analyze_topology(pretzel).genus, 2);
  expect_valid_cut(pretzel, cut_to_disk(pretzel));
}

TEST(Cut, HandlesWithBoundaryAreCutToo) {
  const Mesh torus_with_hole = without_faces(torus(9, 6), {0, 1});
  expect_valid_cut(torus_with_hole, cut_to_disk(torus_with_hole));
  const Mesh pretzel = voxel_slab(5, 3, {{1, 1}, {3, 1}});
  const Mesh pretzel_with_holes = without_faces(pretzel, {0, 1, 20, 21});
  ASSERT_EQ(analyze_topology(pretzel_with_holes).genus, 2);
  ASSERT_EQ(analyze_topology(pretzel_with_holes).boundary_loops, 2);
  expect_valid_cut(pretzel_with_holes, cut_to_disk(pretzel_with_holes));
}

TEST(Cut, CuttingIsDeterministic) {
  const Mesh pretzel = voxel_slab(5, 3, {{1, 1}, {3, 1}});
  const CutResult a = cut_to_disk(pretzel);
  const CutResult b = cut_to_disk(pretzel);
  EXPECT_EQ(a.disk.faces, b.disk.faces);
  EXPECT_EQ(a.original_vertex, b.original_vertex);
}

// The seams do not depend on the model's units: a closed block (shortest path) and a genus-two slab
// (tree-cotree) give the same disk at 2^-1000 and 2^1000 units as at unit size. Path lengths of
// the model at 2^1000 (about 1e301) used to overflow to infinity.
TEST(Cut, SeamsAreTheSameAtEveryScale) {
  for (const Mesh& mesh : {voxel_slab(4, 3, {}), voxel_slab(5, 3, {{1, 1}, {3, 1}})}) {
    const CutResult at_unit_size = cut_to_disk(mesh);
    ASSERT_EQ(at_unit_size.status, Status::ok) << at_unit_size.message;
    for (const int exponent : {-1000, 1000}) {
      Mesh scaled = mesh;
      scaled.vertices *= std::ldexp(1.0, exponent);
      const CutResult cut = cut_to_disk(scaled);
      ASSERT_EQ(cut.status, Status::ok) << "2^" << exponent << ": " << cut.message;
      EXPECT_EQ(cut.seam_edges, at_unit_size.seam_edges) << "2^" << exponent;
      EXPECT_EQ(cut.disk.faces, at_unit_size.disk.faces) << "2^" << exponent;
      EXPECT_EQ(cut.original_vertex, at_unit_size.original_vertex) << "2^" << exponent;
    }
  }
}

TEST(Cut, BadInputIsRefusedWithTheReason) {
  const Mesh two = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}},
                             {{0, 1, 2}, {3, 4, 5}});
  CutResult cut = cut_to_disk(two);
  EXPECT_EQ(cut.status, Status::not_a_disk);
  EXPECT_EQ(cut.message,
            "cannot cut: 2 connected components: split it into parts and flatten each");

  const Mesh fin = make_mesh({{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}},
                             {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  cut = cut_to_disk(fin);
  EXPECT_EQ(cut.status, Status::non_manifold);
  EXPECT_NE(cut.message.find("(v0, v1) used by 3 faces"), std::string::npos) << cut.message;

  Mesh out_of_range = tetrahedron();
  out_of_range.faces(2, 0) = 4;
  cut = cut_to_disk(out_of_range);
  EXPECT_EQ(cut.status, Status::invalid_input);
  EXPECT_NE(cut.message.find("f2"), std::string::npos) << cut.message;
}

TEST(Cut, TexturedFromCutUsesTheDiskFacesAsUvIndices) {
  const Mesh mesh = octahedron();
  const CutResult cut = cut_to_disk(mesh);
  ASSERT_EQ(cut.status, Status::ok);
  Eigen::MatrixX2d uv(cut.disk.vertex_count(), 2);
  for (int v = 0; v < uv.rows(); ++v) uv.row(v) = Eigen::RowVector2d(v, -v);
  const TexturedMesh textured = textured_from_cut(mesh, cut, uv);
  EXPECT_EQ(textured.mesh.vertices, mesh.vertices);
  EXPECT_EQ(textured.mesh.faces, mesh.faces);
  EXPECT_EQ(textured.uv_faces, cut.disk.faces);
  EXPECT_EQ(textured.uv, uv);
  EXPECT_THROW((void)textured_from_cut(mesh, cut, Eigen::MatrixX2d(3, 2)), Error);
}

// ---------------------------------------------------------------------------------------------
// The corpus: cutting closed/X.obj reproduces disk/X-cut.obj exactly.

struct CorpusCut {
  std::string name;
  int from;
  int to;
  int path_edges;
};

TEST(Cut, ReproducesTheCorpusCutMeshes) {
  const std::filesystem::path data = harmonia::testing::shared_data_dir();
  const std::vector<CorpusCut> cuts = {
      {"cow", 2759, 1954, 56}, {"homer", 3910, 4736, 63}, {"elephant", 5818, 2425, 60}};
  for (const CorpusCut& expected : cuts) {
    const auto closed_path = data / "closed" / (expected.name + ".obj");
    const auto cut_path = data / "disk" / (expected.name + "-cut.obj");
    if (!std::filesystem::exists(closed_path) || !std::filesystem::exists(cut_path)) {
      HARMONIA_SKIP_WITHOUT_CORPUS("corpus not found at " << data << " (set HARMONIA_SHARED_DATA)");
    }
    SCOPED_TRACE(expected.name);
    const Mesh closed = read_obj(closed_path);
    const Mesh reference = read_obj(cut_path);

    CutOptions options;
    options.from_vertex = expected.from;
    options.to_vertex = expected.to;
    const CutResult given = cut_to_disk(closed, options);
    ASSERT_EQ(given.status, Status::ok) << given.message;
    EXPECT_EQ(given.seam_edges, expected.path_edges);
    EXPECT_EQ(given.disk.vertex_count(), reference.vertex_count());
    EXPECT_EQ(given.disk.faces, reference.faces);
    EXPECT_EQ(given.disk.vertices, reference.vertices);

    // The double sweep picks the same end points as the corpus tool did.
    const CutResult swept = cut_to_disk(closed);
    ASSERT_EQ(swept.status, Status::ok) << swept.message;
    EXPECT_EQ(swept.disk.faces, reference.faces);
  }
}

TEST(Cut, EveryClosedCorpusMeshCutsToADisk) {
  std::vector<std::filesystem::path> meshes = harmonia::testing::corpus_meshes("closed");
  for (const auto& path : harmonia::testing::corpus_meshes("deform")) meshes.push_back(path);
  if (meshes.empty()) HARMONIA_SKIP_WITHOUT_CORPUS("corpus not found (set HARMONIA_SHARED_DATA)");
  for (const auto& path : meshes) {
    SCOPED_TRACE(path.filename().string());
    const Mesh mesh = read_obj(path);
    const CutResult cut = cut_to_disk(mesh);
    expect_valid_cut(mesh, cut);
    EXPECT_GE(cut.seam_edges, 2);
  }
}

}  // namespace
}  // namespace harmonia
