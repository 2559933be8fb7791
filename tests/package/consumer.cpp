// Uses each exported target once: engine (context, graph), passes (a scan), geometry (a mesh).
#include <gimg/engine/context.h>
#include <gimg/engine/graph.h>
#include <gimg/geometry/mesh.h>
#include <gimg/passes/primitives.h>

#include <cstdio>
#include <vector>

int main() {
    gimg::geo::Mesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.triangles = {{0, 1, 2}};

    auto ctx = gimg::Context::create();
    std::vector<std::uint32_t> ones(100, 1);
    gimg::Buffer in = ctx->create_buffer({400, "ones"});
    gimg::Buffer out = ctx->create_buffer({400, "sums"});
    ctx->upload(in, ones.data(), 400);
    gimg::Graph g(*ctx);
    auto sums = gimg::passes::add_inclusive_scan(g, g.import_buffer(in), g.import_buffer(out), 100);
    g.export_buffer(sums, gimg::Access::TransferSrc);
    g.compile().execute();
    auto result = ctx->download<std::uint32_t>(out);
    std::printf("consumer: %s, last prefix sum %u, mesh diagonal %.3f\n", ctx->device_info().name.c_str(),
                result.back(), mesh.bounds().diagonal());
    return result.back() == 100 ? 0 : 1;
}
