#version 460
// BiCGSTAB, passes 2 and 4: out = A in (A in compressed rows, diagonal included), and the
// workgroup's sums of two dot products per right-hand side for bicgstab_finish:
// mode 0: (r0 . out) in sums 0-1; mode 1: (out . w) in 0-1 and (out . out) in 2-3. `in` is the
// double vector (Jacobi) or the multigrid cycle's float output, widened as it is read (exactly).
#extension GL_GOOGLE_include_directive : require
#include "solvers/texels.glsl"

layout(local_size_x = 64) in;
layout(binding = 0, rgba32ui) uniform readonly uimage2D a_rows;
layout(binding = 1, rgba32ui) uniform readonly uimage2D a_entries;
layout(binding = 2, rgba32ui) uniform readonly uimage2D in_vec;
layout(binding = 3, rg32f) uniform readonly image2D in32;
layout(binding = 4, rgba32ui) uniform readonly uimage2D w;  // r0 (mode 0) or s (mode 1)
layout(binding = 5, rgba32ui) uniform writeonly uimage2D out_vec;
layout(std430, binding = 6) writeonly buffer Partials { double partials[]; };
layout(push_constant) uniform Push { uint rows; uint mode; uint float_input; };

#include "solvers/workgroup_sums.glsl"

dvec2 input_at(uint j) { return float_input != 0u ? dvec2(LOAD_VEC32(in32, j)) : LOAD_VEC(in_vec, j); }

void main() {
    const uint i = gl_GlobalInvocationID.x;
    dvec4 terms = dvec4(0.0LF);
    if (i < rows) {
        const uvec4 row = imageLoad(a_rows, texel(i));
        dvec2 sum = dvec2(0.0LF);
        for (uint k = row.x; k < row.y; ++k) {
            const uvec4 e = imageLoad(a_entries, texel(k));
            sum += value_of(e) * input_at(e.x);
        }
        STORE_VEC(out_vec, i, sum);
        const dvec2 wi = LOAD_VEC(w, i);
        terms = mode == 1u ? dvec4(wi * sum, sum * sum) : dvec4(wi * sum, 0.0LF, 0.0LF);
    }
    write_workgroup_sums(terms);
}
