// OBJ assets: what read_obj_asset keeps of a hand-made textured file (its vt and vn per corner, its
// material library, each face's object, groups, material and smoothing group), and the writers
// that put a new layout into such a file keeping all of it.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "harmonia/atlas_io.h"
#include "harmonia/io.h"
#include "harmonia/obj_asset.h"
#include "harmonia/texture_atlas.h"
#include "harmonia/types.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

// Two quads (four triangles) of two materials and groups; normals on the first quad only.
constexpr const char* kAsset =
    "mtllib shop.mtl\n"
    "o Crate\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
    "vt 0 0\nvt 0.5 0\nvt 0.5 1\nvt 0 1\nvt 1 0\nvt 1 1\n"
    "vn 0 0 1\n"
    "g Front Lid\n"
    "usemtl Wood Dark\n"
    "s 1\n"
    "f 1/1/1 2/2/1 3/3/1 4/4/1\n"
    "g Side\n"
    "usemtl Metal\n"
    "s off\n"
    "f 2/2 5/5 6/6 3/3\n";

std::string label_of(const ObjAsset& asset, const std::vector<int>& of_face, int face) {
  const int label = of_face[static_cast<std::size_t>(face)];
  return label < 0 ? std::string("(none)") : asset.labels[static_cast<std::size_t>(label)];
}

TEST(ObjAsset, KeepsCornersLabelsAndLibraries) {
  testing::ScratchFolder scratch("obj-asset");
  std::ofstream(scratch.file("crate.obj")) << kAsset;
  const ObjAsset asset = read_obj_asset(scratch.file("crate.obj"));
  ASSERT_EQ(asset.mesh.face_count(), 4);
  EXPECT_EQ(asset.material_libraries, std::vector<std::string>{"shop.mtl"});
  EXPECT_EQ(asset.texcoords.rows(), 6);
  EXPECT_EQ(asset.normals.rows(), 1);
  // The quads fan into (1 2 3) (1 3 4) and (2 5 6) (2 6 3), 0-based here.
  EXPECT_EQ(asset.texcoord_faces.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(asset.texcoord_faces.row(3), Eigen::RowVector3i(1, 5, 2));
  EXPECT_EQ(asset.normal_faces.row(0), Eigen::RowVector3i(0, 0, 0));
  EXPECT_EQ(asset.normal_faces.row(2), Eigen::RowVector3i(-1, -1, -1));
  for (int face = 0; face < 4; ++face) {
    const bool front = face < 2;
    EXPECT_EQ(label_of(asset, asset.object_of_face, face), "Crate");
    EXPECT_EQ(label_of(asset, asset.groups_of_face, face), front ? "Front Lid" : "Side");
    EXPECT_EQ(label_of(asset, asset.material_of_face, face), front ? "Wood Dark" : "Metal");
    EXPECT_EQ(label_of(asset, asset.smoothing_of_face, face), front ? "1" : "off");
  }
  EXPECT_TRUE(asset.carries_more_than_a_mesh());
}

TEST(ObjAsset, AnAtlasWrittenIntoItKeepsTheRest) {
  testing::ScratchFolder scratch("obj-asset");
  std::ofstream(scratch.file("crate.obj")) << kAsset;
  std::filesystem::create_directories(scratch.file("out"));
  const ObjAsset asset = read_obj_asset(scratch.file("crate.obj"));
  const TextureAtlas atlas = texture_atlas(asset.mesh);
  ASSERT_TRUE(atlas.report.ok()) << atlas.report.message;
  write_atlas_obj(scratch.file("out/crate.obj"), asset.mesh, atlas, asset);
  const std::string text = testing::file_bytes(scratch.file("out/crate.obj"));
  // The library is named from the output's folder; groups follow the chart on the g lines.
  EXPECT_NE(text.find("mtllib ../shop.mtl\n"), std::string::npos) << text;
  EXPECT_NE(text.find("usemtl Wood Dark\n"), std::string::npos);
  EXPECT_NE(text.find(" Front Lid\n"), std::string::npos);
  const ObjAsset back = read_obj_asset(scratch.file("out/crate.obj"));
  ASSERT_EQ(back.mesh.faces, asset.mesh.faces);
  EXPECT_EQ(back.normals, asset.normals);
  EXPECT_EQ(back.normal_faces, asset.normal_faces);
  for (int face = 0; face < 4; ++face) {
    EXPECT_EQ(label_of(back, back.material_of_face, face), label_of(asset, asset.material_of_face, face));
    EXPECT_EQ(label_of(back, back.smoothing_of_face, face), label_of(asset, asset.smoothing_of_face, face));
    EXPECT_EQ(label_of(back, back.object_of_face, face), "Crate");
    const std::string groups = label_of(back, back.groups_of_face, face);
    EXPECT_EQ(groups, "chart_" + std::to_string(atlas.chart_of_face[static_cast<std::size_t>(face)]) +
                          " " + label_of(asset, asset.groups_of_face, face));
    // The atlas' UVs replace the file's own.
    for (int corner = 0; corner < 3; ++corner) {
      EXPECT_EQ(back.texcoords(back.texcoord_faces(face, corner), 0), atlas.corner_uv(face, 2 * corner));
      EXPECT_EQ(back.texcoords(back.texcoord_faces(face, corner), 1), atlas.corner_uv(face, 2 * corner + 1));
    }
  }
}

TEST(ObjAsset, IndicesThatLeadNowhereAreReadAsNone) {
  // read_obj takes this file (it does not look at vt and vn indices), so an asset reading does:
  // the normal index 2 of one normal, the texture index 5 of none and the index 0 are none.
  testing::ScratchFolder scratch("obj-asset");
  std::ofstream(scratch.file("loose.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1/5/1 2/0/1 3//2\n";
  ASSERT_NO_THROW((void)read_obj(scratch.file("loose.obj")));
  const ObjAsset asset = read_obj_asset(scratch.file("loose.obj"));
  EXPECT_EQ(asset.normal_faces.row(0), Eigen::RowVector3i(0, 0, -1));
  EXPECT_EQ(asset.texcoord_faces.row(0), Eigen::RowVector3i(-1, -1, -1));
}

}  // namespace
}  // namespace harmonia
