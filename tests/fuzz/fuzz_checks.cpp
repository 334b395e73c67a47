#include "fuzz/fuzz_checks.h"

#include <cstdio>
#include <cstdlib>
#include <string>

#include "harmonia/cleanup.h"
#include "harmonia/topology.h"
#include "harmonia/types.h"

namespace harmonia::fuzz {
namespace {

FindingHandler finding_handler = nullptr;

void expect(bool promise_kept, std::string_view what) {
  if (!promise_kept) finding(what);
}

//! A cleanup result's maps must describe its mesh: one entry per input vertex pointing into the
//! output (or -1), one origin per output vertex and face, each in range.
void check_maps(const CleanupResult& result, const Mesh& input) {
  expect(result.vertex_map.size() == input.vertex_count(), "vertex_map has one entry per input vertex");
  for (Eigen::Index v = 0; v < result.vertex_map.size(); ++v) {
    expect(result.vertex_map(v) >= -1 && result.vertex_map(v) < result.mesh.vertex_count(),
           "vertex_map points into the cleaned mesh");
  }
  expect(result.original_vertex.size() == result.mesh.vertex_count(),
         "original_vertex has one entry per output vertex");
  for (Eigen::Index v = 0; v < result.original_vertex.size(); ++v) {
    expect(result.original_vertex(v) >= 0 && result.original_vertex(v) < input.vertex_count(),
           "original_vertex points into the input");
  }
  expect(result.original_face.size() == result.mesh.face_count(),
         "original_face has one entry per output face");
  for (Eigen::Index f = 0; f < result.original_face.size(); ++f) {
    expect(result.original_face(f) >= 0 && result.original_face(f) < input.face_count(),
           "original_face points into the input");
  }
}

void check_strict(const Mesh& mesh) {
  const CleanupResult strict = cleanup(mesh, {.mode = CleanupMode::strict});
  check_maps(strict, mesh);
  expect(!strict.changed(), "strict cleanup changes nothing");
  expect(strict.mesh.vertices == mesh.vertices && strict.mesh.faces == mesh.faces,
         "strict cleanup returns its input");
  expect((strict.status == Status::ok) == strict.message.empty(),
         "strict cleanup explains exactly its refusals");
}

void check_repair(const Mesh& mesh, double merge_tolerance) {
  const CleanupResult repaired =
      cleanup(mesh, {.mode = CleanupMode::repair, .merge_tolerance = merge_tolerance});
  check_maps(repaired, mesh);
  std::string message;
  expect(check_indices_and_coordinates(repaired.mesh, &message) == Status::ok,
         "repair gives valid indices");
  // Whatever it cannot fix, repair leaves no degenerate or duplicate face and no unused vertex.
  const TopologyReport report = analyze_topology(repaired.mesh);
  expect(report.degenerate_faces.empty(), "repair leaves no degenerate face");
  expect(report.duplicate_faces.empty(), "repair leaves no duplicate face");
  expect(report.unreferenced_vertices.empty(), "repair leaves no unreferenced vertex");
  if (repaired.status != Status::ok) return;
  expect(report.consistently_oriented, "a successful repair orients every component");
  expect(report.non_manifold_edges.empty() && report.non_manifold_vertices.empty(),
         "a successful repair is manifold");
  // Repairing a repaired mesh finds nothing more to do (with exact merging: a tolerance can chain
  // new neighbours once others have gone).
  if (merge_tolerance == 0.0) {
    const CleanupResult again = cleanup(repaired.mesh, {.mode = CleanupMode::repair});
    expect(again.status == Status::ok && !again.changed(), "repair is idempotent");
  }
}

}  // namespace

FindingHandler set_finding_handler(FindingHandler handler) {
  const FindingHandler previous = finding_handler;
  finding_handler = handler;
  return previous;
}

void finding(std::string_view what) {
  if (finding_handler != nullptr) finding_handler(what);
  std::fprintf(stderr, "harmonia fuzz finding: %.*s\n", static_cast<int>(what.size()), what.data());
  std::abort();
}

void check_accepted_mesh(const Mesh& mesh) {
  std::string message;
  expect(check_indices_and_coordinates(mesh, &message) == Status::ok,
         "a parser accepts only valid indices and finite coordinates");
  const TopologyReport report = analyze_topology(mesh);
  expect(report.vertices == mesh.vertex_count() && report.faces == mesh.face_count(),
         "the topology report counts the mesh");
  expect(report.is_disk() == report.disk_problem().empty(), "disk_problem explains is_disk");
  (void)report.is_closed_manifold();
  check_strict(mesh);
  check_repair(mesh, 0.0);
  check_repair(mesh, 1e-3);
}

void parse_and_check(std::string_view contents, const Parser& parse) {
  Mesh mesh;
  try {
    mesh = parse(contents, input_name);
  } catch (const Error& error) {
    expect(error.status() == Status::parse_error, "a parser refuses with parse_error");
    expect(std::string_view(error.what()).starts_with(input_name),
           "a parse error starts with the file's name");
    return;
  }
  check_accepted_mesh(mesh);
}

}  // namespace harmonia::fuzz
