// The "before and after" picture of a surface edit: the rest mesh and the deformed one side by
// side with one camera (picture/side_by_side_picture.h), so that whatever the edit did not move looks
// exactly the same on both sides; the faces coloured by their vertices' roles in the edit.
#include "harmonia/deform_picture.h"

#include <array>
#include <cstddef>
#include <set>
#include <string>
#include <vector>

#include "harmonia/types.h"
#include "io/atomic_file.h"
#include "picture/color_map.h"
#include "picture/side_by_side_picture.h"

namespace harmonia {
namespace {

using detail::LegendEntry;
using detail::Rgb;

const std::string kCaller = "write_deform_picture";

constexpr Rgb kFreeColor{210, 210, 210};
constexpr Rgb kFixedColor{105, 145, 225};
// The handles' tints, cycled: warm hues that stay apart from each other, from the free grey and
// from the fixed blue.
constexpr std::array<Rgb, 6> kHandleColors = {{{240, 125, 45},
                                               {215, 55, 55},
                                               {235, 185, 40},
                                               {195, 75, 140},
                                               {160, 95, 50},
                                               {250, 150, 120}}};

// ---------------------------------------------------------------------------------------------
// The edit as drawn

Rgb role_color(int role) {
  if (role == kDeformRoleFixed) return kFixedColor;
  if (role >= 0) return kHandleColors[static_cast<std::size_t>(role) % kHandleColors.size()];
  return kFreeColor;
}

void validate(const Mesh& rest, const Eigen::MatrixX3d& deformed,
              const std::vector<int>& vertex_roles, const DeformPictureOptions& options) {
  const auto refuse = [](const std::string& problem) {
    throw Error(Status::invalid_input, kCaller + ": " + problem);
  };
  detail::check_picture_size(options.width, options.height, kCaller);
  const Eigen::Index vertices = rest.vertices.rows();
  const std::string per_vertex = " for " + std::to_string(vertices) + " vertices";
  if (deformed.rows() != vertices)
    refuse(std::to_string(deformed.rows()) + " deformed positions" + per_vertex);
  if (static_cast<Eigen::Index>(vertex_roles.size()) != vertices)
    refuse(std::to_string(vertex_roles.size()) + " vertex roles" + per_vertex);
  for (std::size_t v = 0; v < vertex_roles.size(); ++v)
    if (vertex_roles[v] < kDeformRoleFixed)
      refuse("vertex " + std::to_string(v) + " has role " + std::to_string(vertex_roles[v]) +
             " (-1 free, -2 fixed, a handle's index from 0)");
  detail::check_face_corners(rest.faces, vertices, kCaller);
  detail::check_finite_positions(rest.vertices, "rest", kCaller);
  detail::check_finite_positions(deformed, "deformed", kCaller);
}

// A face takes its corners' role when all three share it; a face across roles is free.
std::vector<Rgb> face_colors(const Mesh& mesh, const std::vector<int>& vertex_roles) {
  std::vector<Rgb> colors(static_cast<std::size_t>(mesh.faces.rows()));
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const int role = vertex_roles[mesh.faces(f, 0)];
    const bool shared =
        vertex_roles[mesh.faces(f, 1)] == role && vertex_roles[mesh.faces(f, 2)] == role;
    colors[static_cast<std::size_t>(f)] = role_color(shared ? role : kDeformRoleFree);
  }
  return colors;
}

// The roles that occur: free, fixed, then the handles by index.
std::vector<LegendEntry> legend_entries(const std::vector<int>& vertex_roles) {
  const std::set<int> roles(vertex_roles.begin(), vertex_roles.end());
  std::vector<LegendEntry> entries;
  if (roles.contains(kDeformRoleFree)) entries.push_back({kFreeColor, "free"});
  if (roles.contains(kDeformRoleFixed)) entries.push_back({kFixedColor, "fixed"});
  for (const int role : roles)
    if (role >= 0) entries.push_back({role_color(role), "handle " + std::to_string(role)});
  return entries;
}

}  // namespace

void write_deform_picture(const std::filesystem::path& png, const Mesh& rest,
                          const Eigen::MatrixX3d& deformed, const std::vector<int>& vertex_roles,
                          const DeformPictureOptions& options) {
  detail::require_png(png, kCaller);  // Before any work.
  validate(rest, deformed, vertex_roles, options);
  const std::vector<Rgb> fill = face_colors(rest, vertex_roles);
  detail::SideBySideLayout layout;
  layout.width = options.width;
  layout.height = options.height;
  layout.title = options.title;
  layout.legend = legend_entries(vertex_roles);
  layout.camera = detail::ViewCamera::shared;
  detail::write_file_atomically(
      png, detail::render_side_by_side_png({rest.faces, rest.vertices, fill, "before"},
                                           {rest.faces, deformed, fill, "after"}, layout));
}

}  // namespace harmonia
