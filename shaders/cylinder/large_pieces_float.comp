#version 460
// Single precision, for devices without shaderFloat64 (with a watertight test: line_hit.glsl says why).
#define REAL float
#define LINE_HIT_WATERTIGHT 1
#define REAL2 vec2
#define REAL3 vec3
#define REAL4 vec4
#define REAL2_OF_TEXEL(t) uintBitsToFloat(t.xy)  // a direction texel: cos bits, sin bits
#extension GL_GOOGLE_include_directive : require
#include "cylinder/large_pieces_body.glsl"
