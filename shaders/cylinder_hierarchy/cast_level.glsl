// A hierarchy level's rays in one pass (cast_level.comp with subgroup votes, cast_level_plain.comp
// without), each sample written into the multiresolution image: the CPU encoder's launches
// (launch_rays.cpp), rules (ray_rules.h) and arithmetic, so the two give the same hierarchy bit for
// bit. Invocation (u, v, band) casts launch H, V or D (band 0, 1, 2) of grid point (u, v):
//  - its launch from the grid (the previous ray pass placed it) and the cells (grid_cells.comp),
//    or where that is not valid the radial launch at its sample of the 2S grid;
//  - a launch at radius r: its parity segment from the wall, (x / r, y, z / r) (or (1, y, 0)), to
//    the launch point, then the nearest hit in [-behind, t_max] along the outward normal if the
//    crossings are odd (inside), against it if even; the value is t along the outward normal;
//  - a radial launch: the ordinary image's ray from the axis, front faces only, t in [-1, 1]; the
//    value 1 + t, the distance from the wall;
//  - a miss: by `miss`, 0 a sample on the surface (kind 2), 1 nothing, 2 the radial launch.
// With CAST_LEVEL_ONE (cast_level_one.comp), invocation (u, v) is level 1's pixel instead: the
// ordinary image's ray. Every walk has one call site (crossings, nearest hit): lavapipe inlines each
// call, and more copies of the walk made the pass slower.
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0, rgba32ui) uniform readonly uimage2D node_texels;
layout(binding = 1, rgba32ui) uniform readonly uimage2D corner_texels;
layout(std430, binding = 2) readonly buffer Faces { uint face_of[]; };  // slot -> face
layout(std430, binding = 3) readonly buffer Directions { double dirs[]; };  // as level_step.glsl's
layout(binding = 4, rgba32ui) uniform readonly uimage2D grid_texels;        // level_grid.glsl's layouts
layout(binding = 5, rgba32ui) uniform readonly uimage2D cell_texels;
layout(binding = 6, rg32ui) uniform writeonly uimage2D bands;  // N x N: (t as a float, kind)
// The next level's grid (level 1's with level_one), as next_grid.comp builds it from the stored
// samples; written where write_next is 1.
layout(binding = 7, rgba32ui) uniform writeonly uimage2D next_texels;
layout(push_constant) uniform Push {
    uint side;  // S
    uint n;     // N
    uint base;  // B
    uint miss;  // 0 surface, 1 empty, 2 radial (HierarchyMiss)
    uint write_next;  // 1: write next_texels
    float scene;      // the largest |coordinate| of the tree's boxes
    double behind;  // ray_rules.h's kBehind
    double reach;   // t_max = reach x span; 0: without limit
};
// Level 1's pass is a shader of its own (cast_level_one.comp): lavapipe would run the other path too.
const bool level_one = CAST_LEVEL_ONE != 0;

#include "raycast/walk.glsl"
#include "cylinder_hierarchy/level_grid.glsl"

const uint kEmpty = 0u, kHit = 1u, kMiss = 2u, kRadial = 3u;

// What a ray's hit stands for: a launch along its normal, the ordinary image's ray at a sample
// (its value the distance from the wall), or level 1's pixel.
const uint kAlongNormal = 0u, kRadialRay = 1u, kLevelOne = 2u;

struct Ray {
    dvec3 o, d;
    double t_min, t_max;
    bool front;
    uint meaning;
};

// The ordinary image's ray from the axis at the height of `l` (a radial launch), front faces only.
Ray radial_ray(GridLaunch l) {
    return Ray(dvec3(0.0LF, l.origin.y, 0.0LF), l.normal, -1.0LF, 1.0LF, true, kRadialRay);
}

