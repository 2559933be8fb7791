#version 460
// Shading for people looking at meshes: a key and a fill light that follow the camera, two-sided
// (open meshes show their back faces), a little specular, optional colour by normal, checker,
// scalar or signed scalar, and an anti-aliased wireframe from barycentric distances.
#extension GL_GOOGLE_include_directive : require
#include "render/render_params.h"
#include "render/colormaps.h"

layout(push_constant) uniform Push {
    mat4 view_projection;
    vec4 eye;
    vec4 scalar_range;
    uint color_mode;
    uint flags;
};

layout(location = 0) in vec3 world;
layout(location = 1) in vec3 normal_in;
layout(location = 2) in vec3 barycentric;
layout(location = 3) in float scalar;
layout(location = 4) in vec2 texcoord;
layout(location = 0) out vec4 color;

vec3 base_color(vec3 n) {
    if (color_mode == GIMG_COLOR_NORMAL) return 0.5 * n + 0.5;
    if (color_mode == GIMG_COLOR_CHECKER) {
        // Texture coordinates when the mesh has them, else a 3D checker in space.
        const float s = scalar_range.z;
        const bool odd = (flags & GIMG_RENDER_HAS_TEXCOORDS) != 0u
                             ? (int(floor(texcoord.x * s)) + int(floor(texcoord.y * s))) % 2 != 0
                             : (int(floor(world.x * s)) + int(floor(world.y * s)) + int(floor(world.z * s))) % 2 != 0;
        return odd ? vec3(0.93, 0.45, 0.20) : vec3(0.95, 0.93, 0.88);
    }
    const float t = (scalar - scalar_range.x) / max(scalar_range.y - scalar_range.x, 1e-20);
    if (color_mode == GIMG_COLOR_SCALAR) return viridis(clamp(t, 0.0, 1.0));
    if (color_mode == GIMG_COLOR_DIVERGING) return diverging(clamp(2.0 * t - 1.0, -1.0, 1.0));
    return vec3(0.72, 0.76, 0.82);
}

void main() {
    vec3 n = normalize(normal_in);
    const vec3 to_eye = normalize(eye.xyz - world);
    if (dot(n, to_eye) < 0.0) n = -n;  // two-sided
    // Lights in camera-relative directions so every view is lit the same way.
    const vec3 forward = -to_eye;
    const vec3 right = normalize(cross(forward, vec3(0.0, 1.0, 0.0) + vec3(1e-6, 0.0, 0.0)));
    const vec3 up = cross(right, forward);
    const vec3 key = normalize(-forward + 0.6 * up - 0.5 * right);
    const vec3 fill = normalize(-forward - 0.3 * up + 0.8 * right);
    const vec3 albedo = base_color(n);
    const float diffuse = 0.75 * max(dot(n, key), 0.0) + 0.25 * max(dot(n, fill), 0.0);
    const float specular = 0.18 * pow(max(dot(n, normalize(key + to_eye)), 0.0), 40.0);
    vec3 c = pow(clamp(albedo * (0.22 + 0.85 * diffuse) + vec3(specular), 0.0, 1.0), vec3(1.0 / 2.2));
    if ((flags & GIMG_RENDER_WIREFRAME) != 0u) {
        // Blended after gamma so the lines stay dark.
        const vec3 width = fwidth(barycentric) * scalar_range.w;
        const vec3 edge = smoothstep(0.5 * width, width, barycentric);
        const float line = 1.0 - min(min(edge.x, edge.y), edge.z);
        c = mix(c, vec3(0.10, 0.12, 0.16), 0.8 * line);
    }
    color = vec4(c, 1.0);
}
