// The walk through geo::TriangleBvh's tree on the GPU, shared by every pass that casts rays
// (raycast.comp, cylinder_hierarchy/cast_level.comp). Define RAYCAST_VOTE (1 where the device has
// subgroup votes in compute shaders) and declare the tree's bindings before including it:
//   node_texels, corner_texels (rgba32ui images: texel arrays) and the buffer Faces { uint face_of[]; }.
//
// Both answers (the nearest hit; the crossings, hits within 1e-12 in t counted once) are a function
// of the set of triangles hit, so any walk that tests every triangle whose box the ray enters gives
// them: the boxes are tested in float, conservatively, and only the triangle test must equal the
// CPU's. It does: geo::intersect_ray_triangle's arithmetic in double, written out term for term
// and `precise`, so that no multiply-add is fused.
//
// The tree is the builder's node array with skip links (the node after a node's subtree), walked
// without a stack: entered, an inner node goes on to its first child, a missed node or a tested leaf
// to its skip. Node n is texels 2n (lo, skip) and 2n + 1 (hi, (first << 3) | count: count 0 for an
// inner node, whose children are nodes first and first + 1, and a leaf's slots first .. first +
// count - 1); slot s's corners are texels 5s .. 5s + 4, nine doubles as pairs of uints. Texel
// arrays: common/texel_array.glsl (lavapipe gathers from images but loads from storage buffers lane
// by lane).
#include "common/double_cpu.glsl"
#include "common/texel_array.glsl"

const uint kNone = 0xffffffffu;
const int kMaxHits = 64;

struct Node {
    vec3 lo;
    uint skip;
    vec3 hi;
    uint first;  // (first << 3) | count
};

Node node(uint n) {
    const uvec4 a = imageLoad(node_texels, texel(2u * n)), b = imageLoad(node_texels, texel(2u * n + 1u));
    return Node(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w);
}

// The box test, in float and conservative: geo::TriangleBvh's (geometry/src/bvh_query.cpp says
// why it never culls a triangle the exact test would hit), value for value.
struct Slabs {
    vec3 o, inv;
    bvec3 parallel;
    float w;
    double scale;
};

Slabs slabs(dvec3 o, dvec3 d, float scene) {
    Slabs sl;
    sl.o = vec3(o);
    const double m = max(max(abs(d.x), abs(d.y)), abs(d.z));
    sl.scale = m;
    for (int a = 0; a < 3; ++a) {
        sl.parallel[a] = abs(d[a]) <= 1e-30LF * m;
        sl.inv[a] = sl.parallel[a] ? 0.0 : float(m / d[a]);
    }
    precise float w = 3.814697265625e-6 * (scene + max(max(abs(sl.o.x), abs(sl.o.y)), abs(sl.o.z)));  // 2^-18
    sl.w = w;
    return sl;
}

// [t_near, t_far] in the slabs' units, rounded outward.
vec2 slab_range(Slabs sl, double t_near, double t_far) {
    const float a = float(t_near * sl.scale), b = float(t_far * sl.scale);
    precise vec2 range = vec2(a - 2.4e-7 * abs(a), b + 2.4e-7 * abs(b));
    return range;
}

// Branch-free: lavapipe runs every lane of a vector through each branch any lane takes.
bool enters(Slabs sl, vec3 box_lo, vec3 box_hi, vec2 range) {
    precise vec3 lo = box_lo - sl.w, hi = box_hi + sl.w;
    precise vec3 t0 = (lo - sl.o) * sl.inv, t1 = (hi - sl.o) * sl.inv;
    const vec3 near = mix(min(t0, t1), vec3(-1.0 / 0.0), sl.parallel);
    const vec3 far = mix(max(t0, t1), vec3(1.0 / 0.0), sl.parallel);
    const bvec3 below = lessThan(sl.o, lo), above = greaterThan(sl.o, hi);
    bool outside = !(sl.scale > 0.0LF);  // a zero direction hits nothing
    for (int a = 0; a < 3; ++a) outside = outside || (sl.parallel[a] && (below[a] || above[a]));
    return !outside && max(max(near.x, near.y), max(near.z, range.x)) <= min(min(far.x, far.y), min(far.z, range.y));
}

