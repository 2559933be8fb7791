#version 460
// Sampling a mesh into a position geometry image: each corner goes to its parameter (s, t) in the
// image (row 0 at t = 1) and carries its 3D position, interpolated linearly across the triangle.
layout(std430, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, binding = 1) readonly buffer Params { vec2 params[]; };
layout(std430, binding = 2) readonly buffer Triangles { uint triangles[]; };

layout(location = 0) noperspective out vec3 position;

void main() {
    const uint v = triangles[gl_VertexIndex];
    const vec2 st = params[v];
    position = vec3(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
    gl_Position = vec4(2.0 * st.x - 1.0, 1.0 - 2.0 * st.y, 0.5, 1.0);
}
