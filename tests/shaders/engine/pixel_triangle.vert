#version 460
// Vertex pulling: positions in pixel coordinates (origin top-left, y down), converted to NDC.
layout(std430, binding = 0) readonly buffer Positions { vec2 positions[]; };
layout(push_constant) uniform Push { vec2 extent; };

void main() {
    vec2 p = positions[gl_VertexIndex];
    gl_Position = vec4(p / extent * 2.0 - 1.0, 0.5, 1.0);
}
