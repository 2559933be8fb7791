#version 460
// Vertex pulling for the mesh renderer: one invocation per triangle corner (draw 3 * faces
// vertices, no index buffer), so each corner knows its barycentric coordinate (wireframe) and the
// face normal (flat shading) without a geometry shader.
#extension GL_GOOGLE_include_directive : require
#include "render/render_params.h"

layout(std430, binding = 0) readonly buffer Positions { float positions[]; };  // xyz per vertex
layout(std430, binding = 1) readonly buffer Triangles { uint triangles[]; };   // 3 per face
layout(std430, binding = 2) readonly buffer Normals { float normals[]; };      // xyz per vertex (smooth)
layout(std430, binding = 3) readonly buffer Scalars { float scalars[]; };      // per vertex
layout(std430, binding = 4) readonly buffer Texcoords { vec2 texcoords[]; };   // per vertex

layout(push_constant) uniform Push {
    mat4 view_projection;
    vec4 eye;           // camera position, w unused
    vec4 scalar_range;  // x = min, y = max, z = checker scale, w = wire width (pixels)
    uint color_mode;
    uint flags;
};

layout(location = 0) out vec3 world;
layout(location = 1) out vec3 normal;
layout(location = 2) out vec3 barycentric;
layout(location = 3) out float scalar;
layout(location = 4) out vec2 texcoord;

vec3 position(uint v) { return vec3(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]); }

void main() {
    const uint face = gl_VertexIndex / 3, corner = gl_VertexIndex % 3;
    const uint a = triangles[3 * face], b = triangles[3 * face + 1], c = triangles[3 * face + 2];
    const uint v = corner == 0 ? a : (corner == 1 ? b : c);
    world = position(v);
    if ((flags & GIMG_RENDER_SMOOTH) != 0u) {
        normal = vec3(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]);
    } else {
        const vec3 n = cross(position(b) - position(a), position(c) - position(a));
        normal = dot(n, n) > 0.0 ? normalize(n) : vec3(0.0, 0.0, 1.0);
    }
    barycentric = vec3(corner == 0 ? 1.0 : 0.0, corner == 1 ? 1.0 : 0.0, corner == 2 ? 1.0 : 0.0);
    scalar = color_mode == GIMG_COLOR_SCALAR || color_mode == GIMG_COLOR_DIVERGING ? scalars[v] : 0.0;
    texcoord = (flags & GIMG_RENDER_HAS_TEXCOORDS) != 0u ? texcoords[v] : vec2(0.0);
    gl_Position = view_projection * vec4(world, 1.0);
}
