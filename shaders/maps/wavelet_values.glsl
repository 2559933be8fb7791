// The wavelet transform's arrays as r32ui texel arrays (common/texel_array.glsl): doubles as two
// texels (low word first), a vertex's value as three doubles, so a texel array of 6 V texels holds
// the same bytes as a buffer of V dvec3. lavapipe gathers 32-bit texels with one instruction for 8
// lanes; it loads from storage buffers lane by lane.
#include "common/texel_array.glsl"

#define WORD_AT(image, i) imageLoad(image, texel(i)).x
#define DOUBLE_AT(image, i) packDouble2x32(uvec2(WORD_AT(image, 2u * (i)), WORD_AT(image, 2u * (i) + 1u)))
#define VALUE_AT(image, v) dvec3(DOUBLE_AT(image, 3u * (v)), DOUBLE_AT(image, 3u * (v) + 1u), DOUBLE_AT(image, 3u * (v) + 2u))
#define STORE_DOUBLE(image, i, value_)                                  \
    {                                                                   \
        const uvec2 w_ = unpackDouble2x32(value_);                      \
        imageStore(image, texel(2u * (i)), uvec4(w_.x));                \
        imageStore(image, texel(2u * (i) + 1u), uvec4(w_.y));           \
    }
#define STORE_VALUE(image, v, value_)                                   \
    {                                                                   \
        STORE_DOUBLE(image, 3u * (v), (value_).x)                       \
        STORE_DOUBLE(image, 3u * (v) + 1u, (value_).y)                  \
        STORE_DOUBLE(image, 3u * (v) + 2u, (value_).z)                  \
    }
