// The targets that take files as they come (a mutated binary body rarely survives a mutated
// header, so they reach the text readers mostly; the binary targets reach the rest), and glTF
// documents as they come, read, summarized, given texture coordinates and written back.
#include "fuzz/fuzz_targets.h"

#include <unistd.h>

#include <array>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <typeinfo>
#include <vector>

#include "fuzz/fuzz_checks.h"
#include "harmonia/gltf.h"
#include "harmonia/mesh.h"
#include "harmonia/topology.h"
#include "harmonia/types.h"
#include "io/mesh_parsers.h"

namespace harmonia::fuzz {
namespace {

std::string_view as_text(Bytes input) {
  return {reinterpret_cast<const char*>(input.data()), input.size()};
}

void expect(bool promise_kept, std::string_view what) {
  if (!promise_kept) finding(what);
}

// Runs one step of the glTF target; true when it returned, false when it refused as glTF code may
// (harmonia::Error with parse_error, unsupported or invalid_input, and a reading step's message
// naming the file). Any other exception is a finding.
template <typename Step>
bool gltf_step(std::string_view step, bool reading, Step&& run) {
  try {
    run();
    return true;
  } catch (const Error& error) {
    const Status status = error.status();
    expect(status == Status::parse_error || status == Status::unsupported ||
               status == Status::invalid_input,
           std::string(step) + " refuses with parse_error, unsupported or invalid_input: " +
               error.what());
    expect(!reading || std::string_view(error.what()).starts_with(input_name),
           std::string(step) + " names the file when it refuses: " + error.what());
    return false;
  } catch (const std::exception& error) {
    finding(std::string(step) + " refuses only with harmonia::Error, not " +
            typeid(error).name() + ": " + error.what());
  }
}

// What GltfTriangles promises: a mesh with valid indices and finite coordinates (with `full`, also
// the topology report and both cleanups of check_accepted_mesh), and parts that follow one another,
// each one's triangles on its own vertices, with one increasing source triangle per face.
void check_gltf_triangles(const GltfTriangles& triangles, bool full) {
  const Mesh& mesh = triangles.mesh;
  if (full) {
    check_accepted_mesh(mesh);
  } else {
    std::string message;
    expect(check_indices_and_coordinates(mesh, &message) == Status::ok,
           "glTF triangles have valid indices and finite coordinates");
  }
  Eigen::Index vertex = 0, face = 0;
  for (const GltfPart& part : triangles.parts) {
    expect(part.first_vertex == vertex && part.vertex_count >= 0 && part.first_face == face &&
               part.face_count >= 0 && part.first_face + part.face_count <= mesh.face_count(),
           "the parts of glTF triangles follow one another");
    expect(part.source_triangle.size() == static_cast<std::size_t>(part.face_count),
           "a glTF part has a source triangle per face");
    for (int local = 0; local < part.face_count; ++local) {
      for (int corner = 0; corner < 3; ++corner) {
        const int index = mesh.faces(part.first_face + local, corner);
        expect(index >= part.first_vertex && index < part.first_vertex + part.vertex_count,
               "a glTF part's triangles use its own vertices");
      }
      const int source = part.source_triangle[static_cast<std::size_t>(local)];
      expect(source >= 0 && (local == 0 || source > part.source_triangle[static_cast<std::size_t>(local) - 1]),
             "a glTF part's source triangles increase");
    }
    vertex += part.vertex_count;
    face += part.face_count;
  }
  expect(vertex == mesh.vertex_count() && face == mesh.face_count(),
         "the parts of glTF triangles cover the mesh");
}

// The summary counts what scene_triangles reads: each triangle primitive's triangles, once per
// instance in the default scene (once per mesh when there is no scene).
void check_gltf_summary(const GltfDocument& document, const GltfSummary& summary,
                        const GltfTriangles& scene) {
  expect(summary.meshes.size() == static_cast<std::size_t>(document.mesh_count()),
         "a glTF summary has every mesh");
  expect(summary.default_scene >= -1 && summary.default_scene < summary.scenes,
         "a glTF summary's default scene is one of its scenes");
  std::int64_t faces = 0;
  for (const GltfMeshSummary& mesh : summary.meshes) {
    std::int64_t mesh_faces = 0;
    for (const GltfPrimitiveSummary& primitive : mesh.primitives) {
      expect(primitive.mode >= 0 && primitive.mode <= 6 && primitive.vertices >= 0 &&
                 primitive.triangles >= 0,
             "a glTF summary counts its primitives");
      mesh_faces += primitive.triangles;
    }
    faces += mesh_faces * (summary.default_scene >= 0 ? mesh.instances : 1);
  }
  expect(faces == scene.mesh.face_count(), "a glTF summary counts the scene's triangles");
}

// Where the glTF target writes: a file of its own process, in memory where /dev/shm exists (the
// writer syncs every file), removed after each reading back.
const std::filesystem::path& gltf_scratch_file() {
  static const std::filesystem::path path = [] {
    std::error_code error;
    const std::filesystem::path folder = std::filesystem::is_directory("/dev/shm", error)
                                             ? std::filesystem::path("/dev/shm")
                                             : std::filesystem::temp_directory_path();
    return folder / ("harmonia-fuzz-gltf-" + std::to_string(::getpid()) + ".glb");
  }();
  return path;
}

// A per-corner layout that splits some vertices (each corner's u is its number in the face) and
// two charts.
std::vector<GltfPrimitiveUpdate> trivial_texcoord_updates(const GltfTriangles& triangles) {
  const Eigen::Index faces = triangles.mesh.face_count();
  Eigen::Matrix<double, Eigen::Dynamic, 6> corner_uv(faces, 6);
  std::vector<int> chart_of_face(static_cast<std::size_t>(faces));
  for (Eigen::Index f = 0; f < faces; ++f) {
    corner_uv.row(f) << 0.0, 0.0, 0.5, 0.0, 1.0, 0.0;
    chart_of_face[static_cast<std::size_t>(f)] = static_cast<int>(f % 2);
  }
  return texcoord_updates(triangles, corner_uv, chart_of_face);
}

// Each corner of `written` at the position of the same corner of `read`.
bool same_corners(const Mesh& written, const Mesh& read) {
  if (written.face_count() != read.face_count()) return false;
  for (Eigen::Index f = 0; f < written.face_count(); ++f) {
    for (int corner = 0; corner < 3; ++corner) {
      if (written.vertices.row(written.faces(f, corner)) != read.vertices.row(read.faces(f, corner))) {
        return false;
      }
    }
  }
  return true;
}

// Gives the document's triangles new texture coordinates and writes it as GLB: the file must read
// back with the same triangles (texture coordinates split vertices but move no corner).
void write_and_read_back(const GltfDocument& document, const GltfTriangles& scene) {
  const GltfTriangles* triangles = &scene;
  std::optional<GltfTriangles> each_mesh;
  std::vector<GltfPrimitiveUpdate> updates;
  if (!gltf_step("texcoord_updates", false, [&] { updates = trivial_texcoord_updates(scene); })) {
    // A mesh placed by several nodes: one layout per mesh instead (`harmonia atlas` on a scene).
    if (!gltf_step("all_mesh_triangles", true, [&] { each_mesh = all_mesh_triangles(document); })) {
      return;
    }
    check_gltf_triangles(*each_mesh, false);
    if (!gltf_step("texcoord_updates", false,
                   [&] { updates = trivial_texcoord_updates(*each_mesh); })) {
      return;
    }
    triangles = &*each_mesh;
  }
  const std::filesystem::path& path = gltf_scratch_file();
  if (!gltf_step("write_gltf", false, [&] { write_gltf(path, document, updates); })) return;
  std::string problem;
  try {
    const GltfDocument read = GltfDocument::read(path);
    const GltfTriangles again = each_mesh ? all_mesh_triangles(read) : read.scene_triangles();
    check_gltf_triangles(again, false);
    if (!same_corners(triangles->mesh, again.mesh)) problem = "its triangles changed";
  } catch (const std::exception& error) {
    problem = error.what();
  }
  std::error_code error;
  std::filesystem::remove(path, error);
  expect(problem.empty(), "a glTF file written from an accepted one reads back: " + problem);
}

}  // namespace

void fuzz_obj(Bytes input) {
  parse_and_check(as_text(input), detail::parse_obj);
  // The textured reading accepts a subset (every face needs texture indices), and its texture
  // triangles must point into its texture coordinates.
  parse_and_check(as_text(input), [](std::string_view text, std::string_view name) {
    const TexturedMesh textured = detail::parse_textured_obj(text, name);
    if (textured.uv_faces.rows() != textured.mesh.face_count()) {
      finding("a textured OBJ has one texture triangle per face");
    }
    if (textured.uv_faces.size() > 0 &&
        (textured.uv_faces.minCoeff() < 0 || textured.uv_faces.maxCoeff() >= textured.uv.rows())) {
      finding("texture indices point into the texture coordinates");
    }
    return textured.mesh;
  });
}

void fuzz_off(Bytes input) { parse_and_check(as_text(input), detail::parse_off); }
void fuzz_ply(Bytes input) { parse_and_check(as_text(input), detail::parse_ply); }
void fuzz_stl(Bytes input) { parse_and_check(as_text(input), detail::parse_stl); }

void fuzz_gltf(Bytes input) {
  std::optional<GltfDocument> document;
  if (!gltf_step("GltfDocument::parse", true,
                 [&] { document = GltfDocument::parse(as_text(input), input_name, {}); })) {
    return;
  }
  GltfTriangles scene;
  if (!gltf_step("scene_triangles", true, [&] { scene = document->scene_triangles(); })) return;
  check_gltf_triangles(scene, true);
  GltfSummary summary;
  if (gltf_step("summary", true, [&] { summary = document->summary(); })) {
    check_gltf_summary(*document, summary, scene);
  }
  GltfTriangles each_mesh;
  if (gltf_step("all_mesh_triangles", true, [&] { each_mesh = all_mesh_triangles(*document); })) {
    check_gltf_triangles(each_mesh, false);
  }
  if (scene.mesh.face_count() > 0) write_and_read_back(*document, scene);
}

std::span<const FuzzTarget> fuzz_targets() {
  static constexpr std::array targets = {
      FuzzTarget{"obj", fuzz_obj}, FuzzTarget{"off", fuzz_off},
      FuzzTarget{"ply", fuzz_ply}, FuzzTarget{"ply_binary", fuzz_ply_binary},
      FuzzTarget{"stl", fuzz_stl}, FuzzTarget{"stl_binary", fuzz_stl_binary},
      FuzzTarget{"gltf", fuzz_gltf}};
  return targets;
}

}  // namespace harmonia::fuzz
