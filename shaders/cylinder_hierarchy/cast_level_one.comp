#version 460
// Level 1's rays, the ordinary B x B image (cast_level.glsl), the lanes of a subgroup voting on
// when to test triangles.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_vote : require
#define RAYCAST_VOTE 1
#define CAST_LEVEL_ONE 1
#include "cylinder_hierarchy/cast_level.glsl"
