// The pictures of a deformation transfer: the markers' colours blended by the marker fields on the
// source, carried to the target through the correspondence, and the two meshes drawn side by side
// (picture/side_by_side_picture.h), each view fitted to its own mesh.
#include "harmonia/transfer_picture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "harmonia/types.h"
#include "io/atomic_file.h"
#include "picture/color_map.h"
#include "picture/side_by_side_picture.h"

namespace harmonia {
namespace {

using detail::Rgb;

// The turn between consecutive markers' hues, as a fraction of the colour circle: the golden
// angle, 1 - 1/phi, whose multiples spread evenly round the circle for any number of markers.
constexpr double kGoldenTurn = 1.0 - 1.0 / std::numbers::phi;
// The six shades, saturation by marker % 2 and brightness by marker % 3; none so dark that the
// shading of faces turned from the light makes it black, none so pale that it looks grey.
constexpr std::array<double, 2> kSaturations = {0.75, 0.5};
constexpr std::array<double, 3> kBrightnesses = {0.95, 0.8, 0.65};

// A target face that no source face was matched to (DeformationTransfer::matches() -1).
constexpr Rgb kNoMatchColor = detail::kUndefinedFill;

// Hue as a fraction of the circle (0 red, 1/3 green, 2/3 blue), saturation and brightness in
// [0, 1]: the RGB colour, each channel in [0, 1].
Eigen::Vector3d rgb_from_hsv(double hue, double saturation, double brightness) {
  // Each channel ramps between brightness and brightness (1 - saturation) along the circle.
  const auto channel = [&](double offset) {
    const double k = std::fmod(offset + 6.0 * hue, 6.0);
    return brightness - brightness * saturation * std::clamp(std::min(k, 4.0 - k), 0.0, 1.0);
  };
  return {channel(5.0), channel(3.0), channel(1.0)};
}

Rgb to_bytes(const Eigen::Vector3d& color) {
  const auto channel = [](double value) {
    return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(value, 0.0, 1.0)));
  };
  return {channel(color.x()), channel(color.y()), channel(color.z())};
}

// Marker fields that can be blended on `mesh`: at least one, one row per vertex, all finite.
void check_fields(const Mesh& mesh, const Eigen::MatrixXd& fields, const std::string& name,
                  const std::string& caller) {
  const auto refuse = [&](const std::string& problem) {
    throw Error(Status::invalid_input, caller + ": " + problem);
  };
  if (fields.cols() == 0) refuse(name + " marker fields have no column (no marker)");
  if (fields.rows() != mesh.vertices.rows())
    refuse(name + " marker fields have " + std::to_string(fields.rows()) + " rows for " +
           std::to_string(mesh.vertices.rows()) + " vertices");
  if (!fields.allFinite()) refuse(name + " marker fields hold a value that is not finite");
}

// marker_face_colors once its arguments are known to be good.
Eigen::MatrixX3d blended_face_colors(const Mesh& mesh, const Eigen::MatrixXd& fields) {
  Eigen::MatrixX3d palette(fields.cols(), 3);
  for (Eigen::Index i = 0; i < fields.cols(); ++i)
    palette.row(i) = marker_color(static_cast<int>(i)).transpose();
  // The fields are linear over each face: at the barycentre, the mean of the corners' values.
  Eigen::MatrixXd face_fields(mesh.faces.rows(), fields.cols());
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    face_fields.row(f) = (fields.row(mesh.faces(f, 0)) + fields.row(mesh.faces(f, 1)) +
                          fields.row(mesh.faces(f, 2))) /
                         3.0;
  return (face_fields * palette).cwiseMax(0.0).cwiseMin(1.0);
}

std::vector<Rgb> to_bytes(const Eigen::MatrixX3d& colors) {
  std::vector<Rgb> bytes(static_cast<std::size_t>(colors.rows()));
  for (Eigen::Index f = 0; f < colors.rows(); ++f)
    bytes[static_cast<std::size_t>(f)] = to_bytes(Eigen::Vector3d(colors.row(f).transpose()));
  return bytes;
}

// The checks both pictures make on the meshes, the transfer and the size, before any work.
void validate(const std::string& caller, const Mesh& source_rest, const Mesh& target_rest,
              const DeformationTransfer& transfer, const TransferPictureOptions& options) {
  const auto refuse = [&](const std::string& problem) {
    throw Error(Status::invalid_input, caller + ": " + problem);
  };
  detail::check_picture_size(options.width, options.height, caller);
  if (!transfer.setup_report().ok())
    refuse("the transfer's set-up failed (" + transfer.setup_report().message + ")");
  detail::check_face_corners(source_rest.faces, source_rest.vertices.rows(), caller);
  detail::check_face_corners(target_rest.faces, target_rest.vertices.rows(), caller);
  check_fields(source_rest, transfer.source_fields(), "source", caller);
  check_fields(target_rest, transfer.target_fields(), "target", caller);
  const std::vector<int>& matches = transfer.matches();
  if (!matches.empty() && static_cast<Eigen::Index>(matches.size()) != target_rest.faces.rows())
    refuse(std::to_string(matches.size()) + " matches for " +
           std::to_string(target_rest.faces.rows()) + " target faces");
  for (std::size_t f = 0; f < matches.size(); ++f)
    if (matches[f] < -1 || matches[f] >= source_rest.faces.rows())
      refuse("target face " + std::to_string(f) + " is matched to source face " +
             std::to_string(matches[f]) + ", which does not exist");
  detail::check_finite_positions(source_rest.vertices, "source rest", caller);
  detail::check_finite_positions(target_rest.vertices, "target rest", caller);
}

