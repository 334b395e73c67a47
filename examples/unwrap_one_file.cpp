// Flattens a disk-shaped mesh with harmonia's default map and writes an OBJ with one vt per vertex.
//   unwrap_one_file IN OUT.obj
#include <cstdio>

#include <harmonia/fixed_boundary_map.h>
#include <harmonia/io.h>
#include <harmonia/metrics.h>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: unwrap_one_file IN OUT.obj\n");
    return 2;
  }
  try {
    const harmonia::Mesh mesh = harmonia::read_mesh(argv[1]);            // .obj .off .ply .stl
    const harmonia::MapResult map = harmonia::fixed_boundary_map(mesh);  // cotangent, circle
    if (!map.report.ok()) {  // not a disk, flipped triangles, ...: the message says which
      std::fprintf(stderr, "%s\n", map.report.message.c_str());
      return 1;
    }
    harmonia::write_obj(argv[2], mesh, map.uv);
    const harmonia::DistortionMetrics quality = harmonia::evaluate_map(mesh, map.uv, mesh.faces);
    std::printf("ok: %d flipped, conformal distortion %.3f, area distortion %.3f, L2 stretch %.3f\n",
                quality.flipped_triangles, quality.conformal_distortion_mean,
                quality.area_distortion_mean, quality.l2_stretch);
    return 0;
  } catch (const harmonia::Error& error) {  // a file that cannot be read or written
    std::fprintf(stderr, "%s\n", error.what());
    return 1;
  }
}
