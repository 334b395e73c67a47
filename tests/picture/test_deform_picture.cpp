// The before-and-after picture of a surface edit: the PNG decodes to the requested size; its two
// views are pixel for pixel the same when nothing moved and differ when something did; the fixed
// vertices and the handles show in their colours on both sides; the same arguments give the same
// bytes; bad arguments are refused and a failed write leaves nothing behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "harmonia/deform_picture.h"
#include "harmonia/procedural.h"
#include "harmonia/types.h"
#include "picture/color_map.h"
#include "support/decoded_png.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

namespace fs = std::filesystem;
using detail::Rgb;

class DeformPictureTest : public ::testing::Test {
 protected:
  testing::ScratchFolder scratch_{"deform-picture"};
};

// An edit of the upper unit hemisphere, seen from above: the band along the rim (z < 0.55) fixed,
// the cap around the pole (z > 0.9) the handle, pulled sideways and up, the rest following
// smoothly.
struct Edit {
  Mesh rest;
  Eigen::MatrixX3d deformed;
  std::vector<int> roles;
};

Edit hemisphere_edit() {
  Edit edit;
  edit.rest = hemisphere(12);
  edit.deformed = edit.rest.vertices;
  edit.roles.assign(static_cast<std::size_t>(edit.rest.vertex_count()), kDeformRoleFree);
  const Eigen::RowVector3d pull(0.5, 0.4, 0.3);
  for (Eigen::Index v = 0; v < edit.rest.vertices.rows(); ++v) {
    const double z = edit.rest.vertices(v, 2);
    if (z < 0.55) {
      edit.roles[static_cast<std::size_t>(v)] = kDeformRoleFixed;
    } else {
      if (z > 0.9) edit.roles[static_cast<std::size_t>(v)] = 0;
      const double weight = std::min(1.0, (z - 0.55) / (0.9 - 0.55));
      edit.deformed.row(v) += weight * weight * pull;
    }
  }
  return edit;
}

// A handle's tint, shaded: red well above blue and green. Neither the grey, the blue, the
// background nor the black text is.
bool is_warm(const Rgb& color) {
  return color.red > color.blue + 60 && color.red > color.green + 30;
}
// The fixed vertices' blue, shaded.
bool is_bluish(const Rgb& color) {
  return color.blue > color.red + 60 && color.blue > color.green + 30;
}

TEST_F(DeformPictureTest, IsAPngOfTheRequestedSizeWithAShapeInEachHalf) {
  const Edit edit = hemisphere_edit();
  const fs::path path = scratch_.file("edit.png");
  write_deform_picture(path, edit.rest, edit.deformed, edit.roles);
  const testing::DecodedImage image = testing::decode_png(path);
  ASSERT_EQ(image.width, 1600);
  ASSERT_EQ(image.height, 800);
  for (const auto& [x, y] : testing::corner_pixels(image))
    EXPECT_TRUE(testing::is_background(image.at(x, y))) << "corner " << x << ", " << y;
  EXPECT_TRUE(testing::is_background(image.at(image.width / 2, image.height / 2)));
  for (int half = 0; half < 2; ++half)
    EXPECT_GT(testing::count_in_view(image, half, [](const Rgb& c) { return !testing::is_background(c); }), 50000)
        << "half " << half;

  DeformPictureOptions options;
  options.width = 901;
  options.height = 500;
  options.title = "hemisphere - cap pulled";
  const fs::path small = scratch_.file("small.png");
  write_deform_picture(small, edit.rest, edit.deformed, edit.roles, options);
  const testing::DecodedImage small_image = testing::decode_png(small);
  EXPECT_EQ(small_image.width, 901);
  EXPECT_EQ(small_image.height, 500);
}

TEST_F(DeformPictureTest, TheViewsAreIdenticalWhenNothingMovedAndDifferWhenSomethingDid) {
  const Edit edit = hemisphere_edit();
  const fs::path unmoved = scratch_.file("unmoved.png");
  write_deform_picture(unmoved, edit.rest, edit.rest.vertices, edit.roles);
  const testing::DecodedImage same = testing::decode_png(unmoved);
  ASSERT_EQ(same.width, 1600);
  EXPECT_GT(testing::count_in_view(same, 0, [](const Rgb& c) { return !testing::is_background(c); }), 50000);
  EXPECT_EQ(testing::differences_between_halves(same), 0);

  const fs::path moved = scratch_.file("moved.png");
  write_deform_picture(moved, edit.rest, edit.deformed, edit.roles);
  EXPECT_GT(testing::differences_between_halves(testing::decode_png(moved)), 10000);
}

