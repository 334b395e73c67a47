#pragma once
//! \file atlas.h
//! \brief `harmonia atlas IN OUT [--resolution N] [--padding P] [--max-distortion D]
//! [--picture FILE.png] [--json]`: the texture atlas of any triangle mesh
//! (harmonia/texture_atlas.h) written as an OBJ with per-corner texture coordinates in [0, 1]
//! (harmonia/atlas_io.h).

#include <CLI/CLI.hpp>
#include <istream>
#include <string>

#include "cli/common.h"
#include "cli/progress_line.h"
#include "harmonia/texture_atlas.h"

namespace harmonia::cli {

//! The atlas' size in texels as --resolution gives it: N (N x N) or WxH.
struct AtlasResolution {
  int width = 0;
  int height = 0;
  [[nodiscard]] std::string text() const;  //!< "N" for a square, else "WxH".
};
//! Reads "N" or "WxH" (also "W*H"); the stream fails on anything else.
std::istream& operator>>(std::istream& in, AtlasResolution& resolution);

struct AtlasOptions {
  std::string input;
  std::string output;
  bool in_place = false;  //!< OUT may be IN: the input is replaced by the result.
  //! The atlas' options; the defaults are TextureAtlasOptions' (set in add_atlas_command).
  AtlasResolution resolution;
  int padding = 0;
  double max_distortion = 0.0;
  double max_normal_deviation_degrees = 0.0;
  int threads = 0;  //!< Flattening threads, 0: one per core.
  double texels_per_unit = 0.0;  //!< 0: the densest that fits; else this density, exactly.
  int max_pages = 0;             //!< With texels_per_unit: the most pages, 0 for any number.
  //! none (default: the atlas takes any mesh as it is), strict (refuse dirty input, as unwrap) or
  //! repair (merge duplicate vertices, drop degenerate and duplicate faces, orient consistently).
  std::string cleanup = "none";
  bool keep_splits = false;  //!< The file's splits are chart boundaries (TextureAtlasOptions).
  bool join_charts = false;  //!< Join neighbours whose union flattens within the limit.
  bool repack = false;       //!< Keep the input's own UV charts and only pack them.
  //! glTF output: "mesh" (an atlas per mesh), "primitive" or "scene" (one atlas of every mesh).
  std::string group = "mesh";
  int texcoord = -1;       //!< glTF output: the TEXCOORD_n set; -1: the lowest one missing.
  bool overwrite = false;  //!< glTF output: --texcoord may replace an existing set.
  std::string picture;  //!< Also draw the atlas (PNG); empty: no picture.
  std::string view;     //!< Also write a page to look at it in a browser (.html); empty: none.
  std::string backend = "auto";  //!< cpu, vulkan or auto (see program_solver_options).
  bool json = false;
};

CLI::App* add_atlas_command(CLI::App& app, AtlasOptions& options);


//! --resolution, --padding and --max-distortion, with the checks of their ranges (those
//! TextureAtlasOptions documents), for `atlas` and for `batch`, which passes them on; the values
//! are an AtlasResolution, int and double, or optionals of them.
template <typename Resolution, typename Padding, typename Distortion>
void add_atlas_layout_options(CLI::App& command, Resolution& resolution, Padding& padding,
                              Distortion& max_distortion);

//! The library's options for the command's.
[[nodiscard]] TextureAtlasOptions library_options(const AtlasOptions& options, ProgressLine& progress);

//! Writes OUT (and the picture), then prints the report. ok; input for an unreadable mesh or one
//! the atlas cannot take (dirty in strict mode, no faces); invalid_result when the atlas, written
//! anyway, has flipped or mirrored triangles, overlapping texels, crossing chart boundaries or
//! dropped faces; environment when an output cannot be written (checked before any work).
[[nodiscard]] ExitCode run_atlas(const AtlasOptions& options, const GlobalOptions& global);

// ------------------------------------------------------------------------------ implementation

namespace atlas_limits {
inline constexpr int kSmallestResolution = 16;
inline constexpr int kLargestResolution = 32768;
inline constexpr int kLargestPadding = 64;
//! The option's help text with the default value the library gives it.
[[nodiscard]] std::string with_default(const std::string& text, double value);
//! Refuses a --max-distortion of 1 or less (1 is an isometry: no chart could keep it).
[[nodiscard]] CLI::Validator greater_than_one();
//! Refuses a --resolution that is not N or WxH with sides in [kSmallestResolution, kLargestResolution].
[[nodiscard]] CLI::Validator atlas_resolution();
}  // namespace atlas_limits

template <typename Resolution, typename Padding, typename Distortion>
void add_atlas_layout_options(CLI::App& command, Resolution& resolution, Padding& padding,
                              Distortion& max_distortion) {
  using namespace atlas_limits;
  const TextureAtlasOptions defaults;
  command
      .add_option("--resolution", resolution,
                  with_default("The atlas is N x N texels, or W x H given as WxH (e.g. 2048x1024)",
                               defaults.resolution))
      ->check(atlas_resolution());
  command
      .add_option(
          "--padding", padding,
          with_default("Empty texels between two charts, half of them at the atlas' edge", defaults.padding))
      ->check(CLI::Range(0, kLargestPadding));
  command
      .add_option("--max-distortion", max_distortion,
                  with_default("Largest L2 stretch a chart may keep before it is split (> 1)",
                               defaults.max_distortion))
      ->check(greater_than_one());
}

}  // namespace harmonia::cli
