#version 460
// Large pieces decided by the compute pass: the keys hold every hit.
#extension GL_GOOGLE_include_directive : require
#include "cylinder/atlas_images_body.glsl"
