// Plan: inspection of what compile() derived, and execution.
#include "gimg/engine/plan.h"

#include "check.h"
#include "device.h"
#include "recorder.h"

#include <cstdio>
#include <sstream>

namespace gimg {

using detail::PlanData;

Plan::Plan(std::unique_ptr<PlanData> data) : data_(std::move(data)) {}
Plan::~Plan() = default;
Plan::Plan(Plan&&) noexcept = default;
Plan& Plan::operator=(Plan&&) noexcept = default;

const std::vector<PlannedPass>& Plan::passes() const { return data_->planned; }
const std::vector<std::string>& Plan::culled_passes() const { return data_->culled; }
const std::vector<BarrierInfo>& Plan::final_barriers() const { return data_->final_infos; }

const PlannedPass& Plan::pass(const std::string& name) const {
    for (const auto& p : data_->planned)
        if (p.name == name) return p;
    throw Error(ErrorKind::InvalidArgument, "the plan has no (live) pass named '" + name + "'");
}

namespace {
std::optional<std::uint32_t> physical(const PlanData& d, std::uint32_t id) {
    if (id >= d.physical_of.size() || d.physical_of[id] < 0) return std::nullopt;
    const auto& p = d.physicals[d.physical_of[id]];
    if (p.imported()) return std::nullopt;
    return std::uint32_t(d.physical_of[id]);
}
std::optional<MemoryPlacement> placement_of(const PlanData& d, std::uint32_t id) {
    auto p = physical(d, id);
    if (!p) return std::nullopt;
    return d.physicals[*p].placement;
}
}  // namespace

std::optional<std::uint32_t> Plan::physical_resource(BufferHandle h) const { return physical(*data_, h.id); }
std::optional<std::uint32_t> Plan::physical_resource(ImageHandle h) const { return physical(*data_, h.id); }
std::uint32_t Plan::physical_resource_count() const {
    std::uint32_t n = 0;
    for (const auto& p : data_->physicals) n += p.imported() ? 0 : 1;
    return n;
}
std::optional<MemoryPlacement> Plan::placement(BufferHandle h) const { return placement_of(*data_, h.id); }
std::optional<MemoryPlacement> Plan::placement(ImageHandle h) const { return placement_of(*data_, h.id); }

VkDeviceSize Plan::transient_memory_bytes() const {
    VkDeviceSize total = 0;
    for (VkDeviceSize s : data_->block_sizes) total += s;
    return total;
}

namespace {
std::string stages_text(VkPipelineStageFlags2 s) {
    if (!s) return "NONE";
    static const std::pair<VkPipelineStageFlags2, const char*> names[] = {
        {VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, "INDIRECT"},
        {VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT, "INDEX"},
        {VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT, "VERTEX"},
        {VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, "FRAGMENT"},
        {VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT, "EARLY_Z"},
        {VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, "LATE_Z"},
        {VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, "COLOR_OUT"},
        {VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, "COMPUTE"},
        {VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, "TRANSFER"},
        {VK_PIPELINE_STAGE_2_HOST_BIT, "HOST"},
    };
    std::string out;
    for (auto [bit, name] : names)
        if (s & bit) {
            if (!out.empty()) out += '|';
            out += name;
        }
    return out.empty() ? "OTHER" : out;
}
std::string access_text(VkAccessFlags2 a) {
    if (!a) return "-";
    static const std::pair<VkAccessFlags2, const char*> names[] = {
        {VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT, "indirect"},
        {VK_ACCESS_2_INDEX_READ_BIT, "index"},
        {VK_ACCESS_2_UNIFORM_READ_BIT, "uniform"},
        {VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, "sampled"},
        {VK_ACCESS_2_SHADER_STORAGE_READ_BIT, "storage-r"},
        {VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, "storage-w"},
        {VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT, "color-r"},
        {VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, "color-w"},
        {VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT, "depth-r"},
        {VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, "depth-w"},
        {VK_ACCESS_2_TRANSFER_READ_BIT, "transfer-r"},
        {VK_ACCESS_2_TRANSFER_WRITE_BIT, "transfer-w"},
        {VK_ACCESS_2_HOST_READ_BIT, "host-r"},
        {VK_ACCESS_2_HOST_WRITE_BIT, "host-w"},
    };
    std::string out;
    for (auto [bit, name] : names)
        if (a & bit) {
            if (!out.empty()) out += '|';
            out += name;
        }
    return out.empty() ? "other" : out;
}
const char* layout_text(VkImageLayout l) {
    switch (l) {
        case VK_IMAGE_LAYOUT_UNDEFINED:
            return "UNDEFINED";
        case VK_IMAGE_LAYOUT_GENERAL:
            return "GENERAL";
        case VK_IMAGE_LAYOUT_ATTACHMENT_OPTIMAL:
            return "ATTACHMENT";
        case VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL:
            return "SHADER_READ_ONLY";
        case VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL:
            return "TRANSFER_SRC";
        case VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL:
            return "TRANSFER_DST";
        default:
            return "OTHER";
    }
}
void describe_barriers(std::ostringstream& out, const char* label, const std::vector<BarrierInfo>& barriers) {
    for (const BarrierInfo& b : barriers) {
        out << "    " << label << " " << b.resource << ": " << stages_text(b.src_stages) << "/"
            << access_text(b.src_access) << " -> " << stages_text(b.dst_stages) << "/" << access_text(b.dst_access);
        if (b.image && b.old_layout != b.new_layout)
            out << "  " << layout_text(b.old_layout) << " -> " << layout_text(b.new_layout);
        out << "\n";
    }
}
}  // namespace

std::string Plan::describe() const {
    const PlanData& d = *data_;
    std::ostringstream out;
    out << "plan: " << d.planned.size() << " passes, " << d.culled.size() << " culled, " << physical_resource_count()
        << " transient resources in " << transient_memory_bytes() << " bytes\n";
    for (const PlannedPass& p : d.planned) {
        out << "  " << (p.raster ? "raster " : "compute ") << "'" << p.name << "'";
        if (p.iterations > 1) out << " x" << p.iterations;
        out << "\n";
        describe_barriers(out, "barrier", p.barriers);
        describe_barriers(out, "repeat ", p.repeat_barriers);
    }
    describe_barriers(out, "export ", d.final_infos);
    for (const std::string& c : d.culled) out << "  culled '" << c << "'\n";
    for (std::size_t i = 0; i < d.physicals.size(); ++i) {
        const auto& p = d.physicals[i];
        if (p.imported()) continue;
        out << "  resource #" << i << " " << p.name << " passes " << p.first_use << ".." << p.last_use;
        if (p.placement)
            out << " at " << p.placement->offset << "+" << p.placement->size << " in block " << p.placement->block;
        if (p.exported) out << " (exported)";
        out << "\n";
    }
    return out.str();
}

namespace {
detail::Device& device_of(PlanData& d) {
    if (!d.device)
        throw Error(ErrorKind::InvalidArgument, "this plan was compiled without a Context and cannot execute");
    return *d.device;
}

// After recording, imported objects carry the state the execution leaves them in.
void hand_back_imports(PlanData& d, const detail::Schedule& s) {
    for (std::size_t p = 0; p < d.physicals.size(); ++p) {
        auto& ph = d.physicals[p];
        const bool imported = ph.imported();
        const detail::ResourceDecl* decl = imported ? &d.graph.resources[ph.import_of] : nullptr;
        const Access last = ph.export_access ? *ph.export_access : ph.last_access;
        if (ph.image) {
            Image& img = imported ? *decl->imported_image : ph.image_object;
            img.set_last_access(last);
            img.sync_state() = s.end[p];
        } else {
            Buffer& buf = imported ? *decl->imported_buffer : ph.buffer;
            buf.set_last_access(last);
            buf.sync_state() = s.end[p];
        }
    }
}
}  // namespace

void Plan::execute(const ExecuteOptions& options) {
    PlanData& d = *data_;
    detail::Device& dev = device_of(d);
    dev.wait(d.submitted);  // the command buffer is re-recorded; its last use must be done
    collect_pending_timings();
    if (!d.cmd) d.cmd = dev.allocate_command_buffer();
    GIMG_VK_CHECK(dev.fn.vkResetCommandBuffer(d.cmd, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    GIMG_VK_CHECK(dev.fn.vkBeginCommandBuffer(d.cmd, &begin));
    detail::Recorder recorder(d, d.cmd);
    detail::Schedule s = recorder.record(options.timestamps);
    GIMG_VK_CHECK(dev.fn.vkEndCommandBuffer(d.cmd));
    d.submitted = dev.submit(d.cmd);
    hand_back_imports(d, s);
    d.timings_pending = options.timestamps;
    if (options.wait) wait();
}

void Plan::record(VkCommandBuffer command_buffer, bool timestamps) {
    PlanData& d = *data_;
    device_of(d);
    collect_pending_timings();
    detail::Recorder recorder(d, command_buffer);
    detail::Schedule s = recorder.record(timestamps);
    hand_back_imports(d, s);
    d.timings_pending = timestamps;
}

void Plan::wait() {
    PlanData& d = *data_;
    device_of(d).wait(d.submitted);
    collect_pending_timings();
}

bool Plan::finished() {
    PlanData& d = *data_;
    return device_of(d).finished(d.submitted);
}

void Plan::collect_pending_timings() {
    PlanData& d = *data_;
    if (!d.timings_pending) return;
    detail::Device& dev = device_of(d);
    dev.wait(d.submitted);
    d.timings_pending = false;
    const std::uint32_t count = 2 * std::uint32_t(d.query_pass.size());
    std::vector<std::uint64_t> ticks(count);
    GIMG_VK_CHECK(dev.fn.vkGetQueryPoolResults(dev.device, d.query_pool, 0, count, count * sizeof(std::uint64_t),
                                               ticks.data(), sizeof(std::uint64_t),
                                               VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    d.timings.assign(d.passes.size(), PassTiming{});
    for (std::size_t i = 0; i < d.passes.size(); ++i) d.timings[i].name = d.graph.passes[d.passes[i].decl].name;
    for (std::size_t q = 0; q < d.query_pass.size(); ++q) {
        PassTiming& t = d.timings[d.query_pass[q]];
        t.gpu_ms += double(ticks[2 * q + 1] - ticks[2 * q]) * dev.info.timestamp_period_ns * 1e-6;
        ++t.iterations;
    }
}

const std::vector<PassTiming>& Plan::timings() {
    collect_pending_timings();
    return data_->timings;
}

double Plan::total_gpu_ms() {
    double total = 0.0;
    for (const PassTiming& t : timings()) total += t.gpu_ms;
    return total;
}

Buffer& Plan::buffer(BufferHandle h) {
    PlanData& d = *data_;
    if (h.id >= d.physical_of.size() || d.graph.resources[h.id].image || d.physical_of[h.id] < 0)
        throw Error(ErrorKind::InvalidArgument, "Plan::buffer: not a buffer this plan uses");
    auto& p = d.physicals[d.physical_of[h.id]];
    if (p.imported()) return *d.graph.resources[h.id].imported_buffer;
    if (!p.exported)
        throw Error(ErrorKind::InvalidArgument, "Plan::buffer: '" + p.name + "' is transient; export it to read it");
    return p.buffer;
}

Image& Plan::image(ImageHandle h) {
    PlanData& d = *data_;
    if (h.id >= d.physical_of.size() || !d.graph.resources[h.id].image || d.physical_of[h.id] < 0)
        throw Error(ErrorKind::InvalidArgument, "Plan::image: not an image this plan uses");
    auto& p = d.physicals[d.physical_of[h.id]];
    if (p.imported()) return *d.graph.resources[h.id].imported_image;
    if (!p.exported)
        throw Error(ErrorKind::InvalidArgument, "Plan::image: '" + p.name + "' is transient; export it to read it");
    return p.image_object;
}

}  // namespace gimg
