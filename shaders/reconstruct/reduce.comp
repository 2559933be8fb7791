#version 460
// Level of detail: each output pixel the mean of its 2x2 children when all four are valid, else
// empty (NaN): valid and empty never mix. `channels` floats per pixel (1: d, 3: xyz);
// (a + b) + (c + d), then a quarter, as the CPU reference adds them.
layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer Src { float src[]; };
layout(std430, binding = 1) writeonly buffer Dst { float dst[]; };
layout(push_constant) uniform Push { uint width; uint height; uint channels; };  // of the output

void main() {
    const uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= width || p.y >= height) return;
    const uint w = 2u * width;
    const uint i[4] = uint[4](2u * p.y * w + 2u * p.x, 2u * p.y * w + 2u * p.x + 1u, (2u * p.y + 1u) * w + 2u * p.x,
                              (2u * p.y + 1u) * w + 2u * p.x + 1u);
    const uint o = p.y * width + p.x;
    bool all_valid = true;
    for (int k = 0; k < 4; ++k) all_valid = all_valid && !isnan(src[channels * i[k]]);
    for (uint c = 0; c < channels; ++c) {
        const float sum = (src[channels * i[0] + c] + src[channels * i[1] + c]) +
                          (src[channels * i[2] + c] + src[channels * i[3] + c]);
        dst[channels * o + c] = all_valid ? 0.25 * sum : uintBitsToFloat(0x7fc00000u);
    }
}
