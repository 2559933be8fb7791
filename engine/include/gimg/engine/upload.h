#pragma once
// Host arrays into new device buffers, for passes that read them as storage buffers.
#include "gimg/engine/context.h"

#include <algorithm>
#include <string>
#include <vector>

namespace gimg {

// A device buffer holding `bytes` bytes of `data`; at least 16 bytes, so an empty array still binds.
inline Buffer upload_buffer(Context& ctx, const void* data, std::size_t bytes, const std::string& name) {
    Buffer b = ctx.create_buffer({std::max<std::size_t>(bytes, 16), name});
    if (bytes > 0) ctx.upload(b, data, bytes);
    return b;
}

template <class T>
Buffer upload_buffer(Context& ctx, const std::vector<T>& data, const std::string& name) {
    return upload_buffer(ctx, data.data(), data.size() * sizeof(T), name);
}

}  // namespace gimg
