// Deformations through the region's map (sec. 5): P'_i = P_i + F(u_i, v_i), F a lattice of offsets
// on clamped cubic B-splines (the outer layers fixed at zero) or a height along the normal.
#include "gimg/engine/upload.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/normals.h"
#include "gimg/passes/quad_region.h"
#include "lattice_weights.h"

#include "quad_region/deform_comp.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <span>
#include <vector>

namespace gimg::passes {

namespace {

// The N clamped cubic B-spline basis values at x in [0, 1]: knots 0,0,0,0, 1/(N-3), ..., 1,1,1,1
// (Cox-de Boor), into b[0..N); `knot` holds N + 4 values and b N + 3.
void cubic_basis(std::uint32_t n, double x, std::span<double> knot, std::span<double> b) {
    const std::uint32_t spans = n - 3, knots = n + 4;
    for (std::uint32_t i = 0; i < knots; ++i) knot[i] = i < 3 ? 0.0 : i <= 3 + spans ? double(i - 3) / spans : 1.0;
    x = std::clamp(x, 0.0, 1.0);
    // Degree 0: the one span holding x (the last span holds x = 1).
    for (std::uint32_t i = 0; i + 1 < knots; ++i)
        b[i] = knot[i] < knot[i + 1] && ((x >= knot[i] && x < knot[i + 1]) || (x == 1.0 && knot[i + 1] == 1.0)) ? 1.0
                                                                                                                : 0.0;
    for (std::uint32_t p = 1; p <= 3; ++p)
        for (std::uint32_t i = 0; i + p + 1 < knots; ++i) {
            // Terms of a zero value are skipped (at most four values are not zero): the same sums
            // but for the sign of a zero.
            const double l =
                b[i] != 0.0 && knot[i + p] > knot[i] ? (x - knot[i]) / (knot[i + p] - knot[i]) * b[i] : 0.0;
            const double r = b[i + 1] != 0.0 && knot[i + p + 1] > knot[i + 1]
                                 ? (knot[i + p + 1] - x) / (knot[i + p + 1] - knot[i + 1]) * b[i + 1]
                                 : 0.0;
            b[i] = l + r;
        }
}

// cubic_basis's values without an allocation for lattices of up to 60 control points a side (a
// lattice edit evaluates two bases per region vertex).
class BasisValues {
public:
    BasisValues(std::uint32_t n, double x) {
        if (2 * n + 7 > local_.size()) heap_.resize(2 * n + 7);
        const std::span<double> room = heap_.empty() ? std::span<double>(local_) : std::span<double>(heap_);
        values_ = room.subspan(n + 4, n + 3);
        cubic_basis(n, x, room.first(n + 4), values_);
    }
    double operator[](std::size_t i) const { return values_[i]; }

private:
    std::array<double, 128> local_;
    std::vector<double> heap_;
    std::span<double> values_;
};

// Control point k of n along one side moves: it is not in the outer fixed_layers + 1 of either end.
bool free_node(std::uint32_t k, std::uint32_t n, int fixed_layers) {
    return int(k) > fixed_layers && int(k) + 1 + fixed_layers < int(n);
}

void check_map(const geo::Mesh& mesh, const QuadRegion& region, const std::vector<glm::dvec2>& uv) {
    if (uv.size() != region.mesh.vertex_count())
        throw geo::InputError("the map has " + std::to_string(uv.size()) + " parameters for a region of " +
                              std::to_string(region.mesh.vertex_count()) + " vertices");
    for (std::uint32_t o : region.original)
        if (o != kInsertedNode && o >= mesh.vertex_count())
            throw geo::InputError("the region was cut from another mesh");
}

// G / h: the bump or the height map's bilinear value, in the shader's order of operations.
double unit_height(const PastedFeature& f, glm::dvec2 uv) {
    if (f.heights.empty()) {
        auto b = [](double x) {
            x = std::clamp(x, 0.0, 1.0);
            const double t = 4.0 * x * (1.0 - x);
            return t * t * t;
        };
        return b(uv.x) * b(uv.y);
    }
    if (f.heights.size() != std::size_t(f.width) * f.height || f.width < 2 || f.height < 2)
        throw geo::InputError("a height map needs at least 2 x 2 values");
    const double x = std::clamp(uv.x, 0.0, 1.0) * double(f.width - 1);
    const double y = (1.0 - std::clamp(uv.y, 0.0, 1.0)) * double(f.height - 1);
    const std::uint32_t x0 = std::min(std::uint32_t(x), f.width - 2), y0 = std::min(std::uint32_t(y), f.height - 2);
    const double fx = x - double(x0), fy = y - double(y0);
    auto at = [&](std::uint32_t i, std::uint32_t j) { return double(f.heights[std::size_t(j) * f.width + i]); };
    const double top = at(x0, y0) * (1.0 - fx) + at(x0 + 1, y0) * fx;
    const double bottom = at(x0, y0 + 1) * (1.0 - fx) + at(x0 + 1, y0 + 1) * fx;
    return top * (1.0 - fy) + bottom * fy;
}

// The unweighted mean of the unit normals of the faces at a vertex, normalised (zero where they
// cancel), of the undeformed mesh.
std::vector<glm::dvec3> paste_normals(const geo::Mesh& mesh) {
    const std::vector<glm::dvec3> face_n = geo::face_normals(mesh);
    std::vector<glm::dvec3> normal(mesh.vertex_count(), glm::dvec3(0.0));
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        for (int k = 0; k < 3; ++k) normal[mesh.triangles[f][k]] += face_n[f];
    for (auto& n : normal) n = glm::length(n) > 0.0 ? glm::normalize(n) : glm::dvec3(0.0);
    return normal;
}

// P'_o = P_o + F(u_i, v_i) for every region vertex i of an original vertex o.
template <class Offset>
geo::Mesh offset_region(const geo::Mesh& mesh, const QuadRegion& region, const std::vector<glm::dvec2>& uv,
                        Offset&& offset) {
    check_map(mesh, region, uv);
    geo::Mesh out = mesh;
    for (std::size_t i = 0; i < uv.size(); ++i)
        if (region.original[i] != kInsertedNode) out.positions[region.original[i]] += offset(uv[i]);
    return out;
}

}  // namespace

glm::dvec2 polar_coordinates(glm::dvec2 uv) {
    const glm::dvec2 d = uv - glm::dvec2(0.5);
    double theta = std::atan2(d.y, d.x);
    if (theta < 0.0) theta += 2.0 * std::numbers::pi;
    return {2.0 * glm::length(d), theta};
}

glm::dvec3 PolarLattice::evaluate(glm::dvec2 uv) const {
    if (rings < 7 || sectors < 3) throw geo::InputError("a polar lattice needs at least 7 rings and 3 sectors");
    if (offsets.size() != std::size_t(rings) * sectors)
        throw geo::InputError("the polar lattice has " + std::to_string(offsets.size()) + " offsets for " +
                              std::to_string(rings) + " x " + std::to_string(sectors) + " control points");
    const glm::dvec2 rt = polar_coordinates(uv);
    if (rt.x >= 1.0) return glm::dvec3(0.0);
    const BasisValues br(rings, rt.x);
    // Uniform periodic cubic B-spline in theta: the four control points around the span.
    const double x = rt.y / (2.0 * std::numbers::pi) * sectors;
    const auto span = std::uint32_t(std::floor(x)) % sectors;
    const double t = x - std::floor(x);
    const double c[4] = {(1 - t) * (1 - t) * (1 - t) / 6.0, (3 * t * t * t - 6 * t * t + 4) / 6.0,
                         (-3 * t * t * t + 3 * t * t + 3 * t + 1) / 6.0, t * t * t / 6.0};
    glm::dvec3 f(0.0);
    for (std::uint32_t p = 3; p + 3 < rings; ++p)
        for (int k = 0; k < 4; ++k)
            f += offsets[std::size_t(p) * sectors + (span + sectors - 1 + std::uint32_t(k)) % sectors] * (br[p] * c[k]);
    return f;
}

geo::Mesh deform_by_polar_lattice(const geo::Mesh& mesh, const QuadRegion& region, const std::vector<glm::dvec2>& uv,
                                  const PolarLattice& lattice) {
    return offset_region(mesh, region, uv, [&](glm::dvec2 p) { return lattice.evaluate(p); });
}

double PastedFeature::evaluate(glm::dvec2 uv) const { return scale * unit_height(*this, uv); }

glm::dvec3 OffsetLattice::evaluate(glm::dvec2 uv) const {
    if (columns < 4 || rows < 4) throw geo::InputError("an offset lattice needs at least 4 x 4 control points");
    if (offsets.size() != std::size_t(columns) * rows)
        throw geo::InputError("the lattice has " + std::to_string(offsets.size()) + " offsets for " +
                              std::to_string(columns) + " x " + std::to_string(rows) + " control points");
    const BasisValues bu(columns, uv.x), bv(rows, uv.y);
    glm::dvec3 f(0.0);
    for (std::uint32_t q = 0; q < rows; ++q)
        for (std::uint32_t p = 0; p < columns; ++p)
            if (free_node(p, columns, fixed_layers) && free_node(q, rows, fixed_layers))
                f += offsets[std::size_t(q) * columns + p] * (bu[p] * bv[q]);
    return f;
}

geo::Mesh deform_by_lattice(const geo::Mesh& mesh, const QuadRegion& region, const std::vector<glm::dvec2>& uv,
                            const OffsetLattice& lattice) {
    return offset_region(mesh, region, uv, [&](glm::dvec2 p) { return lattice.evaluate(p); });
}

LatticeWeights::LatticeWeights(const OffsetLattice& shape, const std::vector<glm::dvec2>& uv)
    : columns_(shape.columns), rows_(shape.rows), fixed_layers_(shape.fixed_layers) {
    shape.evaluate({0.5, 0.5});  // the lattice's own checks
    first_p_.resize(uv.size());
    first_q_.resize(uv.size());
    weight_.resize(uv.size());
    // The first of at most four values that are not zero, kept inside the lattice.
    auto first = [](const BasisValues& b, std::uint32_t n) {
        std::uint32_t k = 0;
        while (k + 4 < n && b[k] == 0.0) ++k;
        return k;
    };
    for (std::size_t i = 0; i < uv.size(); ++i) {
        const BasisValues bu(columns_, uv[i].x), bv(rows_, uv[i].y);
        const std::uint32_t p0 = first(bu, columns_), q0 = first(bv, rows_);
        first_p_[i] = p0;
        first_q_[i] = q0;
        for (std::uint32_t q = 0; q < 4; ++q)
            for (std::uint32_t p = 0; p < 4; ++p) weight_[i][4 * q + p] = bu[p0 + p] * bv[q0 + q];
    }
}

bool LatticeWeights::fits(const OffsetLattice& lattice) const {
    return lattice.columns == columns_ && lattice.rows == rows_ && lattice.fixed_layers == fixed_layers_;
}

glm::dvec3 LatticeWeights::offset(std::size_t i, const OffsetLattice& lattice) const {
    glm::dvec3 f(0.0);
    for (std::uint32_t q = first_q_[i]; q < first_q_[i] + 4; ++q)
        for (std::uint32_t p = first_p_[i]; p < first_p_[i] + 4; ++p)
            if (free_node(p, columns_, fixed_layers_) && free_node(q, rows_, fixed_layers_))
                f += lattice.offsets[std::size_t(q) * columns_ + p] *
                     weight_[i][4 * (q - first_q_[i]) + p - first_p_[i]];
    return f;
}

geo::Mesh paste_feature(const geo::Mesh& mesh, const QuadRegion& region, const std::vector<glm::dvec2>& uv,
                        const PastedFeature& feature) {
    check_map(mesh, region, uv);
    const std::vector<glm::dvec3> normal = paste_normals(mesh);
    const double scale = feature.scale * mesh.bounds().diagonal();
    geo::Mesh out = mesh;
    for (std::size_t i = 0; i < uv.size(); ++i) {
        const std::uint32_t o = region.original[i];
        if (o == kInsertedNode) continue;
        out.positions[o] += normal[o] * (unit_height(feature, uv[i]) * scale);
    }
    return out;
}

void add_quad_deformation(Graph& graph, BufferHandle positions, BufferHandle normals, BufferHandle original,
                          BufferHandle uv, BufferHandle offsets, BufferHandle heights, const QuadDeformation& what) {
    static const Spirv kDeform = GIMG_SPIRV(gimg_spv_quad_region_deform_comp);
    struct Push {
        std::uint32_t count, mode, columns, rows;
        double scale;
    };
    const Push push{what.region_vertices, std::uint32_t(what.kind), what.columns, what.rows, what.scale};
    graph.add_compute_pass(
        "quad region deformation",
        [&](PassBuilder& b) {
            for (auto h : {normals, original, uv, offsets, heights}) b.read(h, Access::ComputeRead);
            positions = b.write(positions, Access::ComputeReadWrite);
        },
        [=](Cmd& c) {
            c.dispatch_threads(kDeform, {std::max(push.count, 1u)},
                               {positions, normals, original, uv, offsets, heights}, push);
        });
}

namespace {

geo::Mesh deform_gpu(Context& ctx, const geo::Mesh& mesh, const QuadRegion& region, const std::vector<glm::dvec2>& uv,
                     QuadDeformation what, const std::vector<double>& offsets, const std::vector<float>& heights) {
    check_map(mesh, region, uv);
    std::vector<double> positions(3 * mesh.vertex_count()), normals;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        for (int k = 0; k < 3; ++k) positions[3 * v + std::size_t(k)] = mesh.positions[v][k];
    if (what.kind != QuadDeformation::Kind::Lattice)
        for (const glm::dvec3& n : paste_normals(mesh)) normals.insert(normals.end(), {n.x, n.y, n.z});
    Buffer pos, nrm, org, par, off, hgt;
    ctx.batch_uploads([&] {  // one submission for the six
        pos = upload_buffer(ctx, positions, "deform positions");
        nrm = upload_buffer(ctx, normals, "deform normals");
        org = upload_buffer(ctx, region.original, "deform original");
        par = upload_buffer(ctx, uv, "deform uv");
        off = upload_buffer(ctx, offsets, "deform offsets");
        hgt = upload_buffer(ctx, heights, "deform heights");
    });
    what.region_vertices = std::uint32_t(uv.size());
    Graph g(ctx);
    auto pos_h = g.import_buffer(pos);
    add_quad_deformation(g, pos_h, g.import_buffer(nrm), g.import_buffer(org), g.import_buffer(par),
                         g.import_buffer(off), g.import_buffer(hgt), what);
    g.export_buffer(pos_h, Access::TransferSrc);
    Plan plan = g.compile();
    plan.execute();
    ctx.download(pos, positions.data(), positions.size() * 8);
    geo::Mesh out = mesh;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        out.positions[v] = {positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]};
    return out;
}

}  // namespace

