// The paper's relaxation (eq. 2) as Gauss-Seidel sweeps in colour order: the free vertices coloured
// so no two neighbours share a colour (its rows update in place without reading each other), one
// workgroup per field sweeping colour after colour, and the CPU twin running the same rows in the
// same order.
#include "quad_region/relaxation.h"

#include "gimg/engine/graph.h"
#include "gimg/engine/upload.h"
#include "gimg/geometry/error.h"

#include "quad_region/relax_comp.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace gimg::passes::detail {

namespace {

const Spirv kRelax = GIMG_SPIRV(gimg_spv_quad_region_relax_comp);

struct RelaxPush {  // shaders/quad_region/relax.comp
    std::uint32_t colours, limit, max_sweeps, pad;
    double k;
};

std::uint32_t float_bits(double x) {
    const float f = float(x);
    std::uint32_t bits;
    std::memcpy(&bits, &f, 4);
    return bits;
}

}  // namespace

ColouredRows colour_rows(const geo::MeshAdjacency& adj, const std::vector<double>& weights,
                         const std::vector<std::uint8_t>& interior) {
    const std::size_t n = adj.vertex_count();
    std::vector<std::uint32_t> colour(n, 0xffffffffu);
    std::vector<std::uint32_t> count;  // rows per colour
    std::vector<std::uint8_t> used;    // scratch, reused from vertex to vertex
    for (std::uint32_t v = 0; v < n; ++v) {
        if (!interior[v]) continue;
        used.assign(adj.neighbors(v).size() + 1, 0);
        for (std::uint32_t w : adj.neighbors(v))
            if (interior[w] && colour[w] < used.size()) used[colour[w]] = 1;
        colour[v] = std::uint32_t(std::find(used.begin(), used.end(), 0) - used.begin());
        if (colour[v] >= count.size()) count.resize(colour[v] + 1, 0);
        ++count[colour[v]];
    }
    // Rows by colour, then vertex: a counting sort.
    ColouredRows rows;
    rows.first.assign(count.size() + 1, 0);
    for (std::size_t c = 0; c < count.size(); ++c) rows.first[c + 1] = rows.first[c] + count[c];
    rows.vertex.resize(rows.first.back());
    std::vector<std::uint32_t> fill(rows.first.begin(), rows.first.end() - 1);
    for (std::uint32_t v = 0; v < n; ++v)
        if (colour[v] != 0xffffffffu) rows.vertex[fill[colour[v]]++] = v;
    rows.offsets.assign(1, 0);
    rows.offsets.reserve(rows.vertex.size() + 1);
    for (const std::uint32_t v : rows.vertex) {
        const auto nb = adj.neighbors(v);
        rows.columns.insert(rows.columns.end(), nb.begin(), nb.end());
        rows.weights.insert(rows.weights.end(), weights.begin() + adj.vertex_vertex_offsets[v],
                            weights.begin() + adj.vertex_vertex_offsets[v] + nb.size());
        rows.offsets.push_back(std::uint32_t(rows.columns.size()));
    }
    return rows;
}

std::uint32_t ColouredRows::colour_count() const { return std::uint32_t(first.size() - 1); }

std::size_t relax_cpu(const ColouredRows& rows, double k, double tau, std::size_t max_sweeps,
                      std::vector<glm::dvec2>& uv, int field) {
    const std::uint32_t limit = float_bits(tau);
    // The field on its own, renumbered so that row r's value is values[r] and the fixed vertices
    // follow the rows: the rows read and write one contiguous array, and the other field can be
    // relaxed on another core without sharing cache lines.
    const std::size_t rows_n = rows.vertex.size();
    std::vector<std::uint32_t> slot(uv.size(), 0xffffffffu);
    for (std::size_t r = 0; r < rows_n; ++r) slot[rows.vertex[r]] = std::uint32_t(r);
    std::uint32_t next = std::uint32_t(rows_n);
    for (auto& s : slot)
        if (s == 0xffffffffu) s = next++;
    std::vector<double> values(uv.size());
    for (std::size_t i = 0; i < uv.size(); ++i) values[slot[i]] = uv[i][field];
    std::vector<std::uint32_t> columns(rows.columns.size());
    for (std::size_t e = 0; e < columns.size(); ++e) columns[e] = slot[rows.columns[e]];
    const std::uint32_t* offset = rows.offsets.data();
    const std::uint32_t* column = columns.data();
    const double* weight = rows.weights.data();
    double* x = values.data();
    for (std::size_t done = 0; done < max_sweeps; done += kSweepsPerCheck) {
        std::size_t converged = 0;
        for (std::uint32_t s = 0; s < kSweepsPerCheck; ++s) {
            // Rounding to float is monotonic: the float of the largest correction is the shader's
            // largest float correction. A NaN sticks, as its float bits win the shader's atomicMax.
            double worst = 0.0;
            for (std::size_t r = 0; r < rows_n; ++r) {
                // The shader's order of operations, rounded the same way (no fused multiply-add).
                double mean = 0.0;
                for (std::uint32_t e = offset[r]; e < offset[r + 1]; ++e) mean += weight[e] * x[column[e]];
                const double correction = std::abs(mean - x[r]);
                if (correction > worst || std::isnan(correction)) worst = std::isnan(worst) ? worst : correction;
                x[r] = k * x[r] + (1.0 - k) * mean;
            }
            if (!converged && tau > 0.0 && float_bits(worst) < limit) converged = done + s + 1;
        }
        if (converged || (tau == 0.0 && done + kSweepsPerCheck >= max_sweeps)) {
            for (std::size_t i = 0; i < uv.size(); ++i) uv[i][field] = values[slot[i]];
            return converged ? converged : done + kSweepsPerCheck;
        }
    }
    throw geo::InputError("the relaxation did not settle within " + std::to_string(max_sweeps) + " sweeps");
}

