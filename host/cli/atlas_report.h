#pragma once
// What `harmonia atlas` reports about an atlas, shared by its OBJ and glTF outputs.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/atlas.h"
#include "cli/common.h"
#include "harmonia/texture_atlas.h"

namespace harmonia::cli {

//! Runs the atlas; a failure the library throws (e.g. charts that cannot fit the resolution)
//! becomes the report's status, so that it is reported like one the library returns.
[[nodiscard]] TextureAtlas make_atlas(const Mesh& surface, const TextureAtlasOptions& options);

[[nodiscard]] double total_seconds(const std::vector<PhaseTiming>& timings);

//! The report as one JSON object (the options, the metrics, per-chart figures and timings).
[[nodiscard]] nlohmann::json report_json(const AtlasOptions& options,
                                         const TextureAtlasOptions& atlas_options,
                                         const TextureAtlas& atlas,
                                         const std::vector<PhaseTiming>& timings);

//! The report as the table printed without --json.
void print_table(const AtlasOptions& options, const TextureAtlas& atlas,
                 const std::vector<PhaseTiming>& timings);

//! What makes a written atlas unusable as a texture layout, in words; empty when nothing does.
//! A repack (--repack) keeps each chart's layout as the input has it: only what the packing
//! could have made (overlapping texels between charts, dropped faces) is its defect.
[[nodiscard]] std::string atlas_defects(const AtlasMetrics& metrics, bool repack = false);

//! A repack's faults that its input's layout brought (flipped triangles, mirrored charts, crossing
//! boundaries), in words; empty when there are none.
[[nodiscard]] std::string kept_layout_faults(const AtlasMetrics& metrics);

//! --picture draws one square: throws CliFailure(usage), before anything is written, for an atlas
//! of several pages.
void refuse_picture_of_pages(const TextureAtlas& atlas);

}  // namespace harmonia::cli
