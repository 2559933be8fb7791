#version 460
// One Jacobi step of 1D diffusion with fixed ends: dst[i] = src[i] + alpha (src[i-1] - 2 src[i] + src[i+1]).
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Src { float src[]; };
layout(std430, binding = 1) writeonly buffer Dst { float dst[]; };
layout(push_constant) uniform Push { uint count; float alpha; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    if (i == 0 || i == count - 1) {
        dst[i] = src[i];
        return;
    }
    float l = src[i - 1], c = src[i], r = src[i + 1];
    dst[i] = c + alpha * ((l - c) + (r - c));
}
