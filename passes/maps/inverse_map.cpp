// Pi^{-1} (sec. 2.4): the original triangles' images placed in planar charts of the base domain
// and bucketed, so that any point of a base triangle finds the original triangle over it.
#include "gimg/engine/texel_array.h"
#include "gimg/engine/upload.h"
#include "gimg/geometry/bvh.h"
#include "gimg/geometry/error.h"
#include "gimg/passes/maps.h"
#include "maps/ring_flattening.h"

#include "maps/inverse_map_comp.h"

#include <glm/common.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>

namespace gimg::passes {

namespace {

// A point of the base domain as weights on the base vertices of its support (a vertex, an edge or
// a face of the base).
struct Support {
    std::array<std::uint32_t, 3> vertex{};
    std::array<double, 3> weight{};
    int count = 0;
};

Support support_of(const geo::Mesh& base, const SurfacePoint& s) {
    Support out;
    const glm::uvec3 t = base.triangles[s.face];
    for (int k = 0; k < 3; ++k)
        if (s.bary[k] != 0.0) {
            out.vertex[std::size_t(out.count)] = t[k];
            out.weight[std::size_t(out.count)] = s.bary[k];
            ++out.count;
        }
    return out;
}

bool holds(const glm::uvec3& t, std::uint32_t v) { return t[0] == v || t[1] == v || t[2] == v; }

bool within(const glm::uvec3& t, const Support& s) {
    for (int i = 0; i < s.count; ++i)
        if (!holds(t, s.vertex[std::size_t(i)])) return false;
    return true;
}

// A base vertex's chart: its ring flattened by z^a, or at equal angles where z^a would fold a
// sector (a scaled angle of pi or more), which keeps the fan one-to-one.
struct VertexChart {
    Ring ring;
    glm::dvec2 coords(std::uint32_t centre, std::uint32_t u) const {
        if (u == centre) return glm::dvec2(0.0);
        for (std::size_t k = 0; k < ring.ring.size(); ++k)
            if (ring.ring[k] == u) return ring.mu[k];
        return glm::dvec2(std::nan(""));
    }
};

VertexChart vertex_chart(const geo::Mesh& base, const std::vector<std::vector<std::uint32_t>>& vertex_faces,
                         std::uint32_t v) {
    VertexChart c;
    if (!gather_ring(base.triangles, vertex_faces[v], v, c.ring))
        throw geo::InputError("the base domain is not a closed manifold around a vertex");
    if (!flatten_ring(base.positions, v, c.ring)) {
        const std::size_t k = c.ring.ring.size();
        c.ring.mu.resize(k);
        for (std::size_t i = 0; i < k; ++i) {
            const double a = 2.0 * std::numbers::pi * double(i) / double(k);
            c.ring.mu[i] = {std::cos(a), std::sin(a)};
        }
    }
    return c;
}

constexpr std::uint32_t kNoFace = 0xffffffffu;

struct Placed {
    std::uint32_t chart, face;
    std::array<glm::dvec2, 3> coords;
};

double signed_area(const std::array<glm::dvec2, 3>& p) {
    const glm::dvec2 u = p[1] - p[0], w = p[2] - p[0];
    return 0.5 * (u.x * w.y - u.y * w.x);
}

// The same search as shaders/maps/inverse_map.comp, in the same order of operations.
struct Hit {
    std::uint32_t triangle = 0xffffffffu;
    glm::dvec3 bary{0.0};
    double margin = -1e300;
};

void test_items(const InverseMap& m, std::uint32_t begin, std::uint32_t end, glm::dvec2 p, Hit& best) {
    for (std::uint32_t i = begin; i < end; ++i) {
        const std::uint32_t t = m.cell_items[i];
        const glm::dvec3 w =
            barycentric_2d(p, m.triangle_coords[3 * t], m.triangle_coords[3 * t + 1], m.triangle_coords[3 * t + 2]);
        const double margin = std::min({w.x, w.y, w.z});
        if (margin > best.margin) best = {t, w, margin};
        if (margin >= -1e-12) return;
    }
}

// The cell of the chart's grid holding p, or with `whole` every cell of the chart.
void search_chart(const InverseMap& m, std::uint32_t chart, glm::dvec2 p, bool whole, Hit& best) {
    const glm::dvec4 box = m.chart_box[chart];
    const glm::uvec4 grid = m.chart_grid[chart];
    if (whole) {
        test_items(m, m.cell_offsets[grid.z], m.cell_offsets[grid.z + grid.x * grid.y], p, best);
        return;
    }
    const double fx = std::floor((p.x - box.x) / box.z), fy = std::floor((p.y - box.y) / box.w);
    if (!(fx >= 0.0 && fy >= 0.0 && fx < double(grid.x) && fy < double(grid.y))) return;
    const std::uint32_t cell = grid.z + std::uint32_t(fy) * grid.x + std::uint32_t(fx);
    test_items(m, m.cell_offsets[cell], m.cell_offsets[cell + 1], p, best);
}

// Points in no chart's triangle (a base face all of whose images were too large to chart): the
// flat point of the base triangle between its corners' original vertices, projected onto the
// original surface. Rare; on the CPU after the pass.
void place_unfound(const geo::Mesh& mesh, const InverseMap& m, const std::vector<SurfacePoint>& points,
                   const std::vector<std::size_t>& unfound, std::vector<glm::dvec3>& out) {
    if (unfound.empty()) return;
    const geo::TriangleBvh bvh(mesh);
    for (std::size_t i : unfound) {
        const SurfacePoint& q = points[i];
        const std::uint32_t* corner = &m.face_charts[8 * std::size_t(q.face) + 4];
        const glm::dvec3 flat = q.bary.x * mesh.positions[corner[0]] + q.bary.y * mesh.positions[corner[1]] +
                                q.bary.z * mesh.positions[corner[2]];
        out[i] = bvh.closest_point(flat).point;
    }
}

}  // namespace

InverseMap build_inverse_map(const geo::Mesh& mesh, const BaseDomain& domain) {
    const geo::Mesh& base = domain.base;
    if (domain.param.size() != mesh.vertex_count()) throw geo::InputError("the base domain is of another mesh");
    const std::uint32_t nf = std::uint32_t(base.face_count()), nv = std::uint32_t(base.vertex_count());
    std::vector<std::vector<std::uint32_t>> vertex_faces(nv);
    for (std::uint32_t f = 0; f < nf; ++f)
        for (int k = 0; k < 3; ++k) vertex_faces[base.triangles[f][k]].push_back(f);
    std::vector<VertexChart> charts(nv);
    for (std::uint32_t v = 0; v < nv; ++v) charts[v] = vertex_chart(base, vertex_faces, v);

    InverseMap m;
    for (std::uint32_t f = 0; f < nf; ++f) {
        const glm::uvec3 t = base.triangles[f];
        m.face_charts.insert(m.face_charts.end(), {f, nf + t[0], nf + t[1], nf + t[2], domain.original[t[0]],
                                                   domain.original[t[1]], domain.original[t[2]], 0});
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) m.corner_coords.push_back(charts[t[c]].coords(t[c], t[k]));
    }

