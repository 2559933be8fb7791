#version 460
// The position at this pixel's centre, from barycentric weights computed here in the image's pixel
// units (x = s N, y = (1 - t) N), as the CPU twin computes them. Hardware attribute interpolation is
// only required to be roughly float-accurate and misses 1e-6 on some GPUs (NVIDIA: 1.4e-6 on a unit
// grid at N = 64); this is within a few float roundings everywhere.
layout(std430, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, binding = 1) readonly buffer Params { vec2 params[]; };
layout(std430, binding = 2) readonly buffer Triangles { uint triangles[]; };
layout(push_constant) uniform Push { float size; };

layout(location = 0) flat in uint face;
layout(location = 0) out vec4 color;  // xyz, and 1 for covered

vec3 position_of(uint v) { return vec3(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]); }
vec2 pixel_of(uint v) { return vec2(params[v].x * size, (1.0 - params[v].y) * size); }

void main() {
    const uint a = triangles[3 * face], b = triangles[3 * face + 1], c = triangles[3 * face + 2];
    // Corners relative to the pixel centre, so each edge function is one small cross product.
    const vec2 pa = pixel_of(a) - gl_FragCoord.xy, pb = pixel_of(b) - gl_FragCoord.xy, pc = pixel_of(c) - gl_FragCoord.xy;
    const float ea = pb.x * pc.y - pb.y * pc.x, eb = pc.x * pa.y - pc.y * pa.x, ec = pa.x * pb.y - pa.y * pb.x;
    const vec3 w = vec3(ea, eb, ec) / (ea + eb + ec);
    color = vec4(w.x * position_of(a) + w.y * position_of(b) + w.z * position_of(c), 1.0);
}
