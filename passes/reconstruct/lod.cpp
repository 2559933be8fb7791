// Level of detail by image size: 2x2 means that never mix valid and empty pixels.
#include "gimg/passes/reconstruct.h"

#include "reconstruct_rules.h"

namespace gimg::passes {

CylinderImage lod_reduce(const CylinderImage& image, std::uint32_t times) {
    detail::check_reconstructible(image.width, image.height, times);
    CylinderImage current = image;
    for (std::uint32_t k = 0; k < times; ++k) {
        CylinderImage next(current.width / 2, current.height / 2);
        for (std::uint32_t v = 0; v < next.height; ++v)
            for (std::uint32_t u = 0; u < next.width; ++u) {
                const std::size_t i[4] = {current.index(2 * u, 2 * v), current.index(2 * u + 1, 2 * v),
                                          current.index(2 * u, 2 * v + 1), current.index(2 * u + 1, 2 * v + 1)};
                if (!(current.covered[i[0]] && current.covered[i[1]] && current.covered[i[2]] && current.covered[i[3]]))
                    continue;
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
                const std::size_t i[4] = {current.index(2 * u, 2 * v), current.index(2 * u + 1, 2 * v),
                                          current.index(2 * u, 2 * v + 1), current.index(2 * u + 1, 2 * v + 1)};
                if (!(current.covered[i[0]] && current.covered[i[1]] && current.covered[i[2]] && current.covered[i[3]]))
                    continue;
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
