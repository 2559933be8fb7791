#include "gimg/passes/render.h"

#include "gimg/engine/graph.h"
#include "gimg/engine/upload.h"
#include "gimg/geometry/error.h"
#include "gimg/geometry/normals.h"

#include "render/downsample_comp.h"
#include "render/mesh_frag.h"
#include "render/mesh_vert.h"
#include "render/render_params.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace gimg::passes {

namespace {

const RasterProgram kMeshProgram{GIMG_SPIRV(gimg_spv_render_mesh_vert), GIMG_SPIRV(gimg_spv_render_mesh_frag),
                                 RasterState{}};
const Spirv kDownsample = GIMG_SPIRV(gimg_spv_render_downsample_comp);

struct DrawPush {
    glm::mat4 view_projection;
    glm::vec4 eye;
    glm::vec4 scalar_range;  // min, max, checker scale, wire width
    std::uint32_t color_mode;
    std::uint32_t flags;
    std::uint32_t pad[2];
};
static_assert(sizeof(DrawPush) <= 128);

struct DownsamplePush {
    std::uint32_t size[2];
    std::uint32_t factor;
    std::uint32_t pad;
    float background[4];
};

// Angle-weighted vertex normals as float xyz, for smooth shading.
std::vector<float> float_vertex_normals(const geo::Mesh& mesh) {
    const std::vector<glm::dvec3> n = geo::vertex_normals(mesh);
    std::vector<float> out(3 * n.size());
    for (std::size_t i = 0; i < n.size(); ++i) {
        // Vertices without a normal (isolated, cancelling fans) still need something to shade with.
        const glm::dvec3 v = glm::dot(n[i], n[i]) > 0.0 ? n[i] : glm::dvec3(0.0, 0.0, 1.0);
        out[3 * i] = float(v.x), out[3 * i + 1] = float(v.y), out[3 * i + 2] = float(v.z);
    }
    return out;
}

std::pair<float, float> default_range(std::vector<float> values, bool symmetric) {
    std::sort(values.begin(), values.end());
    const float lo = values[std::size_t(0.02 * double(values.size() - 1))];
    const float hi = values[std::size_t(0.98 * double(values.size() - 1))];
    if (symmetric) {
        const float m = std::max(std::max(std::abs(lo), std::abs(hi)), 1e-20f);
        return {-m, m};
    }
    return {lo, hi > lo ? hi : lo + 1.0f};
}

// The vertices some face uses.
std::vector<glm::dvec3> referenced_positions(const geo::Mesh& mesh) {
    std::vector<std::uint8_t> used(mesh.vertex_count(), 0);
    for (const glm::uvec3& t : mesh.triangles) used[t.x] = used[t.y] = used[t.z] = 1;
    std::vector<glm::dvec3> out;
    for (std::size_t i = 0; i < used.size(); ++i)
        if (used[i]) out.push_back(mesh.positions[i]);
    return out;
}

// The faces with every repeat of a face (the same three vertices, in any order) after its first left
// out: the depth test hides a repeat anyway, and a CPU rasteriser would fill it again.
std::vector<glm::uvec3> without_copies(const std::vector<glm::uvec3>& triangles) {
    std::vector<std::pair<glm::uvec3, std::uint32_t>> keyed(triangles.size());
    for (std::size_t f = 0; f < triangles.size(); ++f) {
        glm::uvec3 k = triangles[f];
        if (k.x > k.y) std::swap(k.x, k.y);
        if (k.y > k.z) std::swap(k.y, k.z);
        if (k.x > k.y) std::swap(k.x, k.y);
        keyed[f] = {k, std::uint32_t(f)};
    }
    auto key_less = [](const glm::uvec3& a, const glm::uvec3& b) {
        return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
    };
    std::sort(keyed.begin(), keyed.end(), [&](const auto& a, const auto& b) {
        return key_less(a.first, b.first) || (a.first == b.first && a.second < b.second);
    });
    std::vector<std::uint8_t> repeat(triangles.size(), 0);
    for (std::size_t i = 1; i < keyed.size(); ++i)
        if (keyed[i].first == keyed[i - 1].first) repeat[keyed[i].second] = 1;
    std::vector<glm::uvec3> out;
    out.reserve(triangles.size());
    for (std::size_t f = 0; f < triangles.size(); ++f)
        if (!repeat[f]) out.push_back(triangles[f]);
    return out;
}

}  // namespace

