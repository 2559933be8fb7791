#version 460
// Sampling a mesh into a position geometry image: each corner goes to its parameter (s, t) in the
// image (row 0 at t = 1). The fragment stage interpolates the positions itself (sample.frag says why),
// so the vertex stage passes on only which face it drew.
layout(std430, binding = 1) readonly buffer Params { vec2 params[]; };
layout(std430, binding = 2) readonly buffer Triangles { uint triangles[]; };

layout(location = 0) flat out uint face;

void main() {
    const vec2 st = params[triangles[gl_VertexIndex]];
    face = gl_VertexIndex / 3;
    gl_Position = vec4(2.0 * st.x - 1.0, 1.0 - 2.0 * st.y, 0.5, 1.0);
}
