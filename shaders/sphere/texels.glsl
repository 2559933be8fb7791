// The planar solves' vectors and sparse matrices in RGBA32UI storage images, one texel an element
// (passes/sphere/texel_layout.h says how).
#include "common/texel_rows.glsl"

dvec2 dvec2_of(uvec4 t) { return dvec2(packDouble2x32(t.xy), packDouble2x32(t.zw)); }
uvec4 texel_of(dvec2 v) { return uvec4(unpackDouble2x32(v.x), unpackDouble2x32(v.y)); }
// A matrix entry or row texel's double.
double value_of(uvec4 t) { return packDouble2x32(t.zw); }

#define LOAD_VEC(image, i) dvec2_of(imageLoad(image, texel(i)))
#define STORE_VEC(image, i, v) imageStore(image, texel(i), texel_of(v))