// The faces' colours on both sides, and the legend that explains what is not a marker colour.
struct TransferColors {
  std::vector<Rgb> source;
  std::vector<Rgb> target;
  std::vector<detail::LegendEntry> legend;
};

TransferColors transfer_colors(const Mesh& source_rest, const Mesh& target_rest,
                               const DeformationTransfer& transfer) {
  TransferColors colors;
  colors.source = to_bytes(blended_face_colors(source_rest, transfer.source_fields()));
  const std::vector<int>& matches = transfer.matches();
  if (matches.empty()) {  // No correspondence: the target's own fields.
    colors.target = to_bytes(blended_face_colors(target_rest, transfer.target_fields()));
    return colors;
  }
  colors.target.reserve(matches.size());
  for (const int match : matches)
    colors.target.push_back(match < 0 ? kNoMatchColor
                                      : colors.source[static_cast<std::size_t>(match)]);
  if (std::find(matches.begin(), matches.end(), -1) != matches.end())
    colors.legend.push_back({kNoMatchColor, "no match"});
  return colors;
}

// Both pictures: the source at `source_positions` and the target at `target_positions`, each
// view fitted to its own mesh.
void write_picture(const std::filesystem::path& png, const Mesh& source_rest,
                   const Eigen::MatrixX3d& source_positions, const Mesh& target_rest,
                   const Eigen::MatrixX3d& target_positions, const DeformationTransfer& transfer,
                   const TransferPictureOptions& options,
                   const std::array<std::string, 2>& captions) {
  const TransferColors colors = transfer_colors(source_rest, target_rest, transfer);
  detail::SideBySideLayout layout;
  layout.width = options.width;
  layout.height = options.height;
  layout.title = options.title;
  layout.legend = colors.legend;
  layout.camera = detail::ViewCamera::per_view;
  detail::write_file_atomically(
      png, detail::render_side_by_side_png(
               {source_rest.faces, source_positions, colors.source, captions[0]},
               {target_rest.faces, target_positions, colors.target, captions[1]}, layout));
}

}  // namespace

Eigen::Vector3d marker_color(int marker) {
  if (marker < 0)
    throw Error(Status::invalid_input,
                "marker_color: marker " + std::to_string(marker) + " (markers count from 0)");
  const double hue = std::fmod(marker * kGoldenTurn, 1.0);
  return rgb_from_hsv(hue, kSaturations[static_cast<std::size_t>(marker % 2)],
                      kBrightnesses[static_cast<std::size_t>(marker % 3)]);
}

Eigen::MatrixX3d marker_face_colors(const Mesh& mesh, const Eigen::MatrixXd& fields) {
  const std::string caller = "marker_face_colors";
  detail::check_face_corners(mesh.faces, mesh.vertices.rows(), caller);
  check_fields(mesh, fields, "the", caller);
  return blended_face_colors(mesh, fields);
}

void write_transfer_correspondence_picture(const std::filesystem::path& png,
                                           const Mesh& source_rest, const Mesh& target_rest,
                                           const DeformationTransfer& transfer,
                                           const TransferPictureOptions& options) {
  const std::string caller = "write_transfer_correspondence_picture";
  detail::require_png(png, caller);  // Before any work.
  validate(caller, source_rest, target_rest, transfer, options);
  write_picture(png, source_rest, source_rest.vertices, target_rest, target_rest.vertices,
                transfer, options, {"source", "target"});
}

void write_transfer_pose_picture(const std::filesystem::path& png, const Mesh& source_rest,
                                 const Eigen::MatrixX3d& source_pose, const Mesh& target_rest,
                                 const Eigen::MatrixX3d& transferred,
                                 const DeformationTransfer& transfer,
                                 const TransferPictureOptions& options) {
  const std::string caller = "write_transfer_pose_picture";
  detail::require_png(png, caller);  // Before any work.
  validate(caller, source_rest, target_rest, transfer, options);
  const auto refuse = [&](const std::string& problem) {
    throw Error(Status::invalid_input, caller + ": " + problem);
  };
  if (source_pose.rows() != source_rest.vertices.rows())
    refuse(std::to_string(source_pose.rows()) + " source pose positions for " +
           std::to_string(source_rest.vertices.rows()) + " source vertices");
  if (transferred.rows() != target_rest.vertices.rows())
    refuse(std::to_string(transferred.rows()) + " transferred positions for " +
           std::to_string(target_rest.vertices.rows()) + " target vertices");
  detail::check_finite_positions(source_pose, "source pose", caller);
  detail::check_finite_positions(transferred, "transferred", caller);
  write_picture(png, source_rest, source_pose, target_rest, transferred, transfer, options,
                {"source pose", "transferred"});
}

}  // namespace harmonia
