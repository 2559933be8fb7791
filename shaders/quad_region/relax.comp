#version 460
// Kuriyama & Kaneko's eq. (2) as Gauss-Seidel sweeps in colour order, one workgroup per field
// (workgroup 0 relaxes u, workgroup 1 v): x_i <- k x_i + (1 - k) sum_j w_ij x_j for the rows of one
// colour at a time (no two of them neighbours, so they update in place), a workgroup barrier
// between colours, GIMG_RELAX_SWEEPS sweeps per dispatch. Each sweep's largest correction
// |sum_j w_ij x_j - x_i| goes into its slot as float bits (which order like the values for
// non-negative floats). After its sweeps the workgroup applies the stopping rule itself, so that
// the host can queue several dispatches and read back only how far each field got: a discrete GPU
// then pays its submission latency a few times per map, not once per colour and sweep.
#extension GL_GOOGLE_include_directive : require
#include "quad_region/relax_layout.h"

layout(local_size_x = GIMG_RELAX_GROUP) in;
layout(std430, binding = 0) readonly buffer Rows { uint row_vertex[]; };
layout(std430, binding = 1) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 2) readonly buffer Columns { uint columns[]; };
layout(std430, binding = 3) readonly buffer Weights { double weights[]; };
layout(std430, binding = 4) coherent buffer Params { double uv[]; };  // (u, v) per vertex
layout(std430, binding = 5) coherent buffer Slots { uint worst[]; };   // [field][sweep], zeroed per dispatch
layout(std430, binding = 6) readonly buffer Colours { uint first[]; };  // colour c: rows [first[c], first[c + 1])
// Per field: the sweeps done so far, and 1 once a sweep's largest correction fell below the limit
// (the count then stops at that sweep).
layout(std430, binding = 7) buffer Progress { uint progress[]; };
layout(push_constant) uniform Push {
    uint colours;
    uint limit;       // tau as float bits; 0 never stops
    uint max_sweeps;  // no dispatch starts once this many are done
    uint pad;
    double k;
};

void main() {
    const uint field = gl_WorkGroupID.x;
    const uint done = progress[2u * field];
    if (progress[2u * field + 1u] != 0u || done >= max_sweeps) return;
    for (uint sweep = 0u; sweep < GIMG_RELAX_SWEEPS; ++sweep) {
        for (uint c = 0u; c < colours; ++c) {
            for (uint r = first[c] + gl_LocalInvocationID.x; r < first[c + 1u]; r += GIMG_RELAX_GROUP) {
                const uint v = row_vertex[r];
                precise double mean = 0.0LF;
                for (uint e = offsets[r]; e < offsets[r + 1u]; ++e) mean += weights[e] * uv[2u * columns[e] + field];
                const double x = uv[2u * v + field];
                atomicMax(worst[field * GIMG_RELAX_SWEEPS + sweep], floatBitsToUint(float(abs(mean - x))));
                precise double next = k * x + (1.0LF - k) * mean;
                uv[2u * v + field] = next;
            }
            memoryBarrierBuffer();
            barrier();
        }
    }
    if (gl_LocalInvocationID.x == 0u) {
        uint settled_at = 0u;
        for (uint s = 0u; s < GIMG_RELAX_SWEEPS; ++s)
            if (settled_at == 0u && worst[field * GIMG_RELAX_SWEEPS + s] < limit) settled_at = done + s + 1u;
        progress[2u * field] = settled_at != 0u ? settled_at : done + GIMG_RELAX_SWEEPS;
        progress[2u * field + 1u] = settled_at != 0u ? 1u : 0u;
    }
}
