#pragma once
// Internal: the bytes of DejaVu Sans (Debian's fonts-dejavu-core), embedded in the library at build
// time by harmonia_embed_file (cmake/embed_file.cmake), so that PNG pictures get their text without
// a font file at run time. The font's copyright and licence notices travel inside it (its name
// table). Hidden: no application sees these symbols.

#include <cstddef>

namespace harmonia::detail {

[[gnu::visibility("hidden")]] extern const unsigned char dejavu_sans_ttf[];
[[gnu::visibility("hidden")]] extern const std::size_t dejavu_sans_ttf_size;

}  // namespace harmonia::detail
