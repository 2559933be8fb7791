// A hierarchy level's rays in one pass, one invocation a launch (cast_launches.comp with subgroup
// votes, cast_launches_plain.comp without), with the CPU encoder's rules
// (passes/cylinder_hierarchy/ray_rules.h) and arithmetic:
//  - a launch at radius r > 0 (or r = 0): its parity segment from the wall, (x / r, y, z / r) (or
//    (1, y, 0)), to the launch point, then the nearest hit in [-behind, t_max] along the outward
//    normal if the crossings are odd (inside), against it if even; the value is t along the
//    outward normal;
//  - a radial launch (r < 0): the ordinary image's ray from the axis, (0, y, 0) along the normal,
//    front faces only, t in [-1, 1]; the value is 1 + t, the distance from the wall.
// Status: 0 nothing hit, 1 hit, 2 more crossings than the walk keeps (the host casts that one).
layout(local_size_x = 64) in;

layout(binding = 0, rgba32ui) uniform readonly uimage2D node_texels;
layout(binding = 1, rgba32ui) uniform readonly uimage2D corner_texels;
layout(std430, binding = 2) readonly buffer Faces { uint face_of[]; };  // slot -> face
// 8 per launch: the launch point, r (its distance from the axis, < 0 for radial launches), the
// outward normal (for radial launches the ray's direction), t_max.
layout(std430, binding = 3) readonly buffer Launches { double launch[]; };
layout(std430, binding = 4) writeonly buffer Values { double value[]; };
layout(std430, binding = 5) writeonly buffer Status { uint status[]; };
layout(push_constant) uniform Push {
    uint count;
    float scene;   // the largest |coordinate| of the tree's boxes
    double behind;  // ray_rules.h's kBehind
};

#include "raycast/walk.glsl"

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    const dvec3 p = dvec3(launch[8 * i], launch[8 * i + 1], launch[8 * i + 2]);
    const double r = launch[8 * i + 3];
    const dvec3 n = dvec3(launch[8 * i + 4], launch[8 * i + 5], launch[8 * i + 6]);
    uint face;
    if (r < 0.0LF) {
        const double t = nearest_hit(dvec3(0.0LF, p.y, 0.0LF), n, -1.0LF, 1.0LF, true, scene, face);
        precise double from_wall = 1.0LF + t;
        value[i] = from_wall;
        status[i] = face == kNone ? 0u : 1u;
        return;
    }
    precise dvec3 wall = r > 0.0LF ? dvec3(p.x / r, p.y, p.z / r) : dvec3(1.0LF, p.y, 0.0LF);
    precise dvec3 segment = p - wall;
    const uint crossings = crossings_of(wall, segment, 0.0LF, 1.0LF, scene);
    if (crossings == kNone) {
        status[i] = 2u;
        return;
    }
    const bool inside = crossings % 2u == 1u;
    const double t = nearest_hit(p, inside ? n : -n, -behind, launch[8 * i + 7], false, scene, face);
    value[i] = inside ? t : -t;
    status[i] = face == kNone ? 0u : 1u;
}
