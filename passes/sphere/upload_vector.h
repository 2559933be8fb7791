#pragma once
// A device buffer holding a copy of a host vector (at least one element's size, so empty vectors
// still make a valid binding).
#include "gimg/engine/context.h"

#include <algorithm>
#include <span>
#include <string>
#include <vector>

namespace gimg::passes::detail {

template <class T>
Buffer upload_vector(Context& ctx, const std::vector<T>& data, const std::string& name) {
    Buffer buffer = ctx.create_buffer({VkDeviceSize(std::max<std::size_t>(data.size(), 1) * sizeof(T)), name});
    if (!data.empty()) ctx.upload(buffer, std::span<const T>(data));
    return buffer;
}

}  // namespace gimg::passes::detail
