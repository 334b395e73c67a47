#pragma once
// Internal: the files of a view page (view_page.cpp), embedded in the library at build time by
// harmonia_embed_file (cmake/embed_file.cmake): three.js and its orbit controls from Debian's
// libjs-three (MIT licence; view_page.cpp writes its notice beside it), and the page's own
// template, script and style from host/picture/view/. Hidden: no application sees these symbols.

#include <cstddef>

namespace harmonia::detail {

[[gnu::visibility("hidden")]] extern const unsigned char three_min_js[];
[[gnu::visibility("hidden")]] extern const std::size_t three_min_js_size;
[[gnu::visibility("hidden")]] extern const unsigned char orbit_controls_js[];
[[gnu::visibility("hidden")]] extern const std::size_t orbit_controls_js_size;
[[gnu::visibility("hidden")]] extern const unsigned char viewer_js[];
[[gnu::visibility("hidden")]] extern const std::size_t viewer_js_size;
[[gnu::visibility("hidden")]] extern const unsigned char viewer_css[];
[[gnu::visibility("hidden")]] extern const std::size_t viewer_css_size;
[[gnu::visibility("hidden")]] extern const unsigned char view_page_html[];
[[gnu::visibility("hidden")]] extern const std::size_t view_page_html_size;

}  // namespace harmonia::detail