    std::vector<Support> support(mesh.vertex_count());
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) support[v] = support_of(base, domain.param[v]);
    std::vector<Placed> placed;
    std::vector<std::uint32_t> candidates;
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {
        const glm::uvec3 t = mesh.triangles[f];
        const std::array<const Support*, 3> s{&support[t[0]], &support[t[1]], &support[t[2]]};
        // One base face holding all three: its barycentric plane. A corner on a base edge or vertex
        // lies in every face there, so all of those are tried, not only its own.
        std::uint32_t home_face = kNoFace;
        const std::uint32_t own = domain.param[t[0]].face;
        if (within(base.triangles[own], *s[1]) && within(base.triangles[own], *s[2])) home_face = own;
        for (int i = 0; i < s[0]->count && home_face == kNoFace; ++i)
            for (std::uint32_t g : vertex_faces[s[0]->vertex[std::size_t(i)]])
                if (within(base.triangles[g], *s[0]) && within(base.triangles[g], *s[1]) &&
                    within(base.triangles[g], *s[2])) {
                    home_face = g;
                    break;
                }
        if (home_face != kNoFace) {
            const glm::uvec3 home = base.triangles[home_face];
            Placed p{home_face, f, {}};
            for (int k = 0; k < 3; ++k) {
                glm::dvec3 w(0.0);
                for (int i = 0; i < s[k]->count; ++i)
                    for (int c = 0; c < 3; ++c)
                        if (home[c] == s[k]->vertex[std::size_t(i)]) w[c] = s[k]->weight[std::size_t(i)];
                p.coords[std::size_t(k)] = {w.y, w.z};
            }
            placed.push_back(p);
            continue;
        }
        ++m.straddling;
        // Base vertices whose star holds the three images: the corners of the faces they lie in.
        candidates.clear();
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c) candidates.push_back(base.triangles[domain.param[t[k]].face][c]);
        std::sort(candidates.begin(), candidates.end());
        candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
        bool any = false;
        for (std::uint32_t v : candidates) {
            bool inside = true;
            for (int k = 0; k < 3 && inside; ++k) {
                bool in_star = false;
                for (std::uint32_t g : vertex_faces[v]) in_star = in_star || within(base.triangles[g], *s[k]);
                inside = in_star;
            }
            if (!inside) continue;
            Placed p{nf + v, f, {}};
            for (int k = 0; k < 3; ++k) {
                glm::dvec2 x(0.0);
                for (int i = 0; i < s[k]->count; ++i)
                    x += s[k]->weight[std::size_t(i)] * charts[v].coords(v, s[k]->vertex[std::size_t(i)]);
                p.coords[std::size_t(k)] = x;
            }
            placed.push_back(p);
            any = true;
        }
        if (!any) ++m.unplaced;
    }

    // Per chart, a uniform grid over its triangles' bounding box.
    const std::uint32_t chart_count = nf + nv;
    std::vector<std::vector<std::uint32_t>> by_chart(chart_count);
    for (std::uint32_t i = 0; i < placed.size(); ++i) by_chart[placed[i].chart].push_back(i);
    m.triangle_coords.reserve(3 * placed.size());
    m.cell_offsets.push_back(0);
    std::vector<std::vector<std::uint32_t>> cells;
    for (std::uint32_t c = 0; c < chart_count; ++c) {
        glm::dvec2 lo(1e300), hi(-1e300);
        for (std::uint32_t i : by_chart[c])
            for (const glm::dvec2& x : placed[i].coords) {
                lo = glm::min(lo, x);
                hi = glm::max(hi, x);
            }
        if (by_chart[c].empty()) lo = hi = glm::dvec2(0.0);
        const glm::dvec2 pad = (hi - lo) * 1e-9 + glm::dvec2(1e-12);
        lo -= pad;
        hi += pad;
        const auto n = std::uint32_t(std::clamp(std::sqrt(double(by_chart[c].size()) / 2.0), 1.0, 256.0));
        const glm::dvec2 size = (hi - lo) / double(n);
        m.chart_box.push_back({lo.x, lo.y, size.x, size.y});
        m.chart_grid.push_back({n, n, std::uint32_t(m.cell_offsets.size() - 1), 0});
        cells.assign(std::size_t(n) * n, {});
        for (std::uint32_t i : by_chart[c]) {
            const auto id = std::uint32_t(m.triangle_face.size());
            glm::dvec2 a(1e300), b(-1e300);
            for (const glm::dvec2& x : placed[i].coords) {
                m.triangle_coords.push_back(x);
                a = glm::min(a, x);
                b = glm::max(b, x);
            }
            m.triangle_face.push_back(placed[i].face);
            if (signed_area(placed[i].coords) < 0.0) ++m.inverted;
            auto cell = [&](double x, double o, double s) {
                return std::uint32_t(std::clamp(std::floor((x - o) / s), 0.0, double(n - 1)));
            };
            for (std::uint32_t y = cell(a.y, lo.y, size.y); y <= cell(b.y, lo.y, size.y); ++y)
                for (std::uint32_t x = cell(a.x, lo.x, size.x); x <= cell(b.x, lo.x, size.x); ++x)
                    cells[std::size_t(y) * n + x].push_back(id);
        }
        for (const auto& items : cells) {
            m.cell_items.insert(m.cell_items.end(), items.begin(), items.end());
            m.cell_offsets.push_back(std::uint32_t(m.cell_items.size()));
        }
    }
    return m;
}

