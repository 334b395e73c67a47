// Surface editing as an engine drives it: the editor is set up once (the expensive part: the
// factorization and the handle's harmonic field), then every frame moves the handle a little and
// asks for the new surface, which costs one back-substitution.
//
// The surface is a hemisphere: its rim is held fixed and the cap around the pole is the handle,
// lifted and tilted a little more each frame, like a user dragging it.
//   editing_loop [FRAMES [LAST_FRAME.obj]]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

#include <harmonia/io.h>
#include <harmonia/procedural.h>
#include <harmonia/surface_editor.h>

namespace {

using Clock = std::chrono::steady_clock;

double milliseconds_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The rim (within `band` of the equator) stays; the cap (within `band` of the pole) is the handle.
harmonia::EditRegions rim_and_cap(const harmonia::Mesh& hemisphere, double band) {
  harmonia::EditRegions regions;
  regions.handles.resize(1);
  for (int v = 0; v < hemisphere.vertex_count(); ++v) {
    const double height = hemisphere.vertices(v, 2);  // 0 on the rim, 1 at the pole
    if (height < band) regions.fixed.push_back(v);
    if (height > 1.0 - band) regions.handles[0].push_back(v);
  }
  return regions;
}

// Largest distance of `vertices` between two positions of the mesh.
double largest_move(const std::vector<int>& vertices, const Eigen::MatrixX3d& before,
                    const Eigen::MatrixX3d& after) {
  double largest = 0.0;
  for (const int v : vertices) largest = std::max(largest, (after.row(v) - before.row(v)).norm());
  return largest;
}

}  // namespace

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::atoi(argv[1]) : 100;
  if (frames < 1) {
    std::fprintf(stderr, "usage: editing_loop [FRAMES [LAST_FRAME.obj]]\n");
    return 2;
  }
  const harmonia::Mesh mesh = harmonia::hemisphere(40);
  const harmonia::EditRegions regions = rim_and_cap(mesh, 0.1);
  std::printf("mesh        hemisphere, %d vertices, %d faces: %zu fixed, %zu in the handle\n",
              mesh.vertex_count(), mesh.face_count(), regions.fixed.size(),
              regions.handles[0].size());

  // Once, when the user picks the regions.
  const Clock::time_point setup_start = Clock::now();
  harmonia::SurfaceEditor editor(mesh, regions);
  const double setup_ms = milliseconds_since(setup_start);
  const harmonia::SolveReport& setup = editor.setup_report();
  if (!setup.ok()) {
    std::fprintf(stderr, "%s\n", setup.message.c_str());
    return 1;
  }
  std::printf("set-up      %.1f ms on %s (%s):", setup_ms,
              std::string(harmonia::to_string(setup.backend)).c_str(), setup.solver.c_str());
  for (const harmonia::PhaseTiming& phase : setup.timings)
    std::printf(" %s %.1f", phase.phase.c_str(), 1e3 * phase.seconds);
  std::printf("\n");
  if (!setup.backend_notice.empty()) std::printf("            %s\n", setup.backend_notice.c_str());

  // Where the handle is dragged to by the last frame: up by a third, tilted by 30 degrees.
  harmonia::SimilarityTransform drag;
  drag.center = Eigen::Vector3d(0.0, 0.0, 1.0);  // the pole
  drag.rotation = Eigen::AngleAxisd(std::numbers::pi / 6, Eigen::Vector3d::UnitX());
  drag.translation = Eigen::Vector3d(0.0, 0.0, 1.0 / 3.0);

  // Every frame: the handle a little further along, the surface solved again.
  harmonia::SurfaceEditResult frame;
  double total_ms = 0.0, slowest_ms = 0.0;
  for (int k = 1; k <= frames; ++k) {
    const Clock::time_point frame_start = Clock::now();
    frame = editor.deform({drag.partial(static_cast<double>(k) / frames)});
    const double frame_ms = milliseconds_since(frame_start);
    if (!frame.report.ok()) {
      std::fprintf(stderr, "frame %d: %s\n", k, frame.report.message.c_str());
      return 1;
    }
    total_ms += frame_ms;
    slowest_ms = std::max(slowest_ms, frame_ms);
  }
  std::printf("frames      %d, mean %.2f ms, max %.2f ms; factorizations so far: %d\n", frames,
              total_ms / frames, slowest_ms, editor.factorization_count());

  // The constraints hold exactly: the rim did not move, the handle is where it was dragged.
  const int pole = 0;
  const Eigen::Vector3d pole_target = drag.apply(mesh.vertices.row(pole).transpose());
  std::printf("last frame  rim moved %.3g, pole off its target by %.3g, %d flipped triangles\n",
              largest_move(regions.fixed, mesh.vertices, frame.positions),
              (frame.positions.row(pole).transpose() - pole_target).norm(),
              frame.report.flipped_triangles);
  if (argc > 2) {
    try {
      harmonia::write_mesh(argv[2], {frame.positions, mesh.faces});
    } catch (const harmonia::Error& error) {  // the file cannot be written
      std::fprintf(stderr, "%s\n", error.what());
      return 1;
    }
  }
  return 0;
}
