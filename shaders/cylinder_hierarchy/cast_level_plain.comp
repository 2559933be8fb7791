#version 460
// A hierarchy level's rays (cast_level.glsl) for devices without subgroup votes in compute shaders.
#extension GL_GOOGLE_include_directive : require
#define RAYCAST_VOTE 0
#define CAST_LEVEL_ONE 0
#include "cylinder_hierarchy/cast_level.glsl"
