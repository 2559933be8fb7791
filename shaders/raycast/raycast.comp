#version 460
// Rays through geo::TriangleBvh on the GPU, one invocation a ray, in double precision with the
// arithmetic of geo::intersect_ray_triangle (Möller–Trumbore, closed barycentric bounds) and of
// the BVH's slab test written out term for term and `precise`, so that no multiply-add is fused
// and every hit equals the CPU's. Two modes:
//  0 nearest: the hit with the smallest t in [t_min, t_max], ties to the lowest face index;
//  1 crossings: the number of hits in [t_min, t_max], hits within 1e-12 in t counted once (a ray
//    through an edge or a corner of a closed mesh crosses it once), as TriangleBvh::crossings. More than kMaxHits hits: 0xffffffff (the host counts that ray itself).
//
// The nodes and corners are texel arrays (common/texel_array.glsl: lavapipe gathers from images but
// loads from storage buffers lane by lane): node n is texels 2n (lo, first) and 2n + 1 (hi, count);
// slot s's corners are texels 5s .. 5s + 4, nine doubles as pairs of uints.
#extension GL_GOOGLE_include_directive : require
#include "common/texel_array.glsl"

layout(local_size_x = 64) in;

layout(binding = 0, rgba32ui) uniform readonly uimage2D node_texels;
layout(binding = 1, rgba32ui) uniform readonly uimage2D corner_texels;
layout(std430, binding = 2) readonly buffer Faces { uint face_of[]; };    // slot -> face
layout(std430, binding = 3) readonly buffer Rays { double ray[]; };       // 8 per ray: o, d, t_min, t_max
layout(std430, binding = 4) writeonly buffer HitT { double hit_t[]; };
layout(std430, binding = 5) writeonly buffer HitFace { uint hit_face[]; };  // face, or the crossings
layout(push_constant) uniform Push {
    uint count;
    uint mode;
    uint front_faces_only;
};

const uint kNone = 0xffffffffu;
const int kStack = 128;
const int kMaxHits = 64;

double inf() { return packDouble2x32(uvec2(0u, 0x7ff00000u)); }

dvec3 cross_cpu(dvec3 x, dvec3 y) {  // glm::cross, term for term
    precise dvec3 r = dvec3(x.y * y.z - y.y * x.z, x.z * y.x - y.z * x.x, x.x * y.y - y.x * x.y);
    return r;
}

double dot_cpu(dvec3 x, dvec3 y) {  // glm::dot: (x.x y.x + x.y y.y) + x.z y.z
    precise double r = (x.x * y.x + x.y * y.y) + x.z * y.z;
    return r;
}

struct Node {
    vec3 lo;
    uint first;  // leaf: first slot; inner: first child
    vec3 hi;
    uint count;  // leaf: slots; inner: 0
};

Node node(uint n) {
    const uvec4 a = imageLoad(node_texels, texel(2u * n)), b = imageLoad(node_texels, texel(2u * n + 1u));
    return Node(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w);
}

// The three corners of a slot.
void corners(uint slot, out dvec3 a, out dvec3 b, out dvec3 c) {
    const uvec4 t0 = imageLoad(corner_texels, texel(5u * slot)), t1 = imageLoad(corner_texels, texel(5u * slot + 1u));
    const uvec4 t2 = imageLoad(corner_texels, texel(5u * slot + 2u)), t3 = imageLoad(corner_texels, texel(5u * slot + 3u));
    const uvec4 t4 = imageLoad(corner_texels, texel(5u * slot + 4u));
    a = dvec3(packDouble2x32(t0.xy), packDouble2x32(t0.zw), packDouble2x32(t1.xy));
    b = dvec3(packDouble2x32(t1.zw), packDouble2x32(t2.xy), packDouble2x32(t2.zw));
    c = dvec3(packDouble2x32(t3.xy), packDouble2x32(t3.zw), packDouble2x32(t4.xy));
}

// geo::intersect_ray_triangle.
bool hit_triangle(uint slot, dvec3 o, dvec3 d, double t_min, double t_max, out double t) {
    dvec3 a, b, c;
    corners(slot, a, b, c);
    precise dvec3 e1 = b - a;
    precise dvec3 e2 = c - a;
    if (front_faces_only != 0u && !(dot_cpu(cross_cpu(e1, e2), d) < 0.0LF)) return false;
    const dvec3 pvec = cross_cpu(d, e2);
    const double det = dot_cpu(e1, pvec);
    if (det == 0.0LF) return false;
    precise double inv = 1.0LF / det;
    precise dvec3 tvec = o - a;
    precise double u = dot_cpu(tvec, pvec) * inv;
    if (!(u >= 0.0LF && u <= 1.0LF)) return false;
    const dvec3 qvec = cross_cpu(tvec, e1);
    precise double v = dot_cpu(d, qvec) * inv;
    precise double uv = u + v;
    if (!(v >= 0.0LF && uv <= 1.0LF)) return false;
    precise double tt = dot_cpu(e2, qvec) * inv;
    if (!(tt >= t_min && tt <= t_max)) return false;
    t = tt;
    return true;
}

