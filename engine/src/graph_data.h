#pragma once
// What a Graph records while passes are declared, before compile(). Engine-internal.

#include "gimg/engine/graph.h"

#include <optional>
#include <string>
#include <vector>

namespace gimg::detail {

constexpr std::uint32_t kNoPass = UINT32_MAX;

struct ResourceDecl {
    bool image = false;
    BufferDesc buffer_desc;
    ImageDesc image_desc;
    Buffer* imported_buffer = nullptr;  // imports only
    Image* imported_image = nullptr;
    std::optional<Access> export_access;
    std::uint32_t version = 0;                      // the newest version declared so far
    std::vector<std::uint32_t> producers{kNoPass};  // producers[v]: the pass that made version v

    bool imported() const { return imported_buffer || imported_image; }
    const std::string& name() const { return image ? image_desc.name : buffer_desc.name; }
};

struct AccessDecl {
    std::uint32_t resource = 0;
    Access access = Access::None;
};

struct AttachmentDecl {
    std::uint32_t resource = 0;
    std::optional<ClearValue> clear;
};

struct PassDecl {
    std::string name;
    bool raster = false;
    bool keep = false;
    std::vector<AccessDecl> accesses;
    std::vector<std::uint32_t> depends_on;  // passes that produced the versions this one uses
    std::vector<AttachmentDecl> colors;
    std::optional<AttachmentDecl> depth;
    RecordFn record;
    int loop = -1;  // index into GraphData::loops, -1 outside loops
};

struct LoopDecl {
    std::uint32_t iterations = 1;
    std::uint32_t first_pass = 0;  // declaration indices, [first_pass, end_pass)
    std::uint32_t end_pass = 0;
};

struct GraphData {
    std::vector<ResourceDecl> resources;
    std::vector<PassDecl> passes;
    std::vector<LoopDecl> loops;
    int open_loop = -1;

    [[noreturn]] void fail(const std::string& message) const;
    ResourceDecl& resource(std::uint32_t id, bool image, const char* what);
};

}  // namespace gimg::detail
