#version 460
// Level 1's rays, the ordinary B x B image (cast_level.glsl), for devices without subgroup votes in
// compute shaders.
#extension GL_GOOGLE_include_directive : require
#define RAYCAST_VOTE 0
#define CAST_LEVEL_ONE 1
#include "cylinder_hierarchy/cast_level.glsl"
