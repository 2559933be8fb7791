#include "gimg/passes/sample.h"

#include "gimg/engine/graph.h"
#include "gimg/engine/upload.h"
#include "gimg/geometry/error.h"

#include "sample/sample_frag.h"
#include "sample/sample_vert.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace gimg::passes {

namespace {

const RasterProgram kSample{GIMG_SPIRV(gimg_spv_sample_sample_vert), GIMG_SPIRV(gimg_spv_sample_sample_frag),
                            RasterState{.depth_test = false, .depth_write = false}};

void check_sampleable(const geo::Mesh& mesh, std::uint32_t size) {
    if (!mesh.has_texcoords()) throw geo::InputError("the mesh has no per-vertex texture coordinates to sample it by");
    if (mesh.face_count() == 0) throw geo::InputError("the mesh has no faces to sample");
    if (size < 2 || size > 16384) throw geo::InputError("sample size must be from 2 to 16384");
}

}  // namespace

ImageHandle add_sample(Graph& graph, BufferHandle positions, BufferHandle parameters, BufferHandle triangles,
                       std::uint32_t face_count, std::uint32_t size, const std::string& name) {
    if (face_count == 0) throw geo::InputError("the mesh has no faces to sample");
    if (size < 2 || size > 16384) throw geo::InputError("sample size must be from 2 to 16384");
    auto image = graph.create_image({size, size, Format::RGBA32F, name + " position image"});
    const std::uint32_t vertices = 3 * face_count;
    graph.add_raster_pass(
        name,
        [&](PassBuilder& b) {
            for (auto h : {parameters, triangles}) b.read(h, Access::VertexRead);
            for (auto h : {positions, parameters, triangles}) b.read(h, Access::FragmentRead);
            image = b.color(image, ClearValue::color(0, 0, 0, 0));
        },
        [=](Cmd& c) {
            const float pixels = float(size);
            c.draw(kSample, vertices, 1, {positions, parameters, triangles}, pixels);
        });
    return image;
}

PositionImage sample_gpu(Context& ctx, const geo::Mesh& mesh, std::uint32_t size) {
    check_sampleable(mesh, size);
    std::vector<float> positions(3 * mesh.vertex_count()), params(2 * mesh.vertex_count());
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
        for (int k = 0; k < 3; ++k) positions[3 * i + k] = float(mesh.positions[i][k]);
        params[2 * i] = float(mesh.texcoords[i].x);
        params[2 * i + 1] = float(mesh.texcoords[i].y);
    }
    Buffer pos_buf, par_buf, tri_buf;
    ctx.batch_uploads([&] {  // one submission for the three
        pos_buf = upload_buffer(ctx, positions, "positions");
        par_buf = upload_buffer(ctx, params, "parameters");
        tri_buf = upload_buffer(ctx, mesh.triangles, "triangles");
    });
    Graph g(ctx);
    const ImageHandle image = add_sample(g, g.import_buffer(pos_buf), g.import_buffer(par_buf),
                                         g.import_buffer(tri_buf), std::uint32_t(mesh.face_count()), size);
    g.export_image(image, Access::TransferSrc);
    Plan plan = g.compile();
    plan.execute();
    const std::vector<std::byte> bytes = ctx.download(plan.image(image));
    const float* rgba = reinterpret_cast<const float*>(bytes.data());
    PositionImage out(size, size);
    for (std::size_t i = 0; i < out.covered.size(); ++i) {
        if (rgba[4 * i + 3] == 0.0f) continue;
        out.covered[i] = 1;
        for (int k = 0; k < 3; ++k) out.xyz[3 * i + k] = rgba[4 * i + k];
    }
    return out;
}

PositionImage sample_cpu(const geo::Mesh& mesh, std::uint32_t size) {
    check_sampleable(mesh, size);
    PositionImage out(size, size);
    const double n = size;
    for (const glm::uvec3& t : mesh.triangles) {
        // Pixel coordinates of the corners: x = s N, y = (1 - t) N; centres at +0.5.
        glm::dvec2 p[3];
        for (int k = 0; k < 3; ++k) p[k] = {mesh.texcoords[t[k]].x * n, (1.0 - mesh.texcoords[t[k]].y) * n};
        const double area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x);
        if (area == 0.0) continue;
        const double lo_x = std::min({p[0].x, p[1].x, p[2].x}), hi_x = std::max({p[0].x, p[1].x, p[2].x});
        const double lo_y = std::min({p[0].y, p[1].y, p[2].y}), hi_y = std::max({p[0].y, p[1].y, p[2].y});
        const long i0 = std::max(0L, long(std::ceil(lo_x - 0.5))),
                   i1 = std::min(long(size) - 1, long(std::floor(hi_x - 0.5)));
        const long j0 = std::max(0L, long(std::ceil(lo_y - 0.5))),
                   j1 = std::min(long(size) - 1, long(std::floor(hi_y - 0.5)));
        for (long j = j0; j <= j1; ++j)
            for (long i = i0; i <= i1; ++i) {
                const glm::dvec2 c{double(i) + 0.5, double(j) + 0.5};
                const double w0 = ((p[1].x - c.x) * (p[2].y - c.y) - (p[1].y - c.y) * (p[2].x - c.x)) / area;
                const double w1 = ((p[2].x - c.x) * (p[0].y - c.y) - (p[2].y - c.y) * (p[0].x - c.x)) / area;
                const double w2 = 1.0 - w0 - w1;
                if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
                const glm::dvec3 q = w0 * mesh.positions[t.x] + w1 * mesh.positions[t.y] + w2 * mesh.positions[t.z];
                const std::size_t o = out.index(std::uint32_t(i), std::uint32_t(j));
                out.covered[o] = 1;
                for (int k = 0; k < 3; ++k) out.xyz[3 * o + k] = float(q[k]);
            }
    }
    return out;
}

}  // namespace gimg::passes
