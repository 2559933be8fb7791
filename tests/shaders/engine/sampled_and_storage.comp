#version 460
// Only for the reflection test: one of each descriptor kind gimg binds, and a padded push block.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D src;
layout(binding = 1, r32f) uniform writeonly image2D dst;
layout(std140, binding = 2) uniform Params { vec4 tint; };
layout(push_constant) uniform Push { mat4 transform; vec3 origin; float scale; };

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    vec4 s = texelFetch(src, p, 0) * tint;
    imageStore(dst, p, vec4((transform * vec4(origin, 1.0)).x * scale + s.x));
}