// Walks from node n to the next leaf the ray enters and returns it (0: none before the end), n then
// the node after it. With votes, a lane that has its leaf walks on while others search, up to its
// next leaf (where it leaves n), so that the lanes test their triangles together (Aila and Laine's
// speculative traversal).
uint next_leaf(inout uint n, uint end, Slabs sl, vec2 range) {
    uint leaf = 0u;
    while (n != end) {
        const Node nd = node(n);
        const bool entered = enters(sl, nd.lo, nd.hi, range);
        if (entered && (nd.first & 7u) != 0u) {
            if (leaf != 0u) break;
            leaf = nd.first;
            n = nd.skip;
        } else {
            n = entered ? nd.first >> 3 : nd.skip;
        }
#if RAYCAST_VOTE
        if (subgroupAll(leaf != 0u)) break;
#else
        if (leaf != 0u) break;
#endif
    }
    return leaf;
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
bool hit_triangle(uint slot, dvec3 o, dvec3 d, double t_min, double t_max, bool front, out double t) {
    dvec3 a, b, c;
    corners(slot, a, b, c);
    precise dvec3 e1 = b - a;
    precise dvec3 e2 = c - a;
    if (front && !(dot_cpu(cross_cpu(e1, e2), d) < 0.0LF)) return false;
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


// The nearest hit in [t_min, t_max] (ties to the lowest face index): its t, face kNone if none.
double nearest_hit(dvec3 o, dvec3 d, double t_min, double t_max, bool front, float scene, out uint face) {
    const Slabs sl = slabs(o, d, scene);
    const uint end = node(0u).skip;
    uint n = 0u;
    double best_t = t_max;
    uint best_face = kNone;
    while (n != end) {
        const uint leaf = next_leaf(n, end, sl, slab_range(sl, t_min, best_t));
        for (uint s = leaf >> 3; s < (leaf >> 3) + (leaf & 7u); ++s) {
            double t;
            if (!hit_triangle(s, o, d, t_min, best_t, front, t)) continue;
            const uint f = face_of[s];
            if (t < best_t || (t == best_t && f < best_face)) {
                best_t = t;
                best_face = f;
            }
        }
    }
    face = best_face;
    return best_t;
}

// The crossings in [t_min, t_max]: every hit, sorted, runs within 1e-12 merged (a ray through an
// edge or a corner of a closed mesh crosses it once), as TriangleBvh::crossings; kNone for more than
// kMaxHits hits (crossings_in_order counts those).
uint crossings_of(dvec3 o, dvec3 d, double t_min, double t_max, float scene) {
    const Slabs sl = slabs(o, d, scene);
    const vec2 range = slab_range(sl, t_min, t_max);
    const uint end = node(0u).skip;
    uint n = 0u;
    double hits[kMaxHits];
    int found = 0;
    while (n != end) {
        const uint leaf = next_leaf(n, end, sl, range);
        for (uint s = leaf >> 3; s < (leaf >> 3) + (leaf & 7u); ++s) {
            double t;
            if (!hit_triangle(s, o, d, t_min, t_max, false, t)) continue;
            if (found == kMaxHits) return kNone;
            int k = found++;
            while (k > 0 && hits[k - 1] > t) {
                hits[k] = hits[k - 1];
                --k;
            }
            hits[k] = t;
        }
    }
    uint crossings = 0u;
    for (int k = 0; k < found; ++k)
        if (k == 0 || hits[k] - hits[k - 1] > 1e-12LF) ++crossings;
    return crossings;
}

// The nearest hit distance in [after, t_max] (with `strictly`, above `after`), any orientation;
// `found` false where there is none.
double next_hit_distance(dvec3 o, dvec3 d, Slabs sl, double after, bool strictly, double t_max, out bool found) {
    const uint end = node(0u).skip;
    uint n = 0u;
    double best_t = t_max;
    found = false;
    while (n != end) {
        const uint leaf = next_leaf(n, end, sl, slab_range(sl, after, best_t));
        for (uint s = leaf >> 3; s < (leaf >> 3) + (leaf & 7u); ++s) {
            double t;
            if (!hit_triangle(s, o, d, after, best_t, false, t) || (strictly && t == after)) continue;
            best_t = t;
            found = true;
        }
    }
    return best_t;
}

// crossings_of without its limit, for the rare segment that crosses the model more than kMaxHits
// times: the distinct hit distances in increasing order, one walk each, by the same merging rule.
uint crossings_in_order(dvec3 o, dvec3 d, double t_min, double t_max, float scene) {
    const Slabs sl = slabs(o, d, scene);
    uint crossings = 0u;
    double last = t_min;
    for (;;) {  // one call site: shader compilers inline every call
        bool found;
        const double t = next_hit_distance(o, d, sl, last, crossings > 0u, t_max, found);
        if (!found) return crossings;
        if (crossings == 0u || t - last > 1e-12LF) ++crossings;
        last = t;
    }
}