std::array<std::size_t, 2> relax_gpu(Context& ctx, const ColouredRows& rows, double k, double tau,
                                     std::size_t max_sweeps, std::vector<glm::dvec2>& uv) {
    if (rows.vertex.empty()) return {1, 1};
    if (max_sweeps > 0x7fffffffu) throw geo::InputError("the relaxation's sweep limit is too large");
    // One submission for the six uploads (a real GPU waits for each: Context::batch_uploads).
    Buffer vertex_buf, offset_buf, column_buf, weight_buf, colour_buf, uv_buf;
    ctx.batch_uploads([&] {
        vertex_buf = upload_buffer(ctx, rows.vertex, "relax rows");
        offset_buf = upload_buffer(ctx, rows.offsets, "relax offsets");
        column_buf = upload_buffer(ctx, rows.columns, "relax columns");
        weight_buf = upload_buffer(ctx, rows.weights, "relax weights");
        colour_buf = upload_buffer(ctx, rows.first, "relax colours");
        uv_buf = upload_buffer(ctx, uv, "relax uv");
    });
    Buffer slot_buf = ctx.create_buffer({2 * kSweepsPerCheck * 4, "relax worst corrections"});
    // Read after every submission: host-visible, so reading it costs no copy.
    Buffer progress_buf = ctx.create_buffer({4 * 4, "relax progress"}, MemoryUsage::Readback);
    const std::array<std::uint32_t, 4> zeros{};
    ctx.upload(progress_buf, zeros.data(), sizeof zeros);

    Graph g(ctx);
    const std::array<BufferHandle, 5> inputs{g.import_buffer(vertex_buf), g.import_buffer(offset_buf),
                                             g.import_buffer(column_buf), g.import_buffer(weight_buf),
                                             g.import_buffer(colour_buf)};
    BufferHandle uv_h = g.import_buffer(uv_buf), slot_h = g.import_buffer(slot_buf);
    BufferHandle progress_h = g.import_buffer(progress_buf);
    const RelaxPush push{rows.colour_count(), float_bits(tau), std::uint32_t(max_sweeps), 0, k};
    g.add_loop(GIMG_RELAX_DISPATCHES, [&] {
        g.add_compute_pass(
            "relax: clear the corrections", [&](PassBuilder& b) { slot_h = b.write(slot_h, Access::TransferDst); },
            [slots = slot_h](Cmd& cmd) { cmd.fill(slots, 0); });
        g.add_compute_pass(
            "relax",
            [&](PassBuilder& b) {
                for (auto h : inputs) b.read(h, Access::ComputeRead);
                uv_h = b.write(uv_h, Access::ComputeReadWrite);
                slot_h = b.write(slot_h, Access::ComputeReadWrite);
                progress_h = b.write(progress_h, Access::ComputeReadWrite);
            },
            [=, uv = uv_h, slots = slot_h, progress = progress_h](Cmd& cmd) {
                cmd.dispatch(kRelax, {2, 1, 1},
                             {inputs[0], inputs[1], inputs[2], inputs[3], uv, slots, inputs[4], progress}, push);
            });
    });
    g.export_buffer(progress_h, Access::HostRead);
    g.export_buffer(uv_h, Access::TransferSrc);
    Plan plan = g.compile();
    // Each submission advances a field that has not stopped by GIMG_RELAX_DISPATCHES chunks.
    for (;;) {
        plan.execute();
        std::array<std::uint32_t, 4> progress{};
        ctx.download(progress_buf, progress.data(), sizeof progress);
        bool finished = true;
        for (int field = 0; field < 2; ++field) {
            const bool settled = progress[2 * field + 1] != 0, spent = progress[2 * field] >= max_sweeps;
            if (!settled && spent && tau > 0.0)
                throw geo::InputError("the relaxation did not settle within " + std::to_string(max_sweeps) + " sweeps");
            finished = finished && (settled || spent);
        }
        if (finished) {
            ctx.download(uv_buf, uv.data(), uv.size() * 16);
            return {progress[0], progress[2]};
        }
    }
}

}  // namespace gimg::passes::detail
