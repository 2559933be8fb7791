// A hierarchy level's grid passes on the render graph (level_passes.h).
#include "level_passes.h"

#include "gimg/engine/error.h"
#include "gimg/engine/texel_array.h"
#include "gimg/passes/cylinder.h"

#include "cylinder_hierarchy/grid_cells_comp.h"
#include "cylinder_hierarchy/level_one_grid_comp.h"
#include "cylinder_hierarchy/next_grid_comp.h"
#include "launch_rays.h"

#include <algorithm>
#include <cstring>

namespace gimg::passes::detail {

namespace {

// Step 0, 1, 2 (add_level_step).
const Spirv kSteps[3] = {GIMG_SPIRV(gimg_spv_cylinder_hierarchy_level_one_grid_comp),
                         GIMG_SPIRV(gimg_spv_cylinder_hierarchy_grid_cells_comp),
                         GIMG_SPIRV(gimg_spv_cylinder_hierarchy_next_grid_comp)};

struct LevelPush {
    std::uint32_t side, n, base;
};

}  // namespace

std::vector<double> level_directions(std::uint32_t base, std::uint32_t size) {
    std::vector<double> dirs;
    for (const auto& d : cylinder_directions(base)) dirs.insert(dirs.end(), {d[0], d[1]});
    for (std::uint32_t m = 2 * base; m <= size; m *= 2)
        for (const auto& d : radial_directions(m, base)) dirs.insert(dirs.end(), {d[0], d[1]});
    return dirs;
}

Image upload_bands(Context& ctx, const CylinderHierarchy& h) {
    std::vector<std::uint32_t> texels(2 * h.t.size());
    for (std::size_t i = 0; i < h.t.size(); ++i) {
        std::memcpy(&texels[2 * i], &h.t[i], 4);
        texels[2 * i + 1] = h.valid[i];
    }
    Image image = ctx.create_image({h.size, h.size, Format::RG32U, "hierarchy bands"});
    ctx.upload(image, texels.data(), texels.size() * 4);
    return image;
}

void read_bands(Context& ctx, Buffer& bands, CylinderHierarchy& h) {
    const std::vector<std::byte> bytes = ctx.download<std::byte>(bands);
    for (std::size_t i = 0; i < h.t.size(); ++i) {
        std::uint32_t kind;
        std::memcpy(&h.t[i], &bytes[8 * i], 4);
        std::memcpy(&kind, &bytes[8 * i + 4], 4);
        h.valid[i] = std::uint8_t(kind);
    }
}

void add_read_back(Context& ctx, Graph& g, ImageHandle image, Buffer& host, const std::string& name) {
    const ImageDesc& desc = g.image_desc(image);
    host = ctx.create_buffer(
        {VkDeviceSize(desc.width) * desc.height * bytes_per_pixel(desc.format), desc.name + " readback"},
        MemoryUsage::Readback);
    BufferHandle out = g.import_buffer(host);
    g.add_compute_pass(
        name,
        [&](PassBuilder& pb) {
            pb.read(image, Access::TransferSrc);
            out = pb.write(out, Access::TransferDst);
        },
        [image, out](Cmd& c) { c.copy(image, out); });
    g.export_buffer(out, Access::HostRead);
}

const Spirv& level_step_kernel(std::uint32_t step) { return kSteps[step]; }

void add_level_step(Graph& g, std::uint32_t step, std::uint32_t side, std::uint32_t size, std::uint32_t base,
                    LevelBuffers& b, const std::string& name) {
    const std::size_t points = std::size_t(side) * side;
    // The shader binds every image; a step's unused ones are one-row stand-ins.
    auto texels = [&](std::size_t count, const std::string& what) {
        return g.create_image(texel_array_desc(count, Format::RGBA32U, what));
    };
    if (step == 0) b.grid = texels(2 * points, "hierarchy grid");
    ImageHandle cells = step == 1 ? texels(4 * points, "hierarchy cells") : step == 2 ? b.cells : texels(0, "unused");
    ImageHandle next = step == 2 ? texels(8 * points, "hierarchy grid") : texels(0, "unused");
    ImageHandle grid = b.grid;
    const LevelPush push{side, size, base};
    g.add_compute_pass(
        name,
        [&](PassBuilder& pb) {
            pb.read(b.bands, Access::ComputeRead);
            pb.read(b.directions, Access::ComputeRead);
            // The three steps' shaders share their bindings (level_step.glsl): each may write the
            // grid and the cells as far as validation can tell, so they are declared written where
            // a step reads them.
            grid = pb.write(grid, step == 0 ? Access::ComputeWrite : Access::ComputeReadWrite);
            cells = pb.write(cells, step == 2 ? Access::ComputeReadWrite : Access::ComputeWrite);
            next = pb.write(next, Access::ComputeWrite);
        },
        [=, bands = b.bands, dirs = b.directions](Cmd& c) {
            c.dispatch_threads(kSteps[step], {side, side}, {bands, dirs, grid, cells, next}, push);
        });
    b.cells = cells;
    b.grid = step == 2 ? next : grid;
}

void check_level_images(const Context& ctx, std::size_t texels, std::uint32_t size, const std::string& what) {
    const std::uint32_t most = ctx.device_info().max_image_dimension_2d;
    const std::size_t rows = (texels + kTexelArrayRowWidth - 1) / kTexelArrayRowWidth;
    if (rows > most || size > most)
        throw Error(ErrorKind::Unsupported, what + " needs images of " + std::to_string(std::max<std::size_t>(rows, size)) +
                                                " rows; the device allows " + std::to_string(most) +
                                                " (use the CPU: --cpu)");
}

HierarchyGrid grid_from_texels(const std::vector<std::byte>& texels, std::uint32_t side, std::uint32_t base) {
    HierarchyGrid out;
    out.side = side;
    out.base = base;
    const std::size_t count = std::size_t(side) * side;
    out.points.resize(count);
    out.valid.resize(count);
    out.outward.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        const std::byte* t = &texels[32 * i];
        double xyz[3];
        float outward;
        std::uint32_t kind;
        std::memcpy(xyz, t, 24);
        std::memcpy(&outward, t + 24, 4);
        std::memcpy(&kind, t + 28, 4);
        out.points[i] = {xyz[0], xyz[1], xyz[2]};
        out.valid[i] = std::uint8_t(kind);
        out.outward[i] = outward >= 0.0f ? 1 : -1;
    }
    return out;
}

}  // namespace gimg::passes::detail
