#pragma once
// A compiled render graph, engine-internal: what compile() derived (order, culling, merged uses,
// lifetimes, physical resources, memory placement, barrier schedule) and what execution needs at
// run time (objects, command buffer, timestamp queries).

#include "gimg/engine/graph.h"
#include "gimg/engine/plan.h"

#include "barrier_rules.h"
#include "graph_data.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace gimg::detail {

struct Device;

// A pass's use of one resource: all its declarations of that resource merged.
struct Use {
    std::uint32_t resource = 0;  // logical resource (index into GraphData::resources)
    AccessInfo info{};
    bool discard = false;  // contents before this use do not matter
};

struct CompiledPass {
    std::uint32_t decl = 0;  // index into GraphData::passes
    std::vector<Use> uses;
    int loop = -1;  // index into PlanData::loops
};

struct CompiledLoop {
    std::uint32_t iterations = 1;
    std::uint32_t first = 0, end = 0;  // compiled pass indices [first, end)
};

struct PhysicalResource {
    bool image = false;
    std::int32_t import_of = -1;  // logical index when this is an imported resource
    bool exported = false;        // holds an exported transient: never reused or aliased
    std::optional<Access> export_access;
    Access last_access = Access::None;  // of the last pass using it (what Buffer::last_access says after)
    BufferDesc buffer_desc;
    ImageDesc image_desc;
    VkImageUsageFlags image_usage = 0;
    std::uint32_t first_use = 0, last_use = 0;  // compiled pass indices, loops widened
    std::string name;                           // the logical names it serves, joined by '|'
    std::optional<MemoryPlacement> placement;   // in an aliasing block
    std::vector<std::uint32_t> shares_memory_with;
    Buffer buffer;  // realised transient objects
    Image image_object;

    bool imported() const { return import_of >= 0; }
};

struct Schedule {
    std::vector<std::vector<Barrier>> before;  // per compiled pass, first iteration
    std::vector<std::vector<Barrier>> repeat;  // per compiled pass, later iterations
    std::vector<Barrier> final_barriers;       // towards the export accesses
    std::vector<SyncState> end;                // per physical resource
};

struct PlanData {
    Context* ctx = nullptr;
    Device* device = nullptr;
    GraphData graph;

    std::vector<CompiledPass> passes;
    std::vector<CompiledLoop> loops;
    std::vector<std::string> culled;
    std::vector<std::int32_t> physical_of;  // per logical resource; -1 when unused
    std::vector<PhysicalResource> physicals;
    std::vector<VkDeviceSize> block_sizes;  // aliasing blocks
    std::vector<Allocation> blocks;
    std::vector<SyncState> wrap_states;  // every resource's state at the end of an execution
    std::uint64_t executions = 0;        // recorded so far

    // Inspection results (first execution, from the imports' states at compile time).
    std::vector<PlannedPass> planned;
    std::vector<BarrierInfo> final_infos;

    // Run time.
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    std::uint64_t submitted = 0;  // timeline value of the last submission
    VkQueryPool query_pool = VK_NULL_HANDLE;
    std::uint32_t query_capacity = 0;
    std::vector<std::uint32_t> query_pass;  // compiled pass of each begin/end query pair
    bool timings_pending = false;
    std::vector<PassTiming> timings;

    ~PlanData();
};

// compile(): liveness, order, merged uses, lifetimes, physical resources; with a device also the
// objects and their memory; then the inspection schedule.
std::unique_ptr<PlanData> plan_graph(Context* ctx, GraphData&& graph);
// Per logical resource: the compiled passes it is used from and to (loops widened; UINT32_MAX
// when unused) and the image usage its accesses need.
struct ResourceLifetimes {
    std::vector<std::uint32_t> first, last;
    std::vector<VkImageUsageFlags> image_usage;
};

// Physical resources for the logical ones: imports stand for themselves, exported transients get
// their own, the others share where descriptions match and lifetimes do not overlap.
void assign_physical_resources(PlanData& plan, const ResourceLifetimes& lifetimes);
// Places physical transients in aliasing blocks (real memory requirements when a device is
// present, estimates otherwise) and, with a device, creates and binds them.
void place_transient_memory(PlanData& plan);
// The barriers of one execution given each physical resource's state at its start.
Schedule schedule_barriers(const PlanData& plan, std::vector<SyncState> states);
// Each physical resource's state at the start of an execution: imports from their objects;
// transients untouched on the first execution, else as the previous execution left them (its
// last reads and writes must finish before this one overwrites them).
std::vector<SyncState> start_states(const PlanData& plan, bool first_execution);
BarrierInfo describe_barrier(const PlanData& plan, const Barrier& barrier);

}  // namespace gimg::detail
