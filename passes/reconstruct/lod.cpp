// Level of detail by image size: 2x2 means that never mix valid and empty pixels.
#include "gimg/passes/reconstruct.h"

#include "reconstruct_rules.h"

namespace gimg::passes {

namespace {

// The four pixels under output pixel (u, v), in the order the shader sums them; true when all
// four are valid (only then is the output pixel valid).
template <class Image>
bool fully_covered_block(const Image& image, std::uint32_t u, std::uint32_t v, std::size_t (&i)[4]) {
    i[0] = image.index(2 * u, 2 * v);
    i[1] = image.index(2 * u + 1, 2 * v);
    i[2] = image.index(2 * u, 2 * v + 1);
    i[3] = image.index(2 * u + 1, 2 * v + 1);
    return image.covered[i[0]] && image.covered[i[1]] && image.covered[i[2]] && image.covered[i[3]];
}

}  // namespace

CylinderImage lod_reduce(const CylinderImage& image, std::uint32_t times) {
    detail::check_reconstructible(image.width, image.height, times);
    CylinderImage current = image;
    for (std::uint32_t k = 0; k < times; ++k) {
        CylinderImage next(current.width / 2, current.height / 2);
        for (std::uint32_t v = 0; v < next.height; ++v)
            for (std::uint32_t u = 0; u < next.width; ++u) {
                std::size_t i[4];
                if (!fully_covered_block(current, u, v, i)) continue;
                // (a + b) + (c + d), then a quarter: the order the shader uses.
                const float sum = (current.distance[i[0]] + current.distance[i[1]]) +
                                  (current.distance[i[2]] + current.distance[i[3]]);
                next.covered[next.index(u, v)] = 1;
                next.distance[next.index(u, v)] = 0.25f * sum;
            }
        current = std::move(next);
    }
    return current;
}

PositionImage lod_reduce(const PositionImage& image, std::uint32_t times) {
    detail::check_reconstructible(image.width, image.height, times);
    PositionImage current = image;
    for (std::uint32_t k = 0; k < times; ++k) {
        PositionImage next(current.width / 2, current.height / 2);
        for (std::uint32_t v = 0; v < next.height; ++v)
            for (std::uint32_t u = 0; u < next.width; ++u) {
                std::size_t i[4];
                if (!fully_covered_block(current, u, v, i)) continue;
                const std::size_t o = next.index(u, v);
                next.covered[o] = 1;
                for (int c = 0; c < 3; ++c) {
                    const float sum = (current.xyz[3 * i[0] + c] + current.xyz[3 * i[1] + c]) +
                                      (current.xyz[3 * i[2] + c] + current.xyz[3 * i[3] + c]);
                    next.xyz[3 * o + c] = 0.25f * sum;
                }
            }
        current = std::move(next);
    }
    return current;
}

}  // namespace gimg::passes
