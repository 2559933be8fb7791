#pragma once
// Typed, versioned handles to render-graph resources. A write returns the next version; declaring
// an access through an older version is an error (it would read data that is gone).

#include <cstdint>

namespace gimg {

struct BufferHandle {
    std::uint32_t id = UINT32_MAX;
    std::uint32_t version = 0;
    bool valid() const { return id != UINT32_MAX; }
};

struct ImageHandle {
    std::uint32_t id = UINT32_MAX;
    std::uint32_t version = 0;
    bool valid() const { return id != UINT32_MAX; }
};

}  // namespace gimg
