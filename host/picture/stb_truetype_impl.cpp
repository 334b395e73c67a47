// The one translation unit that compiles stb_truetype (Debian's libstb-dev, a single-header
// library), which rasterizes the text of PNG pictures. As with stb_image_write_impl.cpp its symbols
// are hidden, so that libharmonia does not export them and cannot clash with an application's own
// copy, and its warnings are third-party and silenced here only. The C library headers it uses come
// first, outside the hidden region.
#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wall"
#pragma GCC diagnostic ignored "-Wextra"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC visibility push(hidden)

#define STB_TRUETYPE_IMPLEMENTATION
#include <stb_truetype.h>

#pragma GCC visibility pop
#pragma GCC diagnostic pop
