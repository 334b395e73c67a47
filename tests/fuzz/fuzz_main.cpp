// The libFuzzer entry point of one target, chosen when compiling: -DHARMONIA_FUZZ_TARGET=fuzz_obj
// makes the program fuzz_obj (tests/fuzz/CMakeLists.txt).
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  harmonia::fuzz::HARMONIA_FUZZ_TARGET({data, size});
  return 0;
}
