// Rays through a mesh, one invocation a ray (raycast.comp with subgroup votes, raycast_plain.comp
// without). Two modes: 0 nearest (t and face, t_max and kNone where nothing is hit), 1 crossings.
layout(local_size_x = 64) in;

layout(binding = 0, rgba32ui) uniform readonly uimage2D node_texels;
layout(binding = 1, rgba32ui) uniform readonly uimage2D corner_texels;
layout(std430, binding = 2) readonly buffer Faces { uint face_of[]; };  // slot -> face
layout(std430, binding = 3) readonly buffer Rays { double ray[]; };     // 8 per ray: o, d, t_min, t_max
layout(std430, binding = 4) writeonly buffer HitT { double hit_t[]; };
layout(std430, binding = 5) writeonly buffer HitFace { uint hit_face[]; };  // face, or the crossings
layout(push_constant) uniform Push {
    uint count;
    uint mode;
    uint front_faces_only;
    float scene;  // the largest |coordinate| of the tree's boxes
};

#include "raycast/walk.glsl"

void main() {
    const uint r = gl_GlobalInvocationID.x;
    if (r >= count) return;
    const dvec3 o = dvec3(ray[8 * r], ray[8 * r + 1], ray[8 * r + 2]);
    const dvec3 d = dvec3(ray[8 * r + 3], ray[8 * r + 4], ray[8 * r + 5]);
    const double t_min = ray[8 * r + 6], t_max = ray[8 * r + 7];
    if (mode == 0u) {
        uint face;
        hit_t[r] = nearest_hit(o, d, t_min, t_max, front_faces_only != 0u, scene, face);
        hit_face[r] = face;
        return;
    }
    hit_t[r] = 0.0LF;
    const uint crossings = crossings_of(o, d, t_min, t_max, scene);
    hit_face[r] = crossings != kNone ? crossings : crossings_in_order(o, d, t_min, t_max, scene);
}
