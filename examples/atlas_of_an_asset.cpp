// The texture atlas of any mesh (closed or open, several parts, split vertices): charts cut along
// the creases, each flattened without a fold, packed into one square texture. Writes an OBJ with
// per-corner vt in [0, 1] and prints what the atlas' report says about it.
//   atlas_of_an_asset IN OUT.obj
#include <cstdio>
#include <map>
#include <string>

#include <harmonia/atlas_io.h>
#include <harmonia/io.h>
#include <harmonia/texture_atlas.h>

namespace {

void print_report(const harmonia::TextureAtlas& atlas) {
  const harmonia::AtlasMetrics& metrics = atlas.metrics;
  const harmonia::SolveReport& report = atlas.report;
  std::printf("atlas       %d x %d texels, %d charts over %d faces\n", atlas.resolution,
              atlas.resolution, metrics.charts, metrics.faces);

  // How many charts each method flattened (the first that kept the stretch within the limit).
  std::map<std::string, int> charts_by_method;
  for (const harmonia::AtlasChart& chart : atlas.charts)
    ++charts_by_method[std::string(harmonia::to_string(chart.method))];
  for (const auto& [method, count] : charts_by_method)
    std::printf("  %-18s %d charts\n", method.c_str(), count);

  std::printf("welded      %d vertices onto others at their point (the file's splits)\n",
              atlas.welded_vertices);
  std::printf("coverage    %.1f %% of the texels, %.1f texels per unit of length\n",
              100.0 * metrics.coverage, metrics.texels_per_unit);
  std::printf("distortion  L2 stretch %.4f, angle %.4f, area %.4f\n", metrics.l2_stretch,
              metrics.angle_distortion, metrics.area_distortion);
  std::printf("defects     %d flipped, %d mirrored charts, %d overlapping texels, "
              "%d boundary crossings, %d dropped faces\n",
              metrics.flipped_triangles, metrics.mirrored_charts, metrics.overlapping_texels,
              metrics.boundary_crossings, metrics.dropped_faces);
  std::string backend(harmonia::to_string(report.backend));
  if (!report.solver.empty()) backend += " (" + report.solver + ")";
  std::printf("backend     %s\n", backend.c_str());
  if (!report.backend_notice.empty()) std::printf("  %s\n", report.backend_notice.c_str());
  for (const std::string& fallback : report.fallbacks) std::printf("  %s\n", fallback.c_str());
  std::printf("time        %.1f ms:", 1e3 * report.total_seconds());
  for (const harmonia::PhaseTiming& phase : report.timings)
    std::printf(" %s %.1f", phase.phase.c_str(), 1e3 * phase.seconds);
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: atlas_of_an_asset IN OUT.obj\n");
    return 2;
  }
  try {
    const harmonia::Mesh mesh = harmonia::read_mesh(argv[1]);
    harmonia::check_writable(argv[2]);  // fail now, not after the work

    harmonia::TextureAtlasOptions options;
    options.resolution = 512;  // the texture is 512 x 512 texels
    options.padding = 4;       // empty texels between charts, so mip-maps do not bleed
    const harmonia::TextureAtlas atlas = harmonia::texture_atlas(mesh, options);
    if (!atlas.report.ok()) {
      std::fprintf(stderr, "%s\n", atlas.report.message.c_str());
      return 1;
    }
    harmonia::write_atlas_obj(argv[2], mesh, atlas);
    print_report(atlas);

    // An atlas with overlapping or flipped texels is written (to look at) but not usable.
    const harmonia::AtlasMetrics& metrics = atlas.metrics;
    const bool usable = metrics.flipped_triangles == 0 && metrics.mirrored_charts == 0 &&
                        metrics.overlapping_texels == 0 && metrics.boundary_crossings == 0 &&
                        metrics.dropped_faces == 0;
    return usable ? 0 : 3;
  } catch (const harmonia::Error& error) {  // unreadable file, charts that cannot fit, ...
    std::fprintf(stderr, "%s\n", error.what());
    return 1;
  }
}
