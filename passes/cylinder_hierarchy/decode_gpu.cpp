// Decoding a hierarchy on the GPU (shaders/cylinder_hierarchy/level_step.glsl): level one, then
// per level the cells and the edges with the interleave, one graph; the CPU decoder's grid.
#include "gimg/passes/cylinder_hierarchy.h"

#include "gimg/engine/error.h"
#include "gimg/engine/upload.h"

#include "launch_rays.h"
#include "level_passes.h"

namespace gimg::passes {

HierarchyGrid decode_cylinder_hierarchy_gpu(Context& ctx, const CylinderHierarchy& h, std::uint32_t level) {
    if (!ctx.device_info().shader_float64)
        throw Error(ErrorKind::Unsupported, "decoding a hierarchy on the GPU needs shaderFloat64 (use the CPU)");
    detail::check_decodable(h, level);
    const std::uint32_t n = h.size, b = h.base, side = b << (level - 1);
    // The largest texel array: the decoded grid, 2 texels a point.
    detail::check_level_images(ctx, 2 * std::size_t(side) * side, n,
                               "decoding level " + std::to_string(level) + " (" + std::to_string(side) + " x " +
                                   std::to_string(side) + ") on the GPU");
    Image bands = detail::upload_bands(ctx, h);
    Buffer directions = upload_buffer(ctx, detail::level_directions(b, n), "hierarchy directions");
    Graph g(ctx);
    detail::LevelBuffers lb{.bands = g.import_image(bands), .directions = g.import_buffer(directions)};
    detail::add_level_step(g, 0, b, n, b, lb, "decode hierarchy: level 1");
    for (std::uint32_t l = 2, s = b; l <= level; ++l, s *= 2) {
        detail::add_level_step(g, 1, s, n, b, lb, "decode hierarchy: cells at " + std::to_string(s));
        detail::add_level_step(g, 2, s, n, b, lb, "decode hierarchy: level " + std::to_string(l));
    }
    Buffer readback;
    detail::add_read_back(ctx, g, lb.grid, readback, "decode hierarchy: read back");
    Plan plan = g.compile();
    plan.execute();
    return detail::grid_from_texels(ctx.download<std::byte>(readback), side, b);
}

}  // namespace gimg::passes
