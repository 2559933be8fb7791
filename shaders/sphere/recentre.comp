#version 460
// Moves the mass centre c of the points towards the sphere's centre by the Moebius transformation
// T_a(x) = (1 - |a|^2)(x - a) / |x - a|^2 - a, a = scale * c with |a| <= 1/2 (moebius_move in
// passes/sphere/sphere_steps.h). It is conformal, so it adds no angle distortion (Gu's
// normalize(y - c) does). It writes a separate buffer: the host keeps the result only if it
// flipped nothing, and halves the scale otherwise.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Points { dvec4 pos[]; };
layout(std430, binding = 1) readonly buffer Sums { double sums[]; };  // level_stats, reduced
layout(std430, binding = 2) readonly buffer Control { double scale; };
layout(std430, binding = 3) writeonly buffer Moved { dvec4 moved[]; };
layout(push_constant) uniform Push { uint vertex_count; };

void main() {
    const uint v = gl_GlobalInvocationID.x;
    if (v >= vertex_count) return;
    dvec3 a = scale * dvec3(sums[0], sums[1], sums[2]) / double(vertex_count);
    if (length(a) > 0.5LF) a *= 0.5LF / length(a);
    const dvec3 d = pos[v].xyz - a;
    const dvec3 y = normalize((1.0LF - dot(a, a)) * d / dot(d, d) - a);
    moved[v] = dvec4(y, 0.0LF);
}
