// Distances as ordered keys, so that a 32-bit atomicMax keeps the largest t: a larger float gets a
// larger key. Key 0 belongs to no distance in [-1, 1] (it would be a NaN) and means "no hit".
uint distance_key(float d) {
    const uint b = floatBitsToUint(d);
    return (b & 0x80000000u) != 0u ? ~b : b | 0x80000000u;
}

float key_distance(uint k) { return uintBitsToFloat((k & 0x80000000u) != 0u ? k & 0x7fffffffu : ~k); }
