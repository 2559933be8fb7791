#pragma once
// The render graph. Declare resources and passes, compile once, execute many times.
//
//   Graph g(ctx);
//   auto data = g.import_buffer(buffer);                        // caller-owned, persistent
//   auto tmp  = g.create_buffer({.size = n * 4, .name = "tmp"}); // transient, owned by the plan
//   g.add_compute_pass("square", [&](PassBuilder& b) {
//       b.read(data, Access::ComputeRead);
//       tmp = b.write(tmp, Access::ComputeWrite);
//   }, [=](Cmd& c) { c.dispatch_threads(kSquare, {n}, {data, tmp}, n); });
//   ...
//   Plan plan = g.compile();   // order, culling, barriers, layouts, transient reuse: derived
//   plan.execute();            // records, submits, waits; again and again without recompiling
//
// Passes run in the order they are added (handles make that a valid order). Setup callbacks run
// at once, inside add_*_pass; record callbacks run at every execution.

#include "gimg/engine/access.h"
#include "gimg/engine/cmd.h"
#include "gimg/engine/handles.h"
#include "gimg/engine/plan.h"
#include "gimg/engine/resources.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace gimg {

class Context;
struct DeviceInfo;

class PassBuilder;
namespace detail {
struct GraphData;
PassBuilder make_pass_builder(GraphData& graph, std::uint32_t pass);
}  // namespace detail

struct ClearValue {
    VkClearValue value{};
    static ClearValue color(float r, float g = 0.0f, float b = 0.0f, float a = 0.0f);
    static ClearValue color_uint(std::uint32_t r, std::uint32_t g = 0, std::uint32_t b = 0, std::uint32_t a = 0);
    static ClearValue depth(float d);
};

class PassBuilder {
public:
    void read(BufferHandle buffer, Access access);
    void read(ImageHandle image, Access access);
    // A write (or read-write) returns the resource's next version; use it from then on.
    [[nodiscard]] BufferHandle write(BufferHandle buffer, Access access);
    [[nodiscard]] ImageHandle write(ImageHandle image, Access access);
    // Raster passes: colour and depth attachments, cleared when `clear` is given, else loaded.
    [[nodiscard]] ImageHandle color(ImageHandle image, std::optional<ClearValue> clear = std::nullopt);
    [[nodiscard]] ImageHandle depth(ImageHandle image, std::optional<ClearValue> clear = std::nullopt);
    // Never cull this pass, even if nothing reads what it writes.
    void keep();

private:
    friend PassBuilder detail::make_pass_builder(detail::GraphData& graph, std::uint32_t pass);
    PassBuilder(detail::GraphData& graph, std::uint32_t pass) : graph_(&graph), pass_(pass) {}
    detail::GraphData* graph_;
    std::uint32_t pass_;
};

using SetupFn = std::function<void(PassBuilder&)>;
using RecordFn = std::function<void(Cmd&)>;

class Graph {
public:
    // A graph that executes on ctx.
    explicit Graph(Context& ctx);
    // A graph with no device: compile() plans it (order, culling, barriers, reuse) for inspection
    // and tests; its plan cannot execute.
    Graph();
    ~Graph();
    Graph(Graph&&) noexcept;
    Graph& operator=(Graph&&) noexcept;

    // Transient resources: created, reused or aliased, and freed by the plan.
    BufferHandle create_buffer(const BufferDesc& desc);
    ImageHandle create_image(const ImageDesc& desc);
    // Persistent resources the caller owns; the graph starts from their last access. Importing the
    // same object again returns its newest version: one resource per object, so that passes of
    // several capabilities sharing it are ordered and synchronised like any other.
    BufferHandle import_buffer(Buffer& buffer);
    ImageHandle import_image(Image& image);
    // An image's description: a transient's as created, an import's as the image has it.
    const ImageDesc& image_desc(ImageHandle image) const;
    // After the graph, leave the resource ready for `next` (e.g. TransferSrc to download it,
    // HostRead to map it). An exported transient is kept by the plan: read it through
    // Plan::buffer() / Plan::image().
    void export_buffer(BufferHandle buffer, Access next);
    void export_image(ImageHandle image, Access next);

    void add_compute_pass(std::string name, const SetupFn& setup, RecordFn record);
    void add_raster_pass(std::string name, const SetupFn& setup, RecordFn record);
    // The passes `body` adds run `iterations` times per execution, with the barriers between
    // iterations derived like any other (Cmd::iteration() tells the pass which one it is in).
    void add_loop(std::uint32_t iterations, const std::function<void()>& body);

    // Plans the graph. The graph is empty afterwards; the plan holds the passes.
    Plan compile();

    // The device the graph executes on; null for a graph with no device.
    const DeviceInfo* device_info() const;

private:
    Context* ctx_ = nullptr;
    std::unique_ptr<detail::GraphData> data_;
};

}  // namespace gimg
