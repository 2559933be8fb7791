// Arrays kept in storage images, one texel an element, 4,096 texels a row
// (gimg/engine/texel_array.h says why: lavapipe gathers from images, and loads from storage buffers
// lane by lane): element i is texel (i mod 4096, i / 4096).
#ifndef GIMG_TEXEL_ARRAY_GLSL
#define GIMG_TEXEL_ARRAY_GLSL
const uint kRowShift = 12u;

ivec2 texel(uint i) { return ivec2(i & ((1u << kRowShift) - 1u), i >> kRowShift); }
#endif
