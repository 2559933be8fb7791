#version 460
// dst[i] = src[i] * scale + offset.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Src { float src[]; };
layout(std430, binding = 1) writeonly buffer Dst { float dst[]; };
layout(push_constant) uniform Push { uint count; float scale; float offset; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < count) dst[i] = src[i] * scale + offset;
}