TEST_F(DeformPictureTest, TheFixedVerticesAndTheHandleShowInTheirColoursOnBothSides) {
  const Edit edit = hemisphere_edit();
  const fs::path coloured = scratch_.file("coloured.png");
  write_deform_picture(coloured, edit.rest, edit.deformed, edit.roles);
  const testing::DecodedImage image = testing::decode_png(coloured);
  for (int half = 0; half < 2; ++half) {
    EXPECT_GT(testing::count_in_view(image, half, is_warm), 2000) << "half " << half;
    EXPECT_GT(testing::count_in_view(image, half, is_bluish), 2000) << "half " << half;
  }

  // Without roles everything is grey: no tint anywhere in the views.
  const std::vector<int> all_free(edit.roles.size(), kDeformRoleFree);
  const fs::path grey = scratch_.file("grey.png");
  write_deform_picture(grey, edit.rest, edit.deformed, all_free);
  const testing::DecodedImage plain = testing::decode_png(grey);
  for (int half = 0; half < 2; ++half) {
    EXPECT_EQ(testing::count_in_view(plain, half, is_warm), 0) << "half " << half;
    EXPECT_EQ(testing::count_in_view(plain, half, is_bluish), 0) << "half " << half;
  }
}

TEST_F(DeformPictureTest, TheSameArgumentsGiveTheSameBytes) {
  const Edit edit = hemisphere_edit();
  DeformPictureOptions options;
  options.width = 800;
  options.height = 400;
  options.title = "hemisphere - cap pulled";
  write_deform_picture(scratch_.file("first.png"), edit.rest, edit.deformed, edit.roles, options);
  write_deform_picture(scratch_.file("second.png"), edit.rest, edit.deformed, edit.roles, options);
  const std::string first = testing::file_bytes(scratch_.file("first.png"));
  EXPECT_FALSE(first.empty());
  EXPECT_EQ(first, testing::file_bytes(scratch_.file("second.png")));
}

TEST_F(DeformPictureTest, RefusesBadArgumentsAndFailedWritesLeaveNothingBehind) {
  const Edit edit = hemisphere_edit();
  const auto status_of = [&](const fs::path& path, const Eigen::MatrixX3d& deformed,
                             const std::vector<int>& roles, const DeformPictureOptions& options) {
    try {
      write_deform_picture(path, edit.rest, deformed, roles, options);
    } catch (const Error& error) {
      return error.status();
    }
    return Status::ok;
  };
  const DeformPictureOptions defaults;
  EXPECT_EQ(status_of(scratch_.file("rows.png"), edit.deformed.topRows(3), edit.roles, defaults),
            Status::invalid_input);
  const std::vector<int> short_roles(edit.roles.begin(), edit.roles.end() - 1);
  EXPECT_EQ(status_of(scratch_.file("roles.png"), edit.deformed, short_roles, defaults),
            Status::invalid_input);
  std::vector<int> unknown_role = edit.roles;
  unknown_role[7] = -3;
  EXPECT_EQ(status_of(scratch_.file("role.png"), edit.deformed, unknown_role, defaults),
            Status::invalid_input);
  Eigen::MatrixX3d not_finite = edit.deformed;
  not_finite(5, 1) = std::nan("");
  EXPECT_EQ(status_of(scratch_.file("nan.png"), not_finite, edit.roles, defaults),
            Status::invalid_input);
  DeformPictureOptions tiny;
  tiny.width = 100;
  EXPECT_EQ(status_of(scratch_.file("tiny.png"), edit.deformed, edit.roles, tiny),
            Status::invalid_input);
  EXPECT_EQ(status_of(scratch_.file("edit.svg"), edit.deformed, edit.roles, defaults),
            Status::io_error);
  EXPECT_EQ(status_of(scratch_.file("edit.jpg"), edit.deformed, edit.roles, defaults),
            Status::io_error);
  EXPECT_TRUE(fs::is_empty(scratch_.path()));

  // Unwritable: a folder that does not exist, and a target that is a folder.
  EXPECT_EQ(status_of(scratch_.path() / "missing" / "edit.png", edit.deformed, edit.roles,
                      defaults),
            Status::io_error);
  EXPECT_TRUE(fs::is_empty(scratch_.path()));
  const fs::path folder = scratch_.file("folder.png");
  fs::create_directory(folder);
  EXPECT_EQ(status_of(folder, edit.deformed, edit.roles, defaults), Status::io_error);
  EXPECT_TRUE(fs::is_directory(folder));
  EXPECT_TRUE(fs::is_empty(folder));
  EXPECT_EQ(std::distance(fs::directory_iterator(scratch_.path()), fs::directory_iterator()), 1);
}

}  // namespace
}  // namespace harmonia
