// Colour maps for scalar fields. viridis: a cubic fit through five of its published anchor
// colours (dark purple, blue, teal, green, yellow). diverging: blue - near white - red for signed
// values in [-1, 1].
vec3 viridis(float t) {
    const vec3 c0 = vec3(0.267, 0.005, 0.329);
    const vec3 c1 = vec3(0.229, 0.322, 0.546);
    const vec3 c2 = vec3(0.128, 0.567, 0.551);
    const vec3 c3 = vec3(0.369, 0.789, 0.383);
    const vec3 c4 = vec3(0.993, 0.906, 0.144);
    const float s = clamp(t, 0.0, 1.0) * 4.0;
    if (s < 1.0) return mix(c0, c1, s);
    if (s < 2.0) return mix(c1, c2, s - 1.0);
    if (s < 3.0) return mix(c2, c3, s - 2.0);
    return mix(c3, c4, s - 3.0);
}

vec3 diverging(float t) {
    const vec3 blue = vec3(0.23, 0.30, 0.75), white = vec3(0.87, 0.87, 0.87), red = vec3(0.71, 0.02, 0.15);
    return t < 0.0 ? mix(white, blue, -t) : mix(white, red, t);
}