std::vector<glm::dvec3> evaluate_inverse_map(const geo::Mesh& mesh, const InverseMap& m,
                                             const std::vector<SurfacePoint>& points, std::size_t* fallbacks) {
    std::vector<glm::dvec3> out(points.size());
    std::size_t missed = 0;
    std::vector<std::size_t> unfound;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const SurfacePoint& q = points[i];
        if (std::size_t(q.face) * 8 >= m.face_charts.size()) throw geo::InputError("a point names no base face");
        // Corners by decreasing barycentric coordinate (ties: the lower corner first).
        std::array<int, 3> order{0, 1, 2};
        std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return q.bary[a] > q.bary[b]; });
        Hit best;
        // The cells holding the point, then, for a point in a gap between charts, whole charts.
        for (bool whole : {false, true}) {
            if (best.margin >= -1e-9) break;
            search_chart(m, m.face_charts[8 * q.face], {q.bary.y, q.bary.z}, whole, best);
            for (int c : order) {
                if (best.margin >= -1e-12) break;
                const glm::dvec2* x = &m.corner_coords[9 * std::size_t(q.face) + 3 * std::size_t(c)];
                search_chart(m, m.face_charts[8 * q.face + 1 + std::uint32_t(c)],
                             q.bary.x * x[0] + q.bary.y * x[1] + q.bary.z * x[2], whole, best);
            }
        }
        // A base vertex is an original vertex: exactly its position.
        if (q.bary.x == 1.0 || q.bary.y == 1.0 || q.bary.z == 1.0) {
            const int c = q.bary.x == 1.0 ? 0 : q.bary.y == 1.0 ? 1 : 2;
            out[i] = mesh.positions[m.face_charts[8 * q.face + 4 + std::uint32_t(c)]];
            continue;
        }
        if (best.triangle == 0xffffffffu) {
            unfound.push_back(i);
            continue;
        }
        if (best.margin < -1e-9) ++missed;
        glm::dvec3 w = glm::max(best.bary, glm::dvec3(0.0));
        const double sum = w.x + w.y + w.z;
        w = sum > 0.0 ? w / sum : glm::dvec3(1.0 / 3.0);
        const glm::uvec3 t = mesh.triangles[m.triangle_face[best.triangle]];
        out[i] = w.x * mesh.positions[t[0]] + w.y * mesh.positions[t[1]] + w.z * mesh.positions[t[2]];
    }
    place_unfound(mesh, m, points, unfound, out);
    if (fallbacks) *fallbacks = missed + unfound.size();
    return out;
}

