// A hierarchy level's rays in one pass (cast_level.comp with subgroup votes, cast_level_plain.comp
// without), each sample written into the multiresolution image: the CPU encoder's launches
// (launch_rays.cpp), rules (ray_rules.h) and arithmetic, so the two give the same hierarchy bit for
// bit. Invocation (u, v, band) casts launch H, V or D (band 0, 1, 2) of grid point (u, v):
//  - its launch from the grid and the cells (decode_level.comp's steps 0-2 made them), or where
//    that is not valid the radial launch at its sample of the 2S grid;
//  - a launch at radius r: its parity segment from the wall, (x / r, y, z / r) (or (1, y, 0)), to
//    the launch point, then the nearest hit in [-behind, t_max] along the outward normal if the
//    crossings are odd (inside), against it if even; the value is t along the outward normal;
//  - a radial launch: the ordinary image's ray from the axis, front faces only, t in [-1, 1]; the
//    value 1 + t, the distance from the wall;
//  - a miss: by `miss`, 0 a sample on the surface (kind 2), 1 nothing, 2 the radial launch.
// With level_one, invocation (u, v) is level 1's pixel instead: the ordinary image's ray.
layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = 0, rgba32ui) uniform readonly uimage2D node_texels;
layout(binding = 1, rgba32ui) uniform readonly uimage2D corner_texels;
layout(std430, binding = 2) readonly buffer Faces { uint face_of[]; };  // slot -> face
layout(std430, binding = 3) readonly buffer Directions { double dirs[]; };  // as decode_level.comp's
layout(binding = 4, rgba32ui) uniform readonly uimage2D grid_texels;        // level_grid.glsl's layouts
layout(binding = 5, rgba32ui) uniform readonly uimage2D cell_texels;
layout(binding = 6, rg32ui) uniform writeonly uimage2D bands;  // N x N: (t as a float, kind)
layout(push_constant) uniform Push {
    uint side;  // S
    uint n;     // N
    uint base;  // B
    uint miss;  // 0 surface, 1 empty, 2 radial (HierarchyMiss)
    uint level_one;  // 1: level 1, the ordinary B x B image, instead
    float scene;     // the largest |coordinate| of the tree's boxes
    double behind;  // ray_rules.h's kBehind
    double reach;   // t_max = reach x span; 0: without limit
};

#include "raycast/walk.glsl"
#include "cylinder_hierarchy/level_grid.glsl"

const uint kEmpty = 0u, kHit = 1u, kMiss = 2u, kRadial = 3u;

// A radial launch's ray: the distance from the wall, or a negative value for a miss.
double cast_radial(GridLaunch l) {
    uint face;
    const double t = nearest_hit(dvec3(0.0LF, l.origin.y, 0.0LF), l.normal, -1.0LF, 1.0LF, true, scene, face);
    precise double from_wall = 1.0LF + t;
    return face == kNone ? -1.0LF : from_wall;
}

// Casts one launch (band 0 H, 1 V, 2 D of grid point (u, v)) and stores its sample.
void cast_launch(uint band, uint u, uint v, GridLaunch l) {
    const uint col = 2u * u + (band != 1u ? 1u : 0u), row = 2u * v + (band != 0u ? 1u : 0u);
    double value = 0.0LF;
    uint kind = kEmpty;
    bool radial = !l.valid;
    if (!radial) {
        const double r = radius(l.origin);
        precise dvec3 wall = r > 0.0LF ? dvec3(l.origin.x / r, l.origin.y, l.origin.z / r)
                                       : dvec3(1.0LF, l.origin.y, 0.0LF);
        precise dvec3 segment = l.origin - wall;
        uint crossings = crossings_of(wall, segment, 0.0LF, 1.0LF, scene);
        if (crossings == kNone) crossings = crossings_in_order(wall, segment, 0.0LF, 1.0LF, scene);
        const bool inside = crossings % 2u == 1u;
        precise double limit = reach * l.span;
        const double t_max = reach > 0.0LF ? limit : packDouble2x32(uvec2(0u, 0x7ff00000u));  // +inf
        uint face;
        const double t = nearest_hit(l.origin, inside ? l.normal : -l.normal, -behind, t_max, false, scene, face);
        if (face != kNone) {
            value = inside ? t : -t;
            kind = kHit;
        } else if (miss == 0u) {
            kind = kMiss;
        } else {
            radial = miss == 2u;
        }
    }
    if (radial) {
        const GridLaunch rl = radial_launch(col, row);
        const double from_wall = rl.valid ? cast_radial(rl) : -1.0LF;
        if (from_wall >= 0.0LF) {
            value = from_wall;
            kind = kRadial;
        }
    }
    const ivec2 at_band = band == 0u ? band_h(u, v) : band == 1u ? band_v(u, v) : band_d(u, v);
    imageStore(bands, at_band, uvec4(floatBitsToUint(float(value)), kind, 0u, 0u));
}

// Level 1's pixel (u, v), as CylinderRaycaster::project: from the axis point at the row's height
// along -theta_u, the nearest front face in t in [-1, 1]; stored as t = 1 - d with d = -t rounded to
// float, as the encoders' level 1.
void cast_level_one(uint u, uint v) {
    const dvec3 o = dvec3(0.0LF, row_height(v, base), 0.0LF);
    uint face;
    const double t = nearest_hit(o, dvec3(-dirs[2 * u], 0.0LF, -dirs[2 * u + 1]), -1.0LF, 1.0LF, true, scene, face);
    const float d = float(-t);
    precise double from_wall = 1.0LF - double(d);
    imageStore(bands, ivec2(u, v),
               face == kNone ? uvec4(0u) : uvec4(floatBitsToUint(float(from_wall)), kHit, 0u, 0u));
}

void main() {
    const uint u = gl_GlobalInvocationID.x, v = gl_GlobalInvocationID.y;
    if (level_one != 0u) {
        if (u < base && v < base) cast_level_one(u, v);
        return;
    }
    if (u >= side || v >= side) return;
    const uint band = gl_GlobalInvocationID.z;
    cast_launch(band, u, v, grid_launch(band, u, v, true));
}
