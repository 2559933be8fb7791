#version 460
// Double precision (devices with shaderFloat64): agrees with the CPU ray caster to rounding.
#define REAL double
#define REAL2 dvec2
#define REAL3 dvec3
#define REAL4 dvec4
#define REAL2_OF_TEXEL(t) dvec2(packDouble2x32(t.xy), packDouble2x32(t.zw))  // a direction texel: cos bits, sin bits
#extension GL_GOOGLE_include_directive : require
#include "cylinder/large_pieces_body.glsl"
