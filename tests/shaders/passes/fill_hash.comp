#version 460
// values[i] = hash(i) % modulus: deterministic input the CPU can reproduce.
layout(local_size_x = 256) in;
layout(std430, binding = 0) writeonly buffer Values { uint values[]; };
layout(push_constant) uniform Push { uint count; uint modulus; };

uint hash(uint x) {
    x ^= x >> 16; x *= 0x7feb352du;
    x ^= x >> 15; x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < count) values[i] = hash(i) % modulus;
}
