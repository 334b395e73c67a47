// The one translation unit that compiles stb_image_write (Debian's libstb-dev, a single-header
// library). Its symbols are hidden so that libharmonia does not export them and cannot clash with
// an application's own copy; its warnings are third-party and silenced here only.
//
// The C library headers it uses come first, outside the hidden region: declared inside it, the C
// library's own functions would be taken as hidden too and fail to link.
#include <assert.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wall"
#pragma GCC diagnostic ignored "-Wextra"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC visibility push(hidden)

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

#pragma GCC visibility pop
#pragma GCC diagnostic pop
