// The targets that take files as they come (a mutated binary body rarely survives a mutated
// header, so they reach the text readers mostly; the binary targets reach the rest).
#include "fuzz/fuzz_targets.h"

#include <array>
#include <string_view>

#include "fuzz/fuzz_checks.h"
#include "harmonia/mesh.h"
#include "io/mesh_parsers.h"

namespace harmonia::fuzz {
namespace {

std::string_view as_text(Bytes input) {
  return {reinterpret_cast<const char*>(input.data()), input.size()};
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

std::span<const FuzzTarget> fuzz_targets() {
  static constexpr std::array targets = {
      FuzzTarget{"obj", fuzz_obj}, FuzzTarget{"off", fuzz_off},
      FuzzTarget{"ply", fuzz_ply}, FuzzTarget{"ply_binary", fuzz_ply_binary},
      FuzzTarget{"stl", fuzz_stl}, FuzzTarget{"stl_binary", fuzz_stl_binary}};
  return targets;
}

}  // namespace harmonia::fuzz
