// Piecewise-linear k-disk wavelets on a semi-regular mesh (Lounsbery, DeRose & Warren 1997;
// sec. 2.5): the local orthogonalisation weights, and the lifting transform on the CPU and GPU.
#include "gimg/engine/error.h"
#include "gimg/engine/texel_array.h"
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

namespace {
// The values' texel array: three doubles of two 32-bit texels per vertex.
std::size_t value_texels(const SemiRegularMesh& mesh) { return std::size_t(mesh.vertex_count.back()) * 6; }
}  // namespace

bool wavelets_fit_device(const Context& ctx, const SemiRegularMesh& mesh, const WaveletFilters& filters) {
    std::size_t offsets = 0, entries = 0;
    for (const WaveletFilters::Level& l : filters.levels) {
        offsets += l.offsets.size();
        entries += l.odd.size();
    }
    const std::size_t largest = std::max({value_texels(mesh), mesh.parents.size() * 2, offsets, entries * 2});
    const std::size_t rows = (largest + kTexelArrayRowWidth - 1) / kTexelArrayRowWidth;
    return ctx.device_info().shader_float64 && rows <= ctx.device_info().max_image_dimension_2d;
}

WaveletBuffers upload_wavelet_filters(Context& ctx, const SemiRegularMesh& mesh, const WaveletFilters& filters) {
    check_mesh(mesh);
    check_filters(mesh, filters);
    if (!ctx.device_info().shader_float64)
        throw Error(ErrorKind::Unsupported, "wavelets on the GPU need shaderFloat64 (use the CPU)");
    check_texel_array_size(ctx, value_texels(mesh), "wavelets on the GPU: the values");
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
    // Two 32-bit texels per uvec2 and per double (low word first, as the host stores them).
    auto words = [](const auto& v) {
        const auto* w = reinterpret_cast<const std::uint32_t*>(v.data());
        return std::span<const std::uint32_t>(w, v.size() * sizeof(v[0]) / 4);
    };
    ctx.batch_uploads([&] {  // one submission for the four
        out.parents = upload_texel_array(ctx, words(mesh.parents), Format::R32U, "wavelet parents");
        out.offsets = upload_texel_array(ctx, std::span<const std::uint32_t>(offsets), Format::R32U, "wavelet offsets");
        out.odd = upload_texel_array(ctx, std::span<const std::uint32_t>(odd), Format::R32U, "wavelet odd");
        out.weight = upload_texel_array(ctx, words(weight), Format::R32U, "wavelet weights");
    });
    return out;
}

