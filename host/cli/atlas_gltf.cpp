#include "cli/atlas_gltf.h"

#include <algorithm>
#include <filesystem>
#include <iostream>

#include "cli/atlas_report.h"
#include "cli/report_output.h"
#include "harmonia/atlas_picture.h"
#include "harmonia/gltf.h"

namespace harmonia::cli {
namespace {

// The triangle sets that get one atlas each, with the names the report gives them.
struct AtlasGroup {
  std::string name;  // "mesh 0 'Duck'", "meshes[0].primitives[1]", "scene".
  GltfTriangles triangles;
};

std::string mesh_label(const GltfDocument& document, int mesh) {
  const std::vector<GltfMeshSummary> meshes = document.summary().meshes;
  const std::string& name = meshes[static_cast<std::size_t>(mesh)].name;
  return "mesh " + std::to_string(mesh) + (name.empty() ? "" : " '" + name + "'");
}

std::vector<AtlasGroup> atlas_groups(const GltfDocument& document, const AtlasOptions& options) {
  std::vector<int> meshes;
  if (!gltf_mesh_choice().empty()) {
    try {
      meshes.push_back(document.find_mesh(gltf_mesh_choice()));
    } catch (const Error& error) {
      throw CliFailure(ExitCode::usage, error.what());
    }
  } else {
    for (int mesh = 0; mesh < document.mesh_count(); ++mesh) meshes.push_back(mesh);
  }
  std::vector<AtlasGroup> groups;
  if (options.group == "scene") {
    if (gltf_mesh_choice().empty()) {
      groups.push_back({"scene", all_mesh_triangles(document)});
    } else {
      groups.push_back({mesh_label(document, meshes.front()), document.mesh_triangles(meshes.front())});
    }
  } else {
    for (const int mesh : meshes) {
      if (options.group == "mesh") {
        groups.push_back({mesh_label(document, mesh), document.mesh_triangles(mesh)});
        continue;
      }
      for (int primitive = 0; primitive < document.primitive_count(mesh); ++primitive) {
        groups.push_back({"meshes[" + std::to_string(mesh) + "].primitives[" +
                              std::to_string(primitive) + "]",
                          document.mesh_triangles(mesh, primitive)});
      }
    }
  }
  std::erase_if(groups, [](const AtlasGroup& group) { return group.triangles.mesh.face_count() == 0; });
  if (groups.empty()) {
    throw CliFailure(ExitCode::input, document.name() + ": no triangles to make an atlas of");
  }
  return groups;
}

// Refuses a texture-coordinate choice that the writer would refuse, before any work.
void check_texcoord_choice(const GltfDocument& document, const std::vector<AtlasGroup>& groups,
                           const GltfWriteOptions& write_options) {
  for (const AtlasGroup& group : groups) {
    for (const GltfPart& part : group.triangles.parts) {
      try {
        (void)texcoord_set_for(document, part.mesh, part.primitive, write_options);
      } catch (const Error& error) {
        throw CliFailure(ExitCode::usage, error.what());
      }
    }
  }
}

// --repack: the group's charts of TEXCOORD_0, its texture set, packed anew (repack_texture_atlas).
TextureAtlas repacked_group(const GltfDocument& document, const AtlasGroup& group,
                            const TextureAtlasOptions& atlas_options) {
  Eigen::Matrix<double, Eigen::Dynamic, 6> corner_uv;
  try {
    corner_uv = corner_texcoords(document, group.triangles, 0);
  } catch (const Error& error) {
    throw CliFailure(ExitCode::input, std::string(error.what()) + ": --repack keeps a primitive's TEXCOORD_0");
  }
  try {
    return repack_texture_atlas(group.triangles.mesh, corner_uv, atlas_options);
  } catch (const Error& error) {
    TextureAtlas failed;
    failed.report.status = error.status();
    failed.report.message = error.what();
    return failed;
  }
}

}  // namespace

ExitCode run_gltf_atlas(const AtlasOptions& options, const GlobalOptions& global) {
  if (options.cleanup != "none") {
    throw CliFailure(ExitCode::usage,
                     "--cleanup " + options.cleanup + " makes a new mesh, which has no place in a "
                     "glTF document; with glTF output the atlas takes the document's triangles as "
                     "they are (its charts span the file's splits unless --keep-splits)");
  }
  if (!options.picture.empty()) require_extension(options.picture, {".png"}, "picture");
  check_output(options.input, options.output, options.in_place, "OUT");
  if (!options.picture.empty()) check_output(options.input, options.picture, false, "--picture");

  ProgressLine progress(global, options.json);
  std::vector<PhaseTiming> timings;
  auto start = Clock::now();
  progress.show("reading " + options.input);
  const GltfDocument document = is_gltf_path(options.input)
                                    ? load_gltf(options.input)
                                    : GltfDocument::from_mesh(load_mesh(options.input), options.input);
  const std::vector<AtlasGroup> groups = atlas_groups(document, options);
  timings.push_back({"read", seconds_since(start)});
  GltfWriteOptions write_options;
  write_options.texcoord = options.texcoord;
  write_options.overwrite = options.overwrite;
  check_texcoord_choice(document, groups, write_options);
  if (!options.picture.empty() && groups.size() != 1) {
    throw CliFailure(ExitCode::usage, "--picture draws one atlas; this makes " +
                                          std::to_string(groups.size()) +
                                          " (--group scene or --mesh makes one)");
  }

  const TextureAtlasOptions atlas_options = library_options(options, progress);
  std::vector<TextureAtlas> atlases;
  std::vector<GltfPrimitiveUpdate> updates;
  for (const AtlasGroup& group : groups) {
    TextureAtlas atlas = options.repack ? repacked_group(document, group, atlas_options)
                                        : make_atlas(group.triangles.mesh, atlas_options);
    progress.clear();
    if (!atlas.report.ok()) {
      if (options.json) std::cout << report_json(options, atlas_options, atlas, timings).dump(2) << '\n';
      throw CliFailure(exit_code_for(atlas.report.status),
                       options.input + ": " + group.name + ": " + atlas.report.message);
    }
    if (!options.picture.empty()) refuse_picture_of_pages(atlas);
    std::vector<GltfPrimitiveUpdate> group_updates =
        texcoord_updates(group.triangles, atlas.corner_uv, atlas.chart_of_face, page_of_face(atlas));
    updates.insert(updates.end(), std::make_move_iterator(group_updates.begin()),
                   std::make_move_iterator(group_updates.end()));
    atlases.push_back(std::move(atlas));
  }

  start = Clock::now();
  progress.show("writing " + options.output);
  write_output([&] { write_gltf(options.output, document, updates, write_options); });
  timings.push_back({"write", seconds_since(start)});
  if (!options.picture.empty()) {
    progress.show("drawing " + options.picture);
    AtlasPictureOptions picture;
    picture.title = std::filesystem::path(options.input).filename().string() + " - " +
                    groups.front().name + " - " + std::to_string(atlases.front().metrics.charts) +
                    " charts";
    write_output([&] {
      write_atlas_picture(options.picture, groups.front().triangles.mesh, atlases.front(), picture);
    });
  }
  progress.clear();

  std::string defects;
  nlohmann::json per_group = nlohmann::json::array();
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const TextureAtlas& atlas = atlases[g];
    std::vector<PhaseTiming> group_timings = atlas.report.timings;
    if (options.json) {
      nlohmann::json report = report_json(options, atlas_options, atlas, group_timings);
      report["group"] = groups[g].name;
      report["vertices"] = groups[g].triangles.mesh.vertex_count();
      per_group.push_back(std::move(report));
    } else {
      std::cout << groups[g].name << '\n';
      print_table(options, atlas, group_timings);
    }
    if (const std::string kept = kept_layout_faults(atlas.metrics); options.repack && !kept.empty())
      note(global, options.output + ": " + groups[g].name + ": kept as the input's TEXCOORD_0 has them: " + kept);
    if (const std::string found = atlas_defects(atlas.metrics, options.repack); !found.empty()) {
      defects += (defects.empty() ? "" : "; ") + groups[g].name + ": " + found;
    }
  }
  if (options.json) {
    // The figures over all atlases, as the one-atlas report has them (the batch log reads these):
    // counts summed, the worst stretch, the mean coverage (each atlas is a texture of its own).
    int faces = 0, charts = 0, flipped = 0, mirrored = 0, overlapping = 0, crossings = 0, dropped = 0;
    double coverage = 0.0, l2_stretch = 0.0;
    for (const TextureAtlas& atlas : atlases) {
      const AtlasMetrics& metrics = atlas.metrics;
      faces += metrics.faces;
      charts += metrics.charts;
      flipped += metrics.flipped_triangles;
      mirrored += metrics.mirrored_charts;
      overlapping += metrics.overlapping_texels;
      crossings += metrics.boundary_crossings;
      dropped += metrics.dropped_faces;
      coverage += metrics.coverage / static_cast<double>(atlases.size());
      l2_stretch = std::max(l2_stretch, metrics.l2_stretch);
    }
    std::cout << nlohmann::json{{"status", "ok"},
                                {"faces", faces},
                                {"charts", charts},
                                {"coverage", coverage},
                                {"l2_stretch", l2_stretch},
                                {"flipped_triangles", flipped},
                                {"mirrored_charts", mirrored},
                                {"overlapping_texels", overlapping},
                                {"boundary_crossings", crossings},
                                {"dropped_faces", dropped},
                                {"input", options.input},
                                {"output", options.output},
                                {"group", options.group},
                                {"primitives_written", updates.size()},
                                {"timings", timings_json(timings)},
                                {"atlases", per_group}}
                     .dump(2)
              << '\n';
  }
  if (!defects.empty()) {
    throw CliFailure(ExitCode::invalid_result,
                     "the atlas has " + defects + "; " + options.output + " was written anyway");
  }
  (void)global;
  return ExitCode::ok;
}

}  // namespace harmonia::cli
