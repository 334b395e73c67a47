// The arithmetic type of every kernel. Each shader is compiled twice (cmake/vulkan.cmake): as is,
// in fp32, and with HARMONIA_FP64 defined, in fp64 for devices with shaderFloat64 enabled
// (DevicePrecision::float64). Buffers of reals hold 4- or 8-byte values accordingly; push
// constants and index buffers are the same in both.
#ifdef HARMONIA_FP64
#define real double
#define real2 dvec2
#define real3 dvec3
#define real2x2 dmat2
// +infinity (the marker of degenerate triangles in shaders/triangle_tensors.comp).
real real_infinity() { return packDouble2x32(uvec2(0u, 0x7ff00000u)); }
#else
#define real float
#define real2 vec2
#define real3 vec3
#define real2x2 mat2
real real_infinity() { return uintBitsToFloat(0x7f800000u); }
#endif
