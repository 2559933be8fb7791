// The planar solves' vectors and sparse matrices in storage images, one texel an element
// (passes/solvers/matrix_texels.h says how): the conjugate gradients' dvec2 in RGBA32UI, the
// multigrid cycle's vec2 in RG32F, matrix rows in RGBA32UI, entries in RGBA32UI (double) or
// RG32UI (float).
#include "common/texel_array.glsl"

dvec2 dvec2_of(uvec4 t) { return dvec2(packDouble2x32(t.xy), packDouble2x32(t.zw)); }
uvec4 texel_of(dvec2 v) { return uvec4(unpackDouble2x32(v.x), unpackDouble2x32(v.y)); }
// A double matrix entry or row texel's double.
double value_of(uvec4 t) { return packDouble2x32(t.zw); }
// A float matrix entry's value.
float float_value_of(uvec2 t) { return uintBitsToFloat(t.y); }

#define LOAD_VEC(image, i) dvec2_of(imageLoad(image, texel(i)))
#define STORE_VEC(image, i, v) imageStore(image, texel(i), texel_of(v))
#define LOAD_VEC32(image, i) imageLoad(image, texel(i)).xy
#define STORE_VEC32(image, i, v) imageStore(image, texel(i), vec4(v, 0.0, 0.0))
