// The paper's relaxation (eq. 2) as Gauss-Seidel sweeps in colour order: the free vertices coloured
// so no two neighbours share a colour, each colour one compute dispatch (its rows update in place
// without reading each other), and the CPU twin running the same rows in the same order.
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

struct RelaxPush {
    std::uint32_t first, count, field, sweep;
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

std::size_t relax_gpu(Context& ctx, const ColouredRows& rows, double k, double tau, std::size_t max_sweeps,
                      std::vector<glm::dvec2>& uv, int field) {
    if (rows.vertex.empty()) return 1;
    Buffer vertex_buf = upload_buffer(ctx, rows.vertex, "relax rows");
    Buffer offset_buf = upload_buffer(ctx, rows.offsets, "relax offsets");
    Buffer column_buf = upload_buffer(ctx, rows.columns, "relax columns");
    Buffer weight_buf = upload_buffer(ctx, rows.weights, "relax weights");
    Buffer uv_buf = upload_buffer(ctx, uv, "relax uv");
    Buffer slot_buf = ctx.create_buffer({kSweepsPerCheck * 4, "relax worst corrections"});

    Graph g(ctx);
    auto vertex_h = g.import_buffer(vertex_buf), offset_h = g.import_buffer(offset_buf);
    auto column_h = g.import_buffer(column_buf), weight_h = g.import_buffer(weight_buf);
    auto uv_h = g.import_buffer(uv_buf), slot_h = g.import_buffer(slot_buf);
    g.add_loop(kSweepsPerCheck, [&] {
        for (std::uint32_t c = 0; c < rows.colour_count(); ++c) {
            const std::uint32_t first = rows.first[c], count = rows.first[c + 1] - first;
            if (count == 0) continue;
            g.add_compute_pass(
                "relax colour " + std::to_string(c),
                [&](PassBuilder& b) {
                    for (auto h : {vertex_h, offset_h, column_h, weight_h}) b.read(h, Access::ComputeRead);
                    uv_h = b.write(uv_h, Access::ComputeReadWrite);
                    slot_h = b.write(slot_h, Access::ComputeReadWrite);
                },
                [=, uv = uv_h, slots = slot_h](Cmd& cmd) {
                    cmd.dispatch_threads(kRelax, {count}, {vertex_h, offset_h, column_h, weight_h, uv, slots},
                                         RelaxPush{first, count, std::uint32_t(field), cmd.iteration(), k});
                });
        }
    });
    g.export_buffer(slot_h, Access::TransferSrc);
    g.export_buffer(uv_h, Access::TransferSrc);
    Plan plan = g.compile();
    const std::uint32_t limit = float_bits(tau);
    const std::vector<std::uint32_t> zeros(kSweepsPerCheck, 0);
    for (std::size_t done = 0; done < max_sweeps; done += kSweepsPerCheck) {
        ctx.upload(slot_buf, zeros.data(), zeros.size() * 4);
        plan.execute();
        std::vector<std::uint32_t> worst(kSweepsPerCheck);
        ctx.download(slot_buf, worst.data(), worst.size() * 4);
        for (std::uint32_t s = 0; s < kSweepsPerCheck; ++s)
            if (tau > 0.0 && worst[s] < limit) {
                ctx.download(uv_buf, uv.data(), uv.size() * 16);
                return done + s + 1;
            }
        if (tau == 0.0 && done + kSweepsPerCheck >= max_sweeps) {
            ctx.download(uv_buf, uv.data(), uv.size() * 16);
            return done + kSweepsPerCheck;
        }
    }
    throw geo::InputError("the relaxation did not settle within " + std::to_string(max_sweeps) + " sweeps");
}

}  // namespace gimg::passes::detail
