#version 460
// GPU ray casting (raycast.glsl), the lanes of a subgroup voting on when to test triangles.
#define RAYCAST_VOTE 1
#extension GL_GOOGLE_include_directive : require
#include "raycast/raycast.glsl"
