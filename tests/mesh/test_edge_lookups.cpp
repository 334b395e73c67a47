// The flat edge and half-edge tables behind topology analysis, checked against straightforward
// ordered-map constructions on clean and deliberately damaged meshes.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

#include "harmonia/io.h"
#include "mesh/edge_table.h"
#include "mesh/face_checks.h"
#include "mesh/halfedge_map.h"
#include "support/test_support.h"
#include "support/topology_meshes.h"

namespace harmonia {
namespace {

using testing::grid_disk;

//! A 4 x 3 grid with everything that breaks the simple cases appended: a third face on an
//! interior edge, a reversed copy of face 0, faces (a, b, a) and (c, c, c), a face (a, a, b) with
//! the same vertex multiset as (a, b, a) and one (a, b, b) with a different one, all three on the
//! boundary edge (a, b) = (2, 3).
Mesh damaged_grid() {
  Mesh mesh = grid_disk(4, 3);
  const std::vector<std::array<int, 3>> extra = {
      {6, 7, 19}, {mesh.faces(0, 0), mesh.faces(0, 2), mesh.faces(0, 1)},
      {2, 3, 2},  {11, 11, 11},
      {2, 2, 3},  {2, 3, 3}};
  const auto original = mesh.faces.rows();
  mesh.faces.conservativeResize(original + static_cast<Eigen::Index>(extra.size()), 3);
  for (std::size_t k = 0; k < extra.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      mesh.faces(original + static_cast<Eigen::Index>(k), c) =
          extra[k][static_cast<std::size_t>(c)];
    }
  }
  return mesh;
}

struct ReferenceEdge {
  std::vector<int> faces;                  // distinct, increasing
  std::vector<std::pair<int, bool>> uses;  // (corner index, runs second -> first), increasing
};

std::map<std::pair<int, int>, ReferenceEdge> reference_edges(const Mesh& mesh) {
  std::map<std::pair<int, int>, ReferenceEdge> edges;
  for (int face = 0; face < mesh.face_count(); ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      const int a = mesh.faces(face, corner);
      const int b = mesh.faces(face, (corner + 1) % 3);
      if (a == b) continue;
      ReferenceEdge& edge = edges[{std::min(a, b), std::max(a, b)}];
      if (edge.faces.empty() || edge.faces.back() != face) edge.faces.push_back(face);
      edge.uses.emplace_back(face * 3 + corner, a > b);
    }
  }
  return edges;
}

void expect_table_matches_reference(const Mesh& mesh) {
  const detail::EdgeTable table(mesh);
  const auto reference = reference_edges(mesh);
  ASSERT_EQ(table.size(), static_cast<int>(reference.size()));
  const std::vector<int> corner_edge = table.corner_edges();
  ASSERT_EQ(corner_edge.size(), static_cast<std::size_t>(mesh.face_count()) * 3);
  int e = 0;
  for (const auto& [key, expected] : reference) {
    EXPECT_EQ(table.first(e), key.first);
    EXPECT_EQ(table.second(e), key.second);
    EXPECT_EQ(table.face_count(e), static_cast<int>(expected.faces.size())) << "edge " << e;
    std::vector<std::pair<int, bool>> uses;
    for (const detail::EdgeUse& use : table.uses(e)) {
      uses.emplace_back(use.corner_index(), use.backward());
      EXPECT_EQ(use.face() * 3 + use.corner(), use.corner_index());
      EXPECT_EQ(corner_edge[static_cast<std::size_t>(use.corner_index())], e);
      // The next corner holds the half-edge's end vertex.
      const int end = use.backward() ? key.first : key.second;
      EXPECT_EQ(mesh.faces(use.face(), use.next_corner_index() % 3), end);
    }
    EXPECT_EQ(uses, expected.uses) << "edge " << e;
    EXPECT_EQ(table.find(key.first, key.second), e);
    EXPECT_EQ(table.find(key.second, key.first), e);
    if (expected.faces.size() == 2) {
      EXPECT_EQ(table.other_face(e, expected.faces[0]), expected.faces[1]);
      EXPECT_EQ(table.other_face(e, expected.faces[1]), expected.faces[0]);
    }
    ++e;
  }
  // Self-loops have no edge, and pairs that are not edges are not found.
  for (int face = 0; face < mesh.face_count(); ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      if (mesh.faces(face, corner) == mesh.faces(face, (corner + 1) % 3)) {
        EXPECT_EQ(
            corner_edge[static_cast<std::size_t>(face) * 3 + static_cast<std::size_t>(corner)], -1);
      }
    }
  }
  for (int a = 0; a < std::min(mesh.vertex_count(), 40); ++a) {
    for (int b = 0; b < std::min(mesh.vertex_count(), 40); ++b) {
      const bool is_edge = a != b && reference.count({std::min(a, b), std::max(a, b)}) > 0;
      EXPECT_EQ(table.find(a, b) >= 0, is_edge) << a << " " << b;
    }
  }
}