// The BVH's RaySlabs::enter: the entry t into the node's box within [t_near, t_far], or inf.
double enter(uint n, dvec3 o, dvec3 inv_dir, bvec3 parallel, double t_near, double t_far) {
    precise double tn = t_near - 1e-12LF * abs(t_near);
    precise double tf = t_far + 1e-12LF * abs(t_far);
    const Node nd = node(n);
    const dvec3 lo = dvec3(nd.lo), hi = dvec3(nd.hi);
    for (int a = 0; a < 3; ++a) {
        if (parallel[a]) {
            if (o[a] < lo[a] || o[a] > hi[a]) return inf();
            continue;
        }
        precise double t0 = (lo[a] - o[a]) * inv_dir[a];
        precise double t1 = (hi[a] - o[a]) * inv_dir[a];
        if (t0 > t1) {
            const double s = t0;
            t0 = t1;
            t1 = s;
        }
        t0 -= 1e-12LF * abs(t0);
        t1 += 1e-12LF * abs(t1);
        tn = max(tn, t0);
        tf = min(tf, t1);
        if (tn > tf) return inf();
    }
    return tn;
}

void main() {
    const uint r = gl_GlobalInvocationID.x;
    if (r >= count) return;
    const dvec3 o = dvec3(ray[8 * r], ray[8 * r + 1], ray[8 * r + 2]);
    const dvec3 d = dvec3(ray[8 * r + 3], ray[8 * r + 4], ray[8 * r + 5]);
    const double t_min = ray[8 * r + 6], t_max = ray[8 * r + 7];
    bvec3 parallel;
    dvec3 inv_dir;
    for (int a = 0; a < 3; ++a) {
        parallel[a] = d[a] == 0.0LF;
        inv_dir[a] = parallel[a] ? 0.0LF : 1.0LF / d[a];
    }
    uint stack_node[kStack];
    double stack_t[kStack];
    int top = 0;
    if (mode == 0u) {
        double best_t = t_max;
        uint best_face = kNone;
        const double t_root = enter(0u, o, inv_dir, parallel, t_min, t_max);
        if (t_root != inf()) {
            stack_node[0] = 0u;
            stack_t[0] = t_root;
            top = 1;
        }
        while (top > 0) {
            --top;
            const uint n = stack_node[top];
            if (stack_t[top] > best_t) continue;
            const Node nd = node(n);
            if (nd.count > 0u) {
                for (uint s = nd.first; s < nd.first + nd.count; ++s) {
                    double t;
                    if (!hit_triangle(s, o, d, t_min, best_t, t)) continue;
                    const uint f = face_of[s];
                    if (t < best_t || (t == best_t && f < best_face)) {
                        best_t = t;
                        best_face = f;
                    }
                }
                continue;
            }
            const uint l = nd.first, rr = l + 1u;
            const double tl = enter(l, o, inv_dir, parallel, t_min, best_t);
            const double tr = enter(rr, o, inv_dir, parallel, t_min, best_t);
            const bool left_first = tl <= tr;
            const uint near_n = left_first ? l : rr, far_n = left_first ? rr : l;
            const double near_t = left_first ? tl : tr, far_t = left_first ? tr : tl;
            if (far_t != inf() && top < kStack) {
                stack_node[top] = far_n;
                stack_t[top] = far_t;
                ++top;
            }
            if (near_t != inf() && top < kStack) {
                stack_node[top] = near_n;
                stack_t[top] = near_t;
                ++top;
            }
        }
        hit_t[r] = best_t;
        hit_face[r] = best_face;
        return;
    }
    // Crossings: every hit in [t_min, t_max], sorted, runs within 1e-12 merged.
    double hits[kMaxHits];
    int found = 0;
    bool overflow = false;
    stack_node[0] = 0u;
    top = 1;
    while (top > 0 && !overflow) {
        --top;
        const uint n = stack_node[top];
        if (enter(n, o, inv_dir, parallel, t_min, t_max) == inf()) continue;
        const Node nd = node(n);
        if (nd.count > 0u) {
            for (uint s = nd.first; s < nd.first + nd.count; ++s) {
                double t;
                if (!hit_triangle(s, o, d, t_min, t_max, t)) continue;
                if (found == kMaxHits) {
                    overflow = true;
                    break;
                }
                int k = found++;
                while (k > 0 && hits[k - 1] > t) {
                    hits[k] = hits[k - 1];
                    --k;
                }
                hits[k] = t;
            }
            continue;
        }
        if (top + 2 <= kStack) {
            stack_node[top++] = nd.first + 1u;
            stack_node[top++] = nd.first;
        }
    }
    uint crossings = 0u;
    for (int k = 0; k < found; ++k)
        if (k == 0 || hits[k] - hits[k - 1] > 1e-12LF) ++crossings;
    hit_t[r] = 0.0LF;
    hit_face[r] = overflow ? kNone : crossings;
}
