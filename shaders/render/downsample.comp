#version 460
// Box-filter supersampling: each output pixel averages factor x factor samples of the
// supersampled picture, blended over the background by coverage (alpha keeps the coverage).
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba8) uniform readonly image2D samples;
layout(binding = 1, rgba8) uniform writeonly image2D result;
layout(push_constant) uniform Push { uvec2 size; uint factor; uint pad; vec4 background; };

void main() {
    const uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= size.x || p.y >= size.y) return;
    vec4 sum = vec4(0.0);
    for (uint y = 0; y < factor; ++y)
        for (uint x = 0; x < factor; ++x) sum += imageLoad(samples, ivec2(p * factor + uvec2(x, y)));
    const vec4 avg = sum / float(factor * factor);
    // Samples were drawn over transparent black: premultiplied colour plus background.
    imageStore(result, ivec2(p), vec4(avg.rgb + (1.0 - avg.a) * background.rgb, avg.a));
}