namespace {

struct PredictPush {
    std::uint32_t first, count, parent0, inverse;
};
struct UpdatePush {
    std::uint32_t count, offsets0, entries0, inverse, from_detail, to_detail;
};

const Spirv kPredict = GIMG_SPIRV(gimg_spv_maps_wavelet_predict_comp);
const Spirv kUpdate = GIMG_SPIRV(gimg_spv_maps_wavelet_update_comp);

// The transform's working arrays (wavelet_predict.comp): the values being transformed and the
// details, each 6 r32ui texels per vertex, so the values buffer copies in and out unchanged.
struct Arrays {
    ImageHandle coarse, detail, parents, offsets, odd, weight;
};

Arrays begin_transform(Graph& graph, const SemiRegularMesh& mesh, WaveletBuffers& filters, BufferHandle values,
                       bool into_detail, const char* what) {
    if (filters.offsets_start.size() != mesh.levels() + 1 || filters.entries_start.size() != mesh.levels() + 1 ||
        !filters.parents)
        throw geo::InputError("wavelet filters on the GPU: uploaded for another mesh");
    const auto texels = std::uint32_t(value_texels(mesh));
    Arrays a{graph.create_image(texel_array_desc(texels, Format::R32U, std::string(what) + " coarse")),
             graph.create_image(texel_array_desc(texels, Format::R32U, std::string(what) + " details")),
             graph.import_image(filters.parents),
             graph.import_image(filters.offsets),
             graph.import_image(filters.odd),
             graph.import_image(filters.weight)};
    ImageHandle& target = into_detail ? a.detail : a.coarse;
    graph.add_compute_pass(
        std::string(what) + ": load values",
        [&](PassBuilder& b) {
            b.read(values, Access::TransferSrc);
            target = b.write(target, Access::TransferDst);
        },
        [=](Cmd& c) { c.copy_texels(values, target, texels); });
    return a;
}

BufferHandle end_transform(Graph& graph, const SemiRegularMesh& mesh, BufferHandle values, ImageHandle result,
                           const char* what) {
    const auto texels = std::uint32_t(value_texels(mesh));
    graph.add_compute_pass(
        std::string(what) + ": store values",
        [&](PassBuilder& b) {
            b.read(result, Access::TransferSrc);
            values = b.write(values, Access::TransferDst);
        },
        [=](Cmd& c) { c.copy_texels(result, values, texels); });
    return values;
}

void add_predict(Graph& graph, Arrays& a, const SemiRegularMesh& mesh, std::uint32_t j, bool inverse) {
    const PredictPush push{mesh.vertex_count[j], mesh.vertex_count[j + 1] - mesh.vertex_count[j],
                           mesh.vertex_count[j] - mesh.vertex_count[0], inverse ? 1u : 0u};
    graph.add_compute_pass(
        std::string(inverse ? "wavelet synthesis" : "wavelet analysis") + ": predict level " + std::to_string(j + 1),
        [&](PassBuilder& b) {
            b.read(a.parents, Access::ComputeRead);
            a.coarse = b.write(a.coarse, Access::ComputeReadWrite);
            a.detail = b.write(a.detail, Access::ComputeReadWrite);
        },
        [=, a = a](Cmd& c) {
            c.dispatch_threads(kPredict, {std::max(push.count, 1u)}, {a.coarse, a.detail, a.parents}, push);
        });
}

void add_update(Graph& graph, Arrays& a, const SemiRegularMesh& mesh, const WaveletBuffers& filters, std::uint32_t j,
                bool inverse, bool from_detail, bool to_detail) {
    const UpdatePush push{mesh.vertex_count[j], filters.offsets_start[j], filters.entries_start[j],
                          inverse ? 1u : 0u,    from_detail ? 1u : 0u,    to_detail ? 1u : 0u};
    graph.add_compute_pass(
        std::string(inverse ? "wavelet synthesis" : "wavelet analysis") + ": update level " + std::to_string(j),
        [&](PassBuilder& b) {
            for (ImageHandle h : {a.offsets, a.odd, a.weight}) b.read(h, Access::ComputeRead);
            a.coarse = b.write(a.coarse, Access::ComputeReadWrite);
            a.detail = b.write(a.detail, Access::ComputeReadWrite);
        },
        [=, a = a](Cmd& c) {
            c.dispatch_threads(kUpdate, {std::max(push.count, 1u)}, {a.coarse, a.detail, a.offsets, a.odd, a.weight},
                               push);
        });
}

bool has_weights(const WaveletBuffers& filters, std::uint32_t j) {
    return filters.entries_start[j + 1] > filters.entries_start[j];
}

}  // namespace

// Analysis: the values go into `coarse`; each level's predict writes its details to `detail`, and
// the update the new coarse values to `coarse`, the last one (always run, an empty row copying) to
// `detail`, which then holds the whole result.
BufferHandle add_wavelet_analysis(Graph& graph, BufferHandle values, const SemiRegularMesh& mesh,
                                  WaveletBuffers& filters, std::uint32_t down_to) {
    check_values(mesh, mesh.vertex_count.back(), down_to, "wavelet analysis");
    if (down_to == mesh.levels()) return values;
    Arrays a = begin_transform(graph, mesh, filters, values, false, "wavelet analysis");
    for (std::uint32_t j = mesh.levels(); j-- > down_to;) {
        add_predict(graph, a, mesh, j, false);
        if (j == down_to || has_weights(filters, j)) add_update(graph, a, mesh, filters, j, false, false, j == down_to);
    }
    return end_transform(graph, mesh, values, a.detail, "wavelet analysis");
}

// Synthesis: the coefficients go into `detail`; the first update reads its coarse values there, and
// every level's coarse values and predicted odd vertices go to `coarse`, which then holds them all.
BufferHandle add_wavelet_synthesis(Graph& graph, BufferHandle values, const SemiRegularMesh& mesh,
                                   WaveletBuffers& filters, std::uint32_t from) {
    check_values(mesh, mesh.vertex_count.back(), from, "wavelet synthesis");
    if (from == mesh.levels()) return values;
    Arrays a = begin_transform(graph, mesh, filters, values, true, "wavelet synthesis");
    for (std::uint32_t j = from; j < mesh.levels(); ++j) {
        if (j == from || has_weights(filters, j)) add_update(graph, a, mesh, filters, j, true, j == from, false);
        add_predict(graph, a, mesh, j, true);
    }
    return end_transform(graph, mesh, values, a.coarse, "wavelet synthesis");
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
