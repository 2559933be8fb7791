#version 460
// Retrieval features on the GPU: each cylindrical image (add_cylinder's float buffer, NaN where
// empty, counted as 0) reduced by the separable cubic kernel of reduce_cylinder_image, whose taps
// (input index and normalised weight, `taps` a output, 0 weights padding) the host computes once:
// circular in theta (u), clamped in height (v).
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, binding = 0) readonly buffer Images { float images[]; };  // count x size x size
layout(std430, binding = 1) readonly buffer TapsU { vec2 taps_u[]; };    // (index bits, weight)
layout(std430, binding = 2) readonly buffer TapsV { vec2 taps_v[]; };
layout(std430, binding = 3) writeonly buffer Features { float features[]; };  // count x reduced x reduced
layout(push_constant) uniform Push {
    uint size, reduced, count, taps;
};

void main() {
    const uvec3 p = gl_GlobalInvocationID;
    if (p.x >= reduced || p.y >= reduced || p.z >= count) return;
    const uint base = p.z * size * size;
    float sum = 0.0;
    for (uint j = 0u; j < taps; ++j) {
        const vec2 tv = taps_v[p.y * taps + j];
        if (tv.y == 0.0) continue;
        const uint v = floatBitsToUint(tv.x);
        float row = 0.0;
        for (uint i = 0u; i < taps; ++i) {
            const vec2 tu = taps_u[p.x * taps + i];
            if (tu.y == 0.0) continue;
            const float d = images[base + v * size + floatBitsToUint(tu.x)];
            row += tu.y * (isnan(d) ? 0.0 : d);
        }
        sum += tv.y * row;
    }
    features[(p.z * reduced + p.y) * reduced + p.x] = sum;
}
