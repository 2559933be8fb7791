// Declaring a render graph: resources, passes with their accesses, loops, imports and exports.
#include "gimg/engine/graph.h"

#include "gimg/engine/context.h"
#include "gimg/engine/error.h"

#include "graph_data.h"
#include "planner.h"

namespace gimg {

using detail::GraphData;
using detail::ResourceDecl;

namespace detail {

void GraphData::fail(const std::string& message) const { throw Error(ErrorKind::InvalidGraph, message); }

ResourceDecl& GraphData::resource(std::uint32_t id, bool image, const char* what) {
    if (id >= resources.size() || resources[id].image != image)
        fail(std::string(what) + ": not a " + (image ? "image" : "buffer") + " handle of this graph");
    return resources[id];
}

}  // namespace detail

ClearValue ClearValue::color(float r, float g, float b, float a) {
    ClearValue c;
    c.value.color.float32[0] = r;
    c.value.color.float32[1] = g;
    c.value.color.float32[2] = b;
    c.value.color.float32[3] = a;
    return c;
}

ClearValue ClearValue::color_uint(std::uint32_t r, std::uint32_t g, std::uint32_t b, std::uint32_t a) {
    ClearValue c;
    c.value.color.uint32[0] = r;
    c.value.color.uint32[1] = g;
    c.value.color.uint32[2] = b;
    c.value.color.uint32[3] = a;
    return c;
}

ClearValue ClearValue::depth(float d) {
    ClearValue c;
    c.value.depthStencil = {d, 0};
    return c;
}

namespace {

// Records an access of (id, version) by `pass`; a write makes the next version.
std::uint32_t declare(GraphData& g, std::uint32_t pass, std::uint32_t id, std::uint32_t version, bool image,
                      Access access, bool write) {
    detail::PassDecl& p = g.passes[pass];
    ResourceDecl& r = g.resource(id, image, p.name.c_str());
    if (access == Access::None || access == Access::HostRead || access == Access::HostWrite)
        g.fail("pass '" + p.name + "' declares " + to_string(access) + " on '" + r.name() +
               "'; passes access resources on the GPU");
    if (version != r.version)
        g.fail("pass '" + p.name + "' uses version " + std::to_string(version) + " of '" + r.name() +
               "', but version " + std::to_string(r.version) + " exists: use the handle the last write returned");
    const AccessInfo info = access_info(access);
    if (write && !info.writes)
        g.fail("pass '" + p.name + "' declares " + to_string(access) + " on '" + r.name() + "' as a write");
    if (!write && info.writes)
        g.fail("pass '" + p.name + "' declares the write " + to_string(access) + " on '" + r.name() +
               "' with read(): use write(), which returns the new version");
    if (image && (access == Access::IndexBuffer || access == Access::IndirectArgs || access == Access::ComputeUniform ||
                  access == Access::GraphicsUniform))
        g.fail("pass '" + p.name + "' declares buffer access " + to_string(access) + " on image '" + r.name() + "'");
    if (!image && (access == Access::ColorAttachment || access == Access::DepthAttachment ||
                   access == Access::ComputeSampled || access == Access::FragmentSampled))
        g.fail("pass '" + p.name + "' declares image access " + to_string(access) + " on buffer '" + r.name() + "'");
    const bool graphics_access =
        access == Access::VertexRead || access == Access::FragmentRead || access == Access::FragmentWrite ||
        access == Access::FragmentReadWrite || access == Access::FragmentSampled || access == Access::GraphicsUniform ||
        access == Access::IndexBuffer || access == Access::ColorAttachment || access == Access::DepthAttachment;
    if (graphics_access && !p.raster)
        g.fail("compute pass '" + p.name + "' declares graphics access " + to_string(access) + " on '" + r.name() +
               "'");

    p.accesses.push_back({id, access});
    // Writes keep the previous producer too: gimg cannot know whether a write covers everything.
    if (r.producers[version] != detail::kNoPass && r.producers[version] != pass)
        p.depends_on.push_back(r.producers[version]);
    if (!write) return version;
    r.version = version + 1;
    r.producers.push_back(pass);
    return r.version;
}

}  // namespace

void PassBuilder::read(BufferHandle h, Access access) {
    declare(*graph_, pass_, h.id, h.version, false, access, false);
}
void PassBuilder::read(ImageHandle h, Access access) { declare(*graph_, pass_, h.id, h.version, true, access, false); }

BufferHandle PassBuilder::write(BufferHandle h, Access access) {
    return {h.id, declare(*graph_, pass_, h.id, h.version, false, access, true)};
}

ImageHandle PassBuilder::write(ImageHandle h, Access access) {
    return {h.id, declare(*graph_, pass_, h.id, h.version, true, access, true)};
}

ImageHandle PassBuilder::color(ImageHandle h, std::optional<ClearValue> clear) {
    auto& p = graph_->passes[pass_];
    if (!p.raster) graph_->fail("pass '" + p.name + "' is not a raster pass but declares a colour attachment");
    ImageHandle next = write(h, Access::ColorAttachment);
    if (is_depth(graph_->resources[h.id].image_desc.format))
        graph_->fail("pass '" + p.name + "': '" + graph_->resources[h.id].name() + "' is a depth image");
    p.colors.push_back({h.id, clear});
    return next;
}

ImageHandle PassBuilder::depth(ImageHandle h, std::optional<ClearValue> clear) {
    auto& p = graph_->passes[pass_];
    if (!p.raster) graph_->fail("pass '" + p.name + "' is not a raster pass but declares a depth attachment");
    if (p.depth) graph_->fail("pass '" + p.name + "' declares two depth attachments");
    ImageHandle next = write(h, Access::DepthAttachment);
    if (!is_depth(graph_->resources[h.id].image_desc.format))
        graph_->fail("pass '" + p.name + "': '" + graph_->resources[h.id].name() + "' is not a depth image");
    p.depth = detail::AttachmentDecl{h.id, clear};
    return next;
}

void PassBuilder::keep() { graph_->passes[pass_].keep = true; }

Graph::Graph(Context& ctx) : ctx_(&ctx), data_(std::make_unique<GraphData>()) {}
Graph::Graph() : data_(std::make_unique<GraphData>()) {}
Graph::~Graph() = default;
Graph::Graph(Graph&&) noexcept = default;
Graph& Graph::operator=(Graph&&) noexcept = default;

const DeviceInfo* Graph::device_info() const { return ctx_ ? &ctx_->device_info() : nullptr; }

BufferHandle Graph::create_buffer(const BufferDesc& desc) {
    if (desc.size == 0) data_->fail("transient buffer '" + desc.name + "' has size 0");
    ResourceDecl r;
    r.buffer_desc = desc;
    if (r.buffer_desc.name.empty()) r.buffer_desc.name = "buffer" + std::to_string(data_->resources.size());
    data_->resources.push_back(std::move(r));
    return {std::uint32_t(data_->resources.size() - 1), 0};
}

ImageHandle Graph::create_image(const ImageDesc& desc) {
    if (desc.width == 0 || desc.height == 0) data_->fail("transient image '" + desc.name + "' has a zero size");
    ResourceDecl r;
    r.image = true;
    r.image_desc = desc;
    if (r.image_desc.name.empty()) r.image_desc.name = "image" + std::to_string(data_->resources.size());
    data_->resources.push_back(std::move(r));
    return {std::uint32_t(data_->resources.size() - 1), 0};
}

BufferHandle Graph::import_buffer(Buffer& buffer) {
    if (!buffer) data_->fail("import of an empty Buffer");
    for (std::uint32_t i = 0; i < data_->resources.size(); ++i)
        if (data_->resources[i].imported_buffer == &buffer) return {i, data_->resources[i].version};
    ResourceDecl r;
    r.buffer_desc = {buffer.size(), buffer.name().empty() ? "imported buffer" : buffer.name()};
    r.imported_buffer = &buffer;
    data_->resources.push_back(std::move(r));
    return {std::uint32_t(data_->resources.size() - 1), 0};
}

ImageHandle Graph::import_image(Image& image) {
    if (!image) data_->fail("import of an empty Image");
    for (std::uint32_t i = 0; i < data_->resources.size(); ++i)
        if (data_->resources[i].imported_image == &image) return {i, data_->resources[i].version};
    ResourceDecl r;
    r.image = true;
    r.image_desc = image.desc();
    if (r.image_desc.name.empty()) r.image_desc.name = "imported image";
    r.imported_image = &image;
    data_->resources.push_back(std::move(r));
    return {std::uint32_t(data_->resources.size() - 1), 0};
}

const ImageDesc& Graph::image_desc(ImageHandle h) const { return data_->resource(h.id, true, "image_desc").image_desc; }

void Graph::export_buffer(BufferHandle h, Access next) {
    ResourceDecl& r = data_->resource(h.id, false, "export_buffer");
    if (next == Access::None) data_->fail("export of '" + r.name() + "' needs the access that comes next");
    r.export_access = next;
}

void Graph::export_image(ImageHandle h, Access next) {
    ResourceDecl& r = data_->resource(h.id, true, "export_image");
    if (next == Access::None || next == Access::HostRead || next == Access::HostWrite)
        data_->fail("export of image '" + r.name() + "' as " + to_string(next) +
                    ": images are not host-visible; export TransferSrc and download it");
    r.export_access = next;
}

namespace {
void add_pass(GraphData& g, std::string name, bool raster, const SetupFn& setup, RecordFn record) {
    for (const auto& p : g.passes)
        if (p.name == name) g.fail("two passes are named '" + name + "'");
    detail::PassDecl p;
    p.name = std::move(name);
    p.raster = raster;
    p.record = std::move(record);
    p.loop = g.open_loop;
    g.passes.push_back(std::move(p));
    PassBuilder builder = detail::make_pass_builder(g, std::uint32_t(g.passes.size() - 1));
    if (setup) setup(builder);
    if (raster && g.passes.back().colors.empty() && !g.passes.back().depth)
        g.fail("raster pass '" + g.passes.back().name + "' declares no attachment");
}
}  // namespace

namespace detail {
PassBuilder make_pass_builder(GraphData& g, std::uint32_t pass) { return PassBuilder(g, pass); }
}  // namespace detail

void Graph::add_compute_pass(std::string name, const SetupFn& setup, RecordFn record) {
    add_pass(*data_, std::move(name), false, setup, std::move(record));
}

void Graph::add_raster_pass(std::string name, const SetupFn& setup, RecordFn record) {
    add_pass(*data_, std::move(name), true, setup, std::move(record));
}

void Graph::add_loop(std::uint32_t iterations, const std::function<void()>& body) {
    if (data_->open_loop >= 0) data_->fail("loops cannot nest");
    if (iterations == 0) data_->fail("a loop needs at least one iteration");
    detail::LoopDecl loop;
    loop.iterations = iterations;
    loop.first_pass = std::uint32_t(data_->passes.size());
    data_->loops.push_back(loop);
    data_->open_loop = int(data_->loops.size() - 1);
    try {
        body();
    } catch (...) {
        data_->open_loop = -1;
        throw;
    }
    data_->open_loop = -1;
    data_->loops.back().end_pass = std::uint32_t(data_->passes.size());
    if (data_->loops.back().end_pass == data_->loops.back().first_pass) data_->fail("a loop without passes");
}

Plan Graph::compile() {
    if (!data_) throw Error(ErrorKind::InvalidGraph, "compile() on a graph that was already compiled");
    auto data = std::move(data_);
    data_ = std::make_unique<GraphData>();
    return Plan(detail::plan_graph(ctx_, std::move(*data)));
}

}  // namespace gimg