namespace {

// `values` as RGBA32UI texels, 16 bytes each (the last padded with zeros).
template <class T>
Image upload_as_texels(Context& ctx, const std::vector<T>& values, const std::string& name) {
    std::vector<glm::uvec4> texels((values.size() * sizeof(T) + 15) / 16, glm::uvec4(0u));
    std::memcpy(texels.data(), values.data(), values.size() * sizeof(T));
    return upload_texel_array(ctx, texels, Format::RGBA32U, name);
}

}  // namespace

// Packing (shaders/maps/inverse_map.comp reads it): face charts 8 uints a face in 2 texels; corner
// coordinates and triangle coordinates a dvec2 a texel; chart boxes 2 texels (origin, cell size);
// chart grids a texel; cell offsets, items and triangle faces R32UI; positions 2 texels a vertex
// (x, y and z, 0); faces a texel (a, b, c, 0).
InverseMapBuffers upload_inverse_map(Context& ctx, const geo::Mesh& mesh, const InverseMap& m) {
    std::vector<glm::dvec2> positions;
    positions.reserve(2 * mesh.vertex_count());
    for (const glm::dvec3& p : mesh.positions) positions.insert(positions.end(), {{p.x, p.y}, {p.z, 0.0}});
    std::vector<glm::uvec4> faces;
    faces.reserve(mesh.face_count());
    for (const glm::uvec3& t : mesh.triangles) faces.emplace_back(t, 0u);
    InverseMapBuffers buffers;
    ctx.batch_uploads([&] {  // one submission for the ten
        buffers = {upload_as_texels(ctx, m.face_charts, "maps face charts"),
                   upload_as_texels(ctx, m.corner_coords, "maps corner coords"),
                   upload_as_texels(ctx, m.chart_box, "maps chart boxes"),
                   upload_as_texels(ctx, m.chart_grid, "maps chart grids"),
                   upload_texel_array(ctx, m.cell_offsets, Format::R32U, "maps cell offsets"),
                   upload_texel_array(ctx, m.cell_items, Format::R32U, "maps cell items"),
                   upload_as_texels(ctx, m.triangle_coords, "maps triangle coords"),
                   upload_texel_array(ctx, m.triangle_face, Format::R32U, "maps triangle faces"),
                   upload_as_texels(ctx, positions, "maps original positions"),
                   upload_texel_array(ctx, faces, Format::RGBA32U, "maps original faces")};
    });
    return buffers;
}

