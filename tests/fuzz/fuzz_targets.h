#pragma once
// The fuzz targets: one per reader, each taking arbitrary bytes and running them through the
// parser and, when it accepts, through fuzz_checks.h. fuzz_main.cpp makes each a libFuzzer
// program (.ci/fuzz runs them); tests/io/test_fuzz_regressions.cpp replays the seed corpus and
// every past finding through the same targets in the ordinary test suite.

#include <cstdint>
#include <span>
#include <string_view>

namespace harmonia::fuzz {

using Bytes = std::span<const std::uint8_t>;

//! Files as they come: OBJ (as a mesh and with texture coordinates), OFF, PLY, STL.
void fuzz_obj(Bytes input);
void fuzz_off(Bytes input);
void fuzz_ply(Bytes input);
void fuzz_stl(Bytes input);
//! Binary bodies behind a header the first bytes choose (fuzz_ply_binary.cpp, fuzz_stl_binary.cpp).
void fuzz_ply_binary(Bytes input);
void fuzz_stl_binary(Bytes input);
//! glTF 2.0 (.gltf or .glb) read from memory, external files refused (harmonia/gltf.h): an accepted
//! document's scene triangles, summary and meshes are checked, and one with triangles is given
//! texture coordinates, written as GLB and read back (fuzz_targets.cpp).
void fuzz_gltf(Bytes input);

struct FuzzTarget {
  std::string_view name;  //!< As in tests/fuzz/corpus/NAME and the program fuzz_NAME.
  void (*run)(Bytes input);
};

//! Every target, in the order above.
[[nodiscard]] std::span<const FuzzTarget> fuzz_targets();

}  // namespace harmonia::fuzz