ImageHandle add_render_mesh(Graph& graph, const RenderMeshBuffers& mesh, const RenderOptions& o, const Camera& camera,
                            const std::string& name) {
    if (mesh.face_count == 0) throw geo::InputError("nothing to render: the mesh has no faces");
    if (o.width == 0 || o.height == 0) throw geo::InputError("render size must be at least 1x1");
    const std::uint32_t limit =
        graph.device_info() ? std::max(graph.device_info()->max_image_dimension_2d, 1u) : 16384u;
    if (o.width > limit || o.height > limit)
        throw geo::InputError("render size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                              " exceeds the device's limit of " + std::to_string(limit));
    const std::uint32_t ss = std::clamp(std::min(o.supersample, limit / std::max(o.width, o.height)), 1u, 8u);
    const bool scalar_mode = o.color == MeshColor::Scalar || o.color == MeshColor::Diverging;
    const double aspect = double(o.width) / double(o.height);
    DrawPush push{};
    push.view_projection = camera.view_projection(aspect);
    push.eye = glm::vec4(glm::vec3(camera.eye), 1.0f);
    const auto range = o.scalar_range ? *o.scalar_range : std::pair<float, float>{0.0f, 1.0f};
    if (scalar_mode && !(range.second > range.first))
        throw geo::InputError("colour by scalar needs a range whose maximum is above its minimum");
    push.scalar_range = {range.first, range.second, float(mesh.checker_scale), 1.1f * float(ss)};
    switch (o.color) {
        case MeshColor::Plain:
            push.color_mode = GIMG_COLOR_PLAIN;
            break;
        case MeshColor::Normal:
            push.color_mode = GIMG_COLOR_NORMAL;
            break;
        case MeshColor::Checker:
            push.color_mode = GIMG_COLOR_CHECKER;
            break;
        case MeshColor::Scalar:
            push.color_mode = GIMG_COLOR_SCALAR;
            break;
        case MeshColor::Diverging:
            push.color_mode = GIMG_COLOR_DIVERGING;
            break;
    }
    push.flags = (o.wireframe ? GIMG_RENDER_WIREFRAME : 0u) | (mesh.has_texcoords ? GIMG_RENDER_HAS_TEXCOORDS : 0u) |
                 (o.smooth ? GIMG_RENDER_SMOOTH : 0u);

    const BufferHandle pos = mesh.positions, tri = mesh.triangles, nrm = mesh.normals, sca = mesh.scalars,
                       tex = mesh.texcoords;
    auto samples = graph.create_image({o.width * ss, o.height * ss, Format::RGBA8, name + " samples"});
    auto depth = graph.create_image({o.width * ss, o.height * ss, Format::D32F, name + " depth"});
    auto picture = graph.create_image({o.width, o.height, Format::RGBA8, name + " picture"});
    const std::uint32_t vertex_count = 3 * mesh.face_count;
    graph.add_raster_pass(
        name + ": draw",
        [&](PassBuilder& b) {
            for (auto h : {pos, tri, nrm, sca, tex}) b.read(h, Access::VertexRead);
            samples = b.color(samples, ClearValue::color(0, 0, 0, 0));
            depth = b.depth(depth, ClearValue::depth(1.0f));
        },
        [=](Cmd& c) {
            c.draw(kMeshProgram, vertex_count, 1, {pos, tri, nrm, sca, tex}, push);
        });
    const DownsamplePush dpush{{o.width, o.height}, ss, 0, {o.background[0], o.background[1], o.background[2], 1.0f}};
    const std::uint32_t width = o.width, height = o.height;
    graph.add_compute_pass(
        name + ": downsample",
        [&](PassBuilder& b) {
            b.read(samples, Access::ComputeRead);
            picture = b.write(picture, Access::ComputeWrite);
        },
        [=](Cmd& c) {
            c.dispatch_threads(kDownsample, {width, height}, {samples, picture}, dpush);
        });
    return picture;
}

geo::RgbaImage render_mesh(Context& ctx, const geo::Mesh& mesh, const RenderOptions& options,
                           const std::optional<Camera>& camera_override) {
    if (mesh.face_count() == 0) throw geo::InputError("nothing to render: the mesh has no faces");
    const bool scalar_mode = options.color == MeshColor::Scalar || options.color == MeshColor::Diverging;
    if (scalar_mode && options.scalars.size() != mesh.vertex_count())
        throw geo::InputError("colour by scalar needs one value per vertex: got " +
                              std::to_string(options.scalars.size()) + " for " + std::to_string(mesh.vertex_count()) +
                              " vertices");

    // Drawn in a frame around the faces' vertices, scaled to unit size (a similarity, applied to the
    // camera too): models from 1e-15 to 1e38 across then rasterise and light alike in float32, and
    // a vertex no face uses neither moves the camera nor counts.
    const std::vector<glm::dvec3> used = referenced_positions(mesh);
    geo::Bounds box{used.front(), used.front()};
    for (const auto& p : used) box.min = glm::min(box.min, p), box.max = glm::max(box.max, p);
    const glm::dvec3 centre = 0.5 * (box.min + box.max);
    const double radius = 0.5 * box.diagonal() > 0.0 && std::isfinite(box.diagonal()) ? 0.5 * box.diagonal() : 1.0;
    std::vector<float> positions(3 * mesh.vertex_count());
    std::vector<glm::dvec3> unit_used;
    unit_used.reserve(used.size());
    for (const auto& p : used) unit_used.push_back((p - centre) / radius);
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i)
        for (int k = 0; k < 3; ++k) positions[3 * i + k] = float((mesh.positions[i][k] - centre[k]) / radius);
    std::vector<float> normals = options.smooth ? float_vertex_normals(mesh) : std::vector<float>{};
    std::vector<float> texcoords;
    if (mesh.has_texcoords())
        for (const auto& t : mesh.texcoords) texcoords.push_back(float(t.x)), texcoords.push_back(float(t.y));

    const std::vector<glm::uvec3> faces = without_copies(mesh.triangles);
    Buffer pos_buf, tri_buf, nrm_buf, sca_buf, tex_buf;
    ctx.batch_uploads([&] {  // one submission for the five
        pos_buf = upload_buffer(ctx, positions.data(), positions.size() * 4, "positions");
        tri_buf = upload_buffer(ctx, faces.data(), faces.size() * sizeof(glm::uvec3), "triangles");
        nrm_buf = upload_buffer(ctx, normals.data(), normals.size() * 4, "normals");
        sca_buf = upload_buffer(ctx, options.scalars.data(), scalar_mode ? options.scalars.size() * 4 : 0, "scalars");
        tex_buf = upload_buffer(ctx, texcoords.data(), texcoords.size() * 4, "texcoords");
    });

    RenderOptions o = options;
    if (scalar_mode && !o.scalar_range) o.scalar_range = default_range(o.scalars, o.color == MeshColor::Diverging);
    const double aspect = double(o.width) / double(std::max(o.height, 1u));
    Camera camera = fit_camera(unit_used, o.view, aspect);
    if (camera_override) {
        camera = *camera_override;
        camera.eye = (camera.eye - centre) / radius;
        camera.target = (camera.target - centre) / radius;
        camera.near_plane /= radius;
        camera.far_plane /= radius;
    }
    Graph g(ctx);
    const RenderMeshBuffers buffers{
        g.import_buffer(pos_buf),
        g.import_buffer(tri_buf),
        g.import_buffer(nrm_buf),
        g.import_buffer(sca_buf),
        g.import_buffer(tex_buf),
        std::uint32_t(faces.size()),
        mesh.has_texcoords(),
        mesh.has_texcoords() ? o.checker_cells : o.checker_cells * radius / std::max(box.diagonal(), 1e-300)};
    const ImageHandle picture = add_render_mesh(g, buffers, o, camera);
    g.export_image(picture, Access::TransferSrc);
    Plan plan = g.compile();
    plan.execute();

    std::vector<std::byte> bytes = ctx.download(plan.image(picture));
    geo::RgbaImage image(o.width, o.height);
    std::memcpy(image.pixels.data(), bytes.data(), image.pixels.size());
    return image;
}