void add_inverse_map(Graph& graph, InverseMapBuffers& map, BufferHandle points, BufferHandle bary, BufferHandle out,
                     std::uint32_t count) {
    static const Spirv kInverse = GIMG_SPIRV(gimg_spv_maps_inverse_map_comp);
    struct Handles {
        ImageHandle face_charts, corner_coords, chart_box, chart_grid, cell_offsets, cell_items, triangle_coords,
            triangle_face, positions, faces;
    };
    Handles h{graph.import_image(map.face_charts),     graph.import_image(map.corner_coords),
              graph.import_image(map.chart_box),       graph.import_image(map.chart_grid),
              graph.import_image(map.cell_offsets),    graph.import_image(map.cell_items),
              graph.import_image(map.triangle_coords), graph.import_image(map.triangle_face),
              graph.import_image(map.positions),       graph.import_image(map.faces)};
    graph.add_compute_pass(
        "MAPS inverse map",
        [&](PassBuilder& b) {
            for (ImageHandle r : {h.face_charts, h.corner_coords, h.chart_box, h.chart_grid, h.cell_offsets,
                                  h.cell_items, h.triangle_coords, h.triangle_face, h.positions, h.faces})
                b.read(r, Access::ComputeRead);
            for (BufferHandle r : {points, bary}) b.read(r, Access::ComputeRead);
            out = b.write(out, Access::ComputeWrite);
        },
        [=](Cmd& c) {
            // Chunks within the smallest maxComputeWorkGroupCount Vulkan allows (65535 groups).
            constexpr std::uint32_t kChunk = 65535u * 64u;
            for (std::uint32_t first = 0; first < std::max(count, 1u); first += kChunk) {
                const struct { std::uint32_t first, count; } push{first, std::min(kChunk, count - first)};
                c.dispatch_threads(
                    kInverse, {std::max(push.count, 1u)},
                    {h.face_charts, h.corner_coords, h.chart_box, h.chart_grid, h.cell_offsets, h.cell_items,
                     h.triangle_coords, h.triangle_face, h.positions, h.faces, points, bary, out},
                    push);
            }
        });
}

std::vector<glm::dvec3> evaluate_inverse_map_gpu(Context& ctx, const geo::Mesh& mesh, const InverseMap& m,
                                                 const std::vector<SurfacePoint>& points, std::size_t* fallbacks) {
    InverseMapBuffers buffers = upload_inverse_map(ctx, mesh, m);
    return evaluate_inverse_map_gpu(ctx, buffers, mesh, m, points, fallbacks);
}

std::vector<glm::dvec3> evaluate_inverse_map_gpu(Context& ctx, InverseMapBuffers& buffers, const geo::Mesh& mesh,
                                                 const InverseMap& m, const std::vector<SurfacePoint>& points,
                                                 std::size_t* fallbacks) {
    std::vector<std::uint32_t> faces(points.size());
    std::vector<double> bary(3 * points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (std::size_t(points[i].face) * 8 >= m.face_charts.size())
            throw geo::InputError("a point names no base face");
        faces[i] = points[i].face;
        for (int k = 0; k < 3; ++k) bary[3 * i + std::size_t(k)] = points[i].bary[k];
    }
    // Batches keep every binding within maxStorageBufferRange (128 MiB on lavapipe).
    constexpr std::size_t kBatch = std::size_t(1) << 21;
    std::vector<double> raw(4 * points.size());
    for (std::size_t first = 0; first < points.size(); first += kBatch) {
        const std::size_t n = std::min(kBatch, points.size() - first);
        Buffer point_buffer = upload_buffer(ctx, faces.data() + first, 4 * n, "maps points");
        Buffer bary_buffer = upload_buffer(ctx, bary.data() + 3 * first, 24 * n, "maps point bary");
        Buffer out = ctx.create_buffer({std::max<std::size_t>(32 * n, 16), "maps remesh positions"});
        Graph g(ctx);
        auto out_h = g.import_buffer(out);
        add_inverse_map(g, buffers, g.import_buffer(point_buffer), g.import_buffer(bary_buffer), out_h,
                        std::uint32_t(n));
        g.export_buffer(out_h, Access::TransferSrc);
        Plan plan = g.compile();
        plan.execute();
        ctx.download(out, raw.data() + 4 * first, 32 * n);
    }
    std::vector<glm::dvec3> result(points.size());
    std::size_t missed = 0;
    std::vector<std::size_t> unfound;
    for (std::size_t i = 0; i < points.size(); ++i) {
        result[i] = {raw[4 * i], raw[4 * i + 1], raw[4 * i + 2]};
        if (raw[4 * i + 3] < 0.0) unfound.push_back(i);
        if (raw[4 * i + 3] > 0.5) ++missed;
    }
    place_unfound(mesh, m, points, unfound, result);
    missed += unfound.size();
    if (fallbacks) *fallbacks = missed;
    return result;
}

}  // namespace gimg::passes
