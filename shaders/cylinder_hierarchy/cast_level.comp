#version 460
// A hierarchy level's rays (cast_level.glsl), the lanes of a subgroup voting on when to test triangles.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_vote : require
#define RAYCAST_VOTE 1
#define CAST_LEVEL_ONE 0
#include "cylinder_hierarchy/cast_level.glsl"