geo::RgbaImage render_side_by_side(Context& ctx, const geo::Mesh& left, const geo::Mesh& right,
                                   const RenderOptions& options) {
    if (left.face_count() == 0 || right.face_count() == 0)
        throw geo::InputError("nothing to render: a mesh has no faces");
    std::vector<glm::dvec3> both = referenced_positions(left);
    const std::vector<glm::dvec3> right_used = referenced_positions(right);
    both.insert(both.end(), right_used.begin(), right_used.end());
    const Camera camera = fit_camera(both, options.view, double(options.width) / double(options.height));
    RenderOptions right_options = options;
    if (options.color == MeshColor::Scalar || options.color == MeshColor::Diverging)
        right_options.scalars.clear(),
            right_options.color = MeshColor::Plain;  // scalars belong to one mesh
    geo::RgbaImage l = render_mesh(ctx, left, options, camera);
    geo::RgbaImage r = render_mesh(ctx, right, right_options, camera);
    geo::RgbaImage out(2 * options.width, options.height);
    for (std::uint32_t y = 0; y < options.height; ++y) {
        std::memcpy(out.at(0, y), l.at(0, y), std::size_t(options.width) * 4);
        std::memcpy(out.at(options.width, y), r.at(0, y), std::size_t(options.width) * 4);
    }
    return out;
}

}  // namespace gimg::passes