void main() {
    // A subgroup of 8 lanes takes a 4 x 2 block of the workgroup's 8 x 8 (not a row of 8): nearer
    // launches walk more alike, and lavapipe runs the 8 until the longest walk ends.
    const uint lane = gl_LocalInvocationIndex;
    const uint u = gl_WorkGroupID.x * 8u + ((lane & 1u) | ((lane >> 1u) & 2u) | ((lane >> 2u) & 4u));
    const uint v = gl_WorkGroupID.y * 8u + (((lane >> 1u) & 1u) | ((lane >> 2u) & 2u) | ((lane >> 3u) & 4u));
    const uint band = gl_GlobalInvocationID.z;
    if (u >= side || v >= side) return;
    // The next grid's sample of this launch, where a radial ray replaces it.
    const uint col = 2u * u + (band != 1u ? 1u : 0u), row = 2u * v + (band != 0u ? 1u : 0u);
    Ray ray;
    GridLaunch l;
    bool casting = true, inside = false;
    if (level_one) {
        // Level 1's pixel (u, v), as CylinderRaycaster::project: from the axis point at the row's
        // height along -theta_u.
        ray = Ray(dvec3(0.0LF, row_height(v, base), 0.0LF), dvec3(-dirs[2 * u], 0.0LF, -dirs[2 * u + 1]), -1.0LF,
                  1.0LF, true, kLevelOne);
    } else {
        l = grid_launch(band, u, v, true);
        if (l.valid) {
            const double r = radius(l.origin);
            precise dvec3 wall = r > 0.0LF ? dvec3(l.origin.x / r, l.origin.y, l.origin.z / r)
                                           : dvec3(1.0LF, l.origin.y, 0.0LF);
            precise dvec3 segment = l.origin - wall;
            uint crossings = crossings_of(wall, segment, 0.0LF, 1.0LF, scene);
            if (crossings == kNone) crossings = crossings_in_order(wall, segment, 0.0LF, 1.0LF, scene);
            inside = crossings % 2u == 1u;
            precise double limit = reach * l.span;
            const double t_max = reach > 0.0LF ? limit : packDouble2x32(uvec2(0u, 0x7ff00000u));  // +inf
            ray = Ray(l.origin, inside ? l.normal : -l.normal, -behind, t_max, false, kAlongNormal);
        } else {
            const GridLaunch rl = radial_launch(col, row);
            casting = rl.valid;
            ray = radial_ray(rl);
        }
    }
    double value = 0.0LF;
    uint kind = kEmpty;
    // At most two walks: the ray, then for a launch that missed with `miss` radial, the radial ray.
    for (uint attempt = 0u; casting && attempt < 2u; ++attempt) {
        uint face;
        const double t = nearest_hit(ray.o, ray.d, ray.t_min, ray.t_max, ray.front, scene, face);
        if (face != kNone) {
            if (ray.meaning == kAlongNormal) {
                value = inside ? t : -t;
                kind = kHit;
            } else if (ray.meaning == kRadialRay) {
                precise double from_wall = 1.0LF + t;
                value = from_wall;
                kind = kRadial;
            } else {  // t = 1 - d with d = -t rounded to float, as the encoders' level 1
                const float d = float(-t);
                precise double from_wall = 1.0LF - double(d);
                value = from_wall;
                kind = kHit;
            }
            break;
        }
        if (ray.meaning != kAlongNormal) break;
        if (miss == 0u) kind = kMiss;
        if (miss != 2u) break;
        const GridLaunch rl = radial_launch(col, row);
        casting = rl.valid;
        ray = radial_ray(rl);
    }
    const ivec2 at_band = level_one    ? ivec2(u, v)
                          : band == 0u ? band_h(u, v)
                          : band == 1u ? band_v(u, v)
                                       : band_d(u, v);
    const float stored = float(value);
    imageStore(bands, at_band, uvec4(floatBitsToUint(stored), kind, 0u, 0u));
    if (write_next == 0u) return;

    // The new grid point from the stored sample, as level_one_grid.comp and next_grid.comp place it.
    const uint i = level_one ? v * side + u : row * (2u * side) + col;
    const uvec4 t[2] = level_one ? level_one_point(u, v, stored, kind) : sample_point(col, row, l, stored, kind);
    imageStore(next_texels, texel(2u * i), t[0]);
    imageStore(next_texels, texel(2u * i + 1u), t[1]);
    if (level_one) return;
    if (band == 0u) {  // and the grid's own point, (2u, 2v)
        const uint o = (2u * v) * (2u * side) + 2u * u, g = v * side + u;
        imageStore(next_texels, texel(2u * o), imageLoad(grid_texels, texel(2u * g)));
        imageStore(next_texels, texel(2u * o + 1u), imageLoad(grid_texels, texel(2u * g + 1u)));
    }
}