geo::Mesh deform_by_lattice_gpu(Context& ctx, const geo::Mesh& mesh, const QuadRegion& region,
                                const std::vector<glm::dvec2>& uv, const OffsetLattice& lattice) {
    lattice.evaluate({0.5, 0.5});  // the lattice's own checks
    if (lattice.columns > 128 || lattice.rows > 128)
        throw geo::InputError("the GPU lattice takes at most 128 x 128 control points");
    std::vector<double> offsets;
    for (std::uint32_t q = 0; q < lattice.rows; ++q)
        for (std::uint32_t p = 0; p < lattice.columns; ++p) {
            const glm::dvec3 o =
                free_node(p, lattice.columns, lattice.fixed_layers) && free_node(q, lattice.rows, lattice.fixed_layers)
                    ? lattice.offsets[std::size_t(q) * lattice.columns + p]
                    : glm::dvec3(0.0);
            offsets.insert(offsets.end(), {o.x, o.y, o.z});
        }
    return deform_gpu(ctx, mesh, region, uv,
                      {.kind = QuadDeformation::Kind::Lattice, .columns = lattice.columns, .rows = lattice.rows},
                      offsets, {});
}

geo::Mesh paste_feature_gpu(Context& ctx, const geo::Mesh& mesh, const QuadRegion& region,
                            const std::vector<glm::dvec2>& uv, const PastedFeature& feature) {
    feature.evaluate({0.5, 0.5});  // the height map's own checks
    const double scale = feature.scale * mesh.bounds().diagonal();
    if (feature.heights.empty())
        return deform_gpu(ctx, mesh, region, uv, {.kind = QuadDeformation::Kind::Bump, .scale = scale}, {}, {});
    return deform_gpu(
        ctx, mesh, region, uv,
        {.kind = QuadDeformation::Kind::HeightMap, .columns = feature.width, .rows = feature.height, .scale = scale},
        {}, feature.heights);
}

}  // namespace gimg::passes
