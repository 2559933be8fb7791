// Piecewise-linear k-disk wavelets on a semi-regular mesh (Lounsbery, DeRose & Warren 1997;
// sec. 2.5): the local orthogonalisation weights, and the lifting transform on the CPU and GPU.
#include "gimg/engine/error.h"
#include "gimg/engine/upload.h"
#include "gimg/geometry/error.h"
#include "gimg/passes/maps.h"

#include "maps/wavelet_predict_comp.h"
#include "maps/wavelet_update_comp.h"

#include <Eigen/Dense>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <span>
#include <string>

namespace gimg::passes {

namespace {

static_assert(sizeof(glm::dvec3) == 24 && sizeof(glm::uvec2) == 8, "tightly packed vectors upload as arrays");

// Vertex -> items of one level, compressed (offsets of V + 1 entries).
struct Csr {
    std::vector<std::uint32_t> offsets, items;
    auto row(std::uint32_t v) const {
        return std::span<const std::uint32_t>(items.data() + offsets[v], offsets[v + 1] - offsets[v]);
    }
};

Csr vertex_faces(const std::vector<glm::uvec3>& faces, std::uint32_t vertices) {
    Csr c;
    c.offsets.assign(vertices + 1, 0);
    for (const glm::uvec3& t : faces)
        for (int k = 0; k < 3; ++k) ++c.offsets[t[k] + 1];
    for (std::uint32_t v = 0; v < vertices; ++v) c.offsets[v + 1] += c.offsets[v];
    c.items.resize(c.offsets.back());
    std::vector<std::uint32_t> fill(c.offsets.begin(), c.offsets.end() - 1);
    for (std::uint32_t f = 0; f < faces.size(); ++f)
        for (int k = 0; k < 3; ++k) c.items[fill[faces[f][k]]++] = f;
    return c;
}

Csr vertex_neighbours(const std::vector<glm::uvec3>& faces, const Csr& vf, std::uint32_t vertices) {
    Csr c;
    c.offsets.push_back(0);
    std::vector<std::uint32_t> ring;
    for (std::uint32_t v = 0; v < vertices; ++v) {
        ring.clear();
        for (std::uint32_t f : vf.row(v))
            for (int k = 0; k < 3; ++k)
                if (faces[f][k] != v) ring.push_back(faces[f][k]);
        std::sort(ring.begin(), ring.end());
        ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
        c.items.insert(c.items.end(), ring.begin(), ring.end());
        c.offsets.push_back(std::uint32_t(c.items.size()));
    }
    return c;
}

void check_mesh(const SemiRegularMesh& mesh) {
    if (mesh.faces.empty() || mesh.vertex_count.size() != mesh.faces.size() ||
        mesh.parents.size() != mesh.vertex_count.back() - mesh.vertex_count.front())
        throw geo::InputError("wavelets: not a semi-regular mesh from subdivide_base");
}

void check_filters(const SemiRegularMesh& mesh, const WaveletFilters& filters) {
    if (filters.levels.size() != mesh.levels())
        throw geo::InputError("wavelet filters: " + std::to_string(filters.levels.size()) + " levels for a mesh of " +
                              std::to_string(mesh.levels()));
    for (std::uint32_t j = 0; j < mesh.levels(); ++j) {
        const WaveletFilters::Level& l = filters.levels[j];
        if (l.offsets.size() != std::size_t(mesh.vertex_count[j]) + 1 || l.offsets.front() != 0 ||
            l.odd.size() != l.offsets.back() || l.weight.size() != l.odd.size() ||
            !std::is_sorted(l.offsets.begin(), l.offsets.end()))
            throw geo::InputError("wavelet filters: level " + std::to_string(j) + " does not fit the mesh");
        for (std::uint32_t m : l.odd)
            if (m < mesh.vertex_count[j] || m >= mesh.vertex_count[j + 1])
                throw geo::InputError("wavelet filters: level " + std::to_string(j) + " names vertex " +
                                      std::to_string(m) + ", not one of its odd vertices");
    }
}

void check_values(const SemiRegularMesh& mesh, std::size_t values, std::uint32_t level, const char* what) {
    check_mesh(mesh);
    if (values != mesh.vertex_count.back())
        throw geo::InputError(std::string(what) + ": " + std::to_string(values) + " values for " +
                              std::to_string(mesh.vertex_count.back()) + " vertices");
    if (level > mesh.levels())
        throw geo::InputError(std::string(what) + ": level " + std::to_string(level) + " of " +
                              std::to_string(mesh.levels()));
}

// The weights of one level, as (even vertex, odd vertex, s) rows in order of the odd vertex.
struct Entry {
    std::uint32_t even, odd;
    double s;
};

// s_{., m} for every odd vertex m of level j + 1. In units of 48 times a level-j triangle's
// normalised area, the hats' products are integers: <phi_i, phi_i> = 8 per triangle at i,
// <phi_i, phi_l> = 4 per triangle holding both, and per triangle (a, b, c) on m's parent edge
// (a, b), <phi_a, phi'_m> = <phi_b, phi'_m> = 5 and <phi_c, phi'_m> = 2 (phi'_m of level j + 1;
// from the refinement relation and the fine triangles of a quarter of the area).
std::vector<Entry> level_weights(const SemiRegularMesh& mesh, std::uint32_t j, int k) {
    const std::vector<glm::uvec3>& faces = mesh.faces[j];
    const std::uint32_t vertices = mesh.vertex_count[j];
    const Csr vf = vertex_faces(faces, vertices);
    const Csr ring = vertex_neighbours(faces, vf, vertices);
    std::vector<std::uint32_t> stamp(vertices, ~0u), local(vertices, 0);
    std::vector<std::uint32_t> disk, touched;
    std::vector<Entry> entries;
    for (std::uint32_t m = vertices; m < mesh.vertex_count[j + 1]; ++m) {
        const glm::uvec2 p = mesh.parents[m - mesh.vertex_count[0]];
        // D_k(m): the parent edge's ends grown by k level-j rings.
        disk.clear();
        for (std::uint32_t v : {p.x, p.y})
            if (stamp[v] != m) {
                stamp[v] = m;
                local[v] = std::uint32_t(disk.size());
                disk.push_back(v);
            }
        std::size_t frontier = 0;
        for (int step = 0; step < k; ++step) {
            const std::size_t end = disk.size();
            for (std::size_t q = frontier; q < end; ++q)
                for (std::uint32_t w : ring.row(disk[q]))
                    if (stamp[w] != m) {
                        stamp[w] = m;
                        local[w] = std::uint32_t(disk.size());
                        disk.push_back(w);
                    }
            frontier = end;
        }
        const auto n = Eigen::Index(disk.size());
        touched.clear();
        for (std::uint32_t v : disk) touched.insert(touched.end(), vf.row(v).begin(), vf.row(v).end());
        std::sort(touched.begin(), touched.end());
        touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
        Eigen::MatrixXd g = Eigen::MatrixXd::Zero(n, n);
        Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
        for (std::uint32_t f : touched) {
            const glm::uvec3 t = faces[f];
            for (int r = 0; r < 3; ++r) {
                if (stamp[t[r]] != m) continue;
                g(local[t[r]], local[t[r]]) += 8.0;
                for (int s = 0; s < 3; ++s)
                    if (s != r && stamp[t[s]] == m) g(local[t[r]], local[t[s]]) += 4.0;
            }
            for (int r = 0; r < 3; ++r) {
                const std::uint32_t u = t[r], v = t[(r + 1) % 3], c = t[(r + 2) % 3];
                if ((u == p.x && v == p.y) || (u == p.y && v == p.x)) {
                    b(local[u]) += 5.0;
                    b(local[v]) += 5.0;
                    if (stamp[c] == m) b(local[c]) += 2.0;
                }
            }
        }
        const Eigen::LDLT<Eigen::MatrixXd> ldlt(g);
        const Eigen::VectorXd s = ldlt.solve(b);
        if (ldlt.info() != Eigen::Success || !s.allFinite())
            throw geo::InputError("wavelet filters: singular Gram matrix at odd vertex " + std::to_string(m) +
                                  " of level " + std::to_string(j + 1));
        for (Eigen::Index q = 0; q < n; ++q) entries.push_back({disk[std::size_t(q)], m, s(q)});
    }
    return entries;
}

// A level-j detail's weight in keep_largest_details: the norm 2^-(j+1) of its odd vertex's hat.
double detail_scale(std::uint32_t j) { return std::ldexp(1.0, -int(j) - 1); }

}  // namespace

WaveletFilters wavelet_filters(const SemiRegularMesh& mesh, int k) {
    check_mesh(mesh);
    if (k > 2) throw geo::InputError("wavelet filters: k = " + std::to_string(k) + " (k-disk for k = 0, 1, 2)");
    WaveletFilters out;
    out.k = k < 0 ? -1 : k;
    for (std::uint32_t j = 0; j < mesh.levels(); ++j) {
        WaveletFilters::Level level;
        level.offsets.assign(std::size_t(mesh.vertex_count[j]) + 1, 0);
        if (k >= 0) {
            const std::vector<Entry> entries = level_weights(mesh, j, k);
            for (const Entry& e : entries) ++level.offsets[e.even + 1];
            for (std::size_t v = 0; v < mesh.vertex_count[j]; ++v) level.offsets[v + 1] += level.offsets[v];
            level.odd.resize(entries.size());
            level.weight.resize(entries.size());
            std::vector<std::uint32_t> fill(level.offsets.begin(), level.offsets.end() - 1);
            for (const Entry& e : entries) {
                level.odd[fill[e.even]] = e.odd;
                level.weight[fill[e.even]++] = e.s;
            }
        }
        out.levels.push_back(std::move(level));
    }
    return out;
}

void wavelet_analysis(const SemiRegularMesh& mesh, const WaveletFilters& filters, std::vector<glm::dvec3>& values,
                      std::uint32_t down_to) {
    check_values(mesh, values.size(), down_to, "wavelet analysis");
    check_filters(mesh, filters);
    for (std::uint32_t j = mesh.levels(); j-- > down_to;) {
        const std::uint32_t first = mesh.vertex_count[j], v0 = mesh.vertex_count[0];
        for (std::uint32_t m = first; m < mesh.vertex_count[j + 1]; ++m) {
            const glm::uvec2 p = mesh.parents[m - v0];
            values[m] = values[m] - 0.5 * (values[p.x] + values[p.y]);
        }
        const WaveletFilters::Level& l = filters.levels[j];
        for (std::uint32_t i = 0; i < first; ++i) {
            glm::dvec3 sum(0.0);
            for (std::uint32_t e = l.offsets[i]; e < l.offsets[i + 1]; ++e) sum += l.weight[e] * values[l.odd[e]];
            values[i] = values[i] + sum;
        }
    }
}

void wavelet_synthesis(const SemiRegularMesh& mesh, const WaveletFilters& filters, std::vector<glm::dvec3>& values,
                       std::uint32_t from) {
    check_values(mesh, values.size(), from, "wavelet synthesis");
    check_filters(mesh, filters);
    for (std::uint32_t j = from; j < mesh.levels(); ++j) {
        const std::uint32_t first = mesh.vertex_count[j], v0 = mesh.vertex_count[0];
        const WaveletFilters::Level& l = filters.levels[j];
        for (std::uint32_t i = 0; i < first; ++i) {
            glm::dvec3 sum(0.0);
            for (std::uint32_t e = l.offsets[i]; e < l.offsets[i + 1]; ++e) sum += l.weight[e] * values[l.odd[e]];
            values[i] = values[i] - sum;
        }
        for (std::uint32_t m = first; m < mesh.vertex_count[j + 1]; ++m) {
            const glm::uvec2 p = mesh.parents[m - v0];
            values[m] = values[m] + 0.5 * (values[p.x] + values[p.y]);
        }
    }
}

WaveletBuffers upload_wavelet_filters(Context& ctx, const SemiRegularMesh& mesh, const WaveletFilters& filters) {
    check_mesh(mesh);
    check_filters(mesh, filters);
    if (!ctx.device_info().shader_float64)
        throw Error(ErrorKind::Unsupported, "wavelets on the GPU need shaderFloat64 (use the CPU)");
    WaveletBuffers out;
    std::vector<std::uint32_t> offsets, odd;
    std::vector<double> weight;
    for (const WaveletFilters::Level& l : filters.levels) {
        out.offsets_start.push_back(std::uint32_t(offsets.size()));
        out.entries_start.push_back(std::uint32_t(odd.size()));
        offsets.insert(offsets.end(), l.offsets.begin(), l.offsets.end());
        odd.insert(odd.end(), l.odd.begin(), l.odd.end());
        weight.insert(weight.end(), l.weight.begin(), l.weight.end());
    }
    out.offsets_start.push_back(std::uint32_t(offsets.size()));
    out.entries_start.push_back(std::uint32_t(odd.size()));
    const VkDeviceSize limit = ctx.device_info().max_storage_buffer_range;
    if (VkDeviceSize(mesh.vertex_count.back()) * 24 > limit || VkDeviceSize(weight.size()) * 8 > limit ||
        VkDeviceSize(offsets.size()) * 4 > limit)
        throw Error(ErrorKind::Unsupported, "wavelets on the GPU: the mesh's arrays exceed maxStorageBufferRange (" +
                                                std::to_string(limit) + " bytes); use the CPU");
    out.parents = upload_buffer(ctx, mesh.parents, "wavelet parents");
    out.offsets = upload_buffer(ctx, offsets, "wavelet offsets");
    out.odd = upload_buffer(ctx, odd, "wavelet odd");
    out.weight = upload_buffer(ctx, weight, "wavelet weights");
    return out;
}

namespace {

struct PredictPush {
    std::uint32_t first, count, parent0, inverse;
};
struct UpdatePush {
    std::uint32_t count, offsets0, entries0, inverse;
};

const Spirv kPredict = GIMG_SPIRV(gimg_spv_maps_wavelet_predict_comp);
const Spirv kUpdate = GIMG_SPIRV(gimg_spv_maps_wavelet_update_comp);

struct FilterHandles {
    BufferHandle parents, offsets, odd, weight;
};

FilterHandles import_filters(Graph& graph, const SemiRegularMesh& mesh, WaveletBuffers& filters) {
    if (filters.offsets_start.size() != mesh.levels() + 1 || filters.entries_start.size() != mesh.levels() + 1 ||
        !filters.parents)
        throw geo::InputError("wavelet filters on the GPU: uploaded for another mesh");
    return {graph.import_buffer(filters.parents), graph.import_buffer(filters.offsets),
            graph.import_buffer(filters.odd), graph.import_buffer(filters.weight)};
}

BufferHandle add_predict(Graph& graph, BufferHandle values, BufferHandle parents, const SemiRegularMesh& mesh,
                         std::uint32_t j, bool inverse) {
    const PredictPush push{mesh.vertex_count[j], mesh.vertex_count[j + 1] - mesh.vertex_count[j],
                           mesh.vertex_count[j] - mesh.vertex_count[0], inverse ? 1u : 0u};
    graph.add_compute_pass(
        std::string(inverse ? "wavelet synthesis" : "wavelet analysis") + ": predict level " + std::to_string(j + 1),
        [&](PassBuilder& b) {
            b.read(parents, Access::ComputeRead);
            values = b.write(values, Access::ComputeReadWrite);
        },
        [=](Cmd& c) {
            c.dispatch_threads(kPredict, {std::max(push.count, 1u)}, {values, parents}, push);
        });
    return values;
}

BufferHandle add_update(Graph& graph, BufferHandle values, const FilterHandles& f, const SemiRegularMesh& mesh,
                        const WaveletBuffers& filters, std::uint32_t j, bool inverse) {
    const UpdatePush push{mesh.vertex_count[j], filters.offsets_start[j], filters.entries_start[j], inverse ? 1u : 0u};
    graph.add_compute_pass(
        std::string(inverse ? "wavelet synthesis" : "wavelet analysis") + ": update level " + std::to_string(j),
        [&](PassBuilder& b) {
            for (BufferHandle h : {f.offsets, f.odd, f.weight}) b.read(h, Access::ComputeRead);
            values = b.write(values, Access::ComputeReadWrite);
        },
        [=](Cmd& c) {
            c.dispatch_threads(kUpdate, {std::max(push.count, 1u)}, {values, f.offsets, f.odd, f.weight}, push);
        });
    return values;
}

}  // namespace

BufferHandle add_wavelet_analysis(Graph& graph, BufferHandle values, const SemiRegularMesh& mesh,
                                  WaveletBuffers& filters, std::uint32_t down_to) {
    check_values(mesh, mesh.vertex_count.back(), down_to, "wavelet analysis");
    const FilterHandles f = import_filters(graph, mesh, filters);
    for (std::uint32_t j = mesh.levels(); j-- > down_to;) {
        values = add_predict(graph, values, f.parents, mesh, j, false);
        if (filters.entries_start[j + 1] > filters.entries_start[j])
            values = add_update(graph, values, f, mesh, filters, j, false);
    }
    return values;
}

BufferHandle add_wavelet_synthesis(Graph& graph, BufferHandle values, const SemiRegularMesh& mesh,
                                   WaveletBuffers& filters, std::uint32_t from) {
    check_values(mesh, mesh.vertex_count.back(), from, "wavelet synthesis");
    const FilterHandles f = import_filters(graph, mesh, filters);
    for (std::uint32_t j = from; j < mesh.levels(); ++j) {
        if (filters.entries_start[j + 1] > filters.entries_start[j])
            values = add_update(graph, values, f, mesh, filters, j, true);
        values = add_predict(graph, values, f.parents, mesh, j, true);
    }
    return values;
}

namespace {

std::vector<glm::dvec3> run_gpu(Context& ctx, const SemiRegularMesh& mesh, WaveletBuffers& buffers,
                                const std::vector<glm::dvec3>& values, std::uint32_t level, bool synthesis) {
    const char* what = synthesis ? "wavelet synthesis" : "wavelet analysis";
    check_values(mesh, values.size(), level, what);
    Buffer data = upload_buffer(ctx, values, "wavelet values");
    Graph g(ctx);
    BufferHandle h = g.import_buffer(data);
    h = synthesis ? add_wavelet_synthesis(g, h, mesh, buffers, level)
                  : add_wavelet_analysis(g, h, mesh, buffers, level);
    g.export_buffer(h, Access::TransferSrc);
    Plan plan = g.compile();
    plan.execute();
    std::vector<glm::dvec3> out(values.size());
    ctx.download(data, out.data(), out.size() * sizeof(glm::dvec3));
    return out;
}

}  // namespace

std::vector<glm::dvec3> wavelet_analysis_gpu(Context& ctx, const SemiRegularMesh& mesh, const WaveletFilters& filters,
                                             const std::vector<glm::dvec3>& values, std::uint32_t down_to) {
    check_values(mesh, values.size(), down_to, "wavelet analysis");
    WaveletBuffers buffers = upload_wavelet_filters(ctx, mesh, filters);
    return run_gpu(ctx, mesh, buffers, values, down_to, false);
}

std::vector<glm::dvec3> wavelet_synthesis_gpu(Context& ctx, const SemiRegularMesh& mesh, const WaveletFilters& filters,
                                              const std::vector<glm::dvec3>& values, std::uint32_t from) {
    check_values(mesh, values.size(), from, "wavelet synthesis");
    WaveletBuffers buffers = upload_wavelet_filters(ctx, mesh, filters);
    return run_gpu(ctx, mesh, buffers, values, from, true);
}

std::vector<glm::dvec3> wavelet_analysis_gpu(Context& ctx, const SemiRegularMesh& mesh, WaveletBuffers& filters,
                                             const std::vector<glm::dvec3>& values, std::uint32_t down_to) {
    return run_gpu(ctx, mesh, filters, values, down_to, false);
}

std::vector<glm::dvec3> wavelet_synthesis_gpu(Context& ctx, const SemiRegularMesh& mesh, WaveletBuffers& filters,
                                              const std::vector<glm::dvec3>& values, std::uint32_t from) {
    return run_gpu(ctx, mesh, filters, values, from, true);
}

std::size_t keep_largest_details(const SemiRegularMesh& mesh, std::vector<glm::dvec3>& coefficients, double fraction) {
    check_values(mesh, coefficients.size(), 0, "keep_largest_details");
    if (!(fraction >= 0.0 && fraction <= 1.0))
        throw geo::InputError("keep_largest_details: fraction " + std::to_string(fraction) + " outside [0, 1]");
    const std::uint32_t v0 = mesh.vertex_count[0];
    const std::size_t details = coefficients.size() - v0;
    const auto keep = std::size_t(std::llround(fraction * double(details)));
    std::vector<double> size(details);
    for (std::uint32_t j = 0; j < mesh.levels(); ++j)
        for (std::uint32_t m = mesh.vertex_count[j]; m < mesh.vertex_count[j + 1]; ++m)
            size[m - v0] = glm::length(coefficients[m]) * detail_scale(j);
    std::vector<std::uint32_t> order(details);
    for (std::uint32_t q = 0; q < details; ++q) order[q] = q;
    // Largest first; ties by id, so the kept set is the same on every platform.
    auto larger = [&](std::uint32_t x, std::uint32_t y) { return size[x] != size[y] ? size[x] > size[y] : x < y; };
    if (keep < details) std::nth_element(order.begin(), order.begin() + std::ptrdiff_t(keep), order.end(), larger);
    for (std::size_t q = keep; q < details; ++q) coefficients[v0 + order[q]] = glm::dvec3(0.0);
    return keep;
}

}  // namespace gimg::passes
