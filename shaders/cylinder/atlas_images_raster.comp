#version 460
// Large pieces decided by the graphics pipeline: its t per atlas pixel joins the keys.
#define RASTER_T
#extension GL_GOOGLE_include_directive : require
#include "cylinder/atlas_images_body.glsl"
