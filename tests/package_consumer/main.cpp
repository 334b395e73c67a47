// A program that uses an installed harmonia through find_package(harmonia) (docs/cpp-api.md).
#include <cstdio>

#include <harmonia/fixed_boundary_map.h>
#include <harmonia/io.h>
#include <harmonia/procedural.h>

int main() {
  const harmonia::Mesh mesh = harmonia::hemisphere(20);  // or harmonia::read_mesh("input.obj")
  harmonia::FixedBoundaryOptions options;
  options.weights = harmonia::WeightScheme::mean_value;  // positive weights: no flips (Tutte)
  const harmonia::MapResult result = harmonia::fixed_boundary_map(mesh, options);
  if (!result.report.ok()) {
    std::fprintf(stderr, "%s: %s\n", harmonia::to_string(result.report.status).data(),
                 result.report.message.c_str());
    return 1;
  }
  harmonia::write_obj("hemisphere-uv.obj", mesh, result.uv);  // one vt per vertex
  std::printf("%d vertices flattened (%s)\n", mesh.vertex_count(), result.report.solver.c_str());
  return 0;
}