TEST(EdgeTable, MatchesAnOrderedMapOnACleanGrid) {
  expect_table_matches_reference(grid_disk(5, 4));
}

TEST(EdgeTable, MatchesAnOrderedMapOnADamagedGrid) {
  const Mesh mesh = damaged_grid();
  expect_table_matches_reference(mesh);
  // Spot checks of the damage: three faces on edge (6, 7); the boundary edge (2, 3) is used once
  // by its grid face and twice by each of (2, 3, 2), (2, 2, 3) and (2, 3, 3): four faces.
  const detail::EdgeTable table(mesh);
  EXPECT_EQ(table.face_count(table.find(6, 7)), 3);
  const int shared = table.find(2, 3);
  ASSERT_GE(shared, 0);
  EXPECT_EQ(table.uses(shared).size(), 7u);
  EXPECT_EQ(table.face_count(shared), 4);
}

TEST(EdgeTable, MatchesAnOrderedMapOnACorpusMesh) {
  const auto meshes = testing::corpus_meshes("disk");
  if (meshes.empty()) HARMONIA_SKIP_WITHOUT_CORPUS("corpus not found");
  expect_table_matches_reference(read_mesh(meshes.front()));
}

TEST(HalfedgeMap, FaceOfAndLeavingMatchAFullSort) {
  for (const Mesh& mesh : {grid_disk(4, 3), damaged_grid()}) {
    std::vector<std::tuple<int, int, int, int>> all;  // (from, to, face, corner)
    for (int face = 0; face < mesh.face_count(); ++face) {
      for (int corner = 0; corner < 3; ++corner) {
        all.emplace_back(mesh.faces(face, corner), mesh.faces(face, (corner + 1) % 3), face,
                         corner);
      }
    }
    std::sort(all.begin(), all.end());
    const detail::HalfedgeMap map(mesh);
    for (int v = 0; v < mesh.vertex_count(); ++v) {
      std::vector<std::tuple<int, int, int, int>> leaving;
      for (const detail::Halfedge& h : map.leaving(v)) {
        leaving.emplace_back(h.from, h.to, h.face, h.corner);
      }
      std::vector<std::tuple<int, int, int, int>> expected;
      for (const auto& entry : all) {
        if (std::get<0>(entry) == v) expected.push_back(entry);
      }
      EXPECT_EQ(leaving, expected) << "vertex " << v;
      for (int w = 0; w < mesh.vertex_count(); ++w) {
        int smallest = -1;
        for (const auto& entry : expected) {
          if (std::get<1>(entry) == w) {
            smallest = std::get<2>(entry);
            break;
          }
        }
        EXPECT_EQ(map.face_of(v, w), smallest) << v << "->" << w;
      }
    }
  }
}

TEST(FaceChecks, DuplicatesAreTheLaterFacesOfEachVertexMultiset) {
  const Mesh mesh = damaged_grid();
  std::map<std::array<int, 3>, int> first_with;
  std::vector<int> expected;
  for (int face = 0; face < mesh.face_count(); ++face) {
    std::array<int, 3> key{mesh.faces(face, 0), mesh.faces(face, 1), mesh.faces(face, 2)};
    std::sort(key.begin(), key.end());
    if (!first_with.emplace(key, face).second) expected.push_back(face);
  }
  // The reversed copy of face 0 and (2, 2, 3) after (2, 3, 2); not (2, 3, 3).
  const int grid_faces = grid_disk(4, 3).face_count();
  EXPECT_EQ(expected, std::vector<int>({grid_faces + 1, grid_faces + 4}));
  EXPECT_EQ(detail::duplicate_face_list(mesh), expected);
}

}  // namespace
}  // namespace harmonia
