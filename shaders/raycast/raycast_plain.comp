#version 460
// GPU ray casting (raycast.glsl) for devices without subgroup votes in compute shaders.
#define RAYCAST_VOTE 0
#extension GL_GOOGLE_include_directive : require
#include "raycast/raycast.glsl"
