#version 460
// GPU ray casting (raycast.glsl), the lanes of a subgroup voting on when to test triangles.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_vote : require
#define RAYCAST_VOTE 1
#include "raycast/raycast.glsl"
