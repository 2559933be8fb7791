#pragma once
// Arrays kept in storage images instead of storage buffers: one texel an element,
// kTexelArrayRowWidth texels a row, as many rows as needed (shaders/common/texel_array.glsl is the
// shader side). Used by the sphere map's planar solves and the cylindrical Z-buffer's geometry.
//
// Why images: lavapipe (Mesa 22.3) compiles a storage-buffer load whose address differs between
// lanes into a loop over the 8 lanes with a branch and a bounds check for each, and an image load
// into a plain gather. A sparse matrix-vector product of armadillo_loop1's Laplacian (104K rows,
// 728K entries) took 2.4-4.4 ms from buffers and 1.2 ms from images, bit-identical (measured on
// the 2-core machines). GPUs load a whole texel as cheaply as 16 bytes of a buffer.
#include "gimg/engine/context.h"
#include "gimg/engine/error.h"
#include "gimg/engine/format.h"

#include <algorithm>
#include <cstring>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace gimg {

inline constexpr std::uint32_t kTexelArrayRowShift = 12;  // texel_array.glsl's kRowShift
inline constexpr std::uint32_t kTexelArrayRowWidth = 1u << kTexelArrayRowShift;

// An image of at least `count` texels (at least one row, so empty arrays still bind).
inline ImageDesc texel_array_desc(std::size_t count, Format format, const std::string& name) {
    const std::size_t rows = std::max<std::size_t>(1, (count + kTexelArrayRowWidth - 1) / kTexelArrayRowWidth);
    return {kTexelArrayRowWidth, std::uint32_t(rows), format, name};
}

// Throws gimg::Error (InvalidArgument) when `count` texels need more image rows than the device has.
inline void check_texel_array_size(const Context& ctx, std::size_t count, const std::string& what) {
    const std::size_t rows = (count + kTexelArrayRowWidth - 1) / kTexelArrayRowWidth;
    if (rows > ctx.device_info().max_image_dimension_2d)
        throw Error(ErrorKind::InvalidArgument, what + ": " + std::to_string(count) + " elements need " +
                                                    std::to_string(rows) + " image rows of " +
                                                    std::to_string(kTexelArrayRowWidth) + "; the device has " +
                                                    std::to_string(ctx.device_info().max_image_dimension_2d));
}

// A device image of `format` (one T a texel: T has the format's size) holding `texels`, padded to
// whole rows with zeros.
template <class T>
Image upload_texel_array(Context& ctx, std::span<const T> texels, Format format, const std::string& name) {
    if (sizeof(T) != bytes_per_pixel(format))
        throw Error(ErrorKind::InvalidArgument,
                    name + ": " + std::to_string(sizeof(T)) + "-byte elements in " + to_string(format) + " texels");
    check_texel_array_size(ctx, texels.size(), name);
    return ctx.create_image(texel_array_desc(texels.size(), format, name), [&](std::span<std::byte> bytes) {
        std::memcpy(bytes.data(), texels.data(), texels.size_bytes());
        std::memset(bytes.data() + texels.size_bytes(), 0, bytes.size() - texels.size_bytes());
    });
}
template <class T>
Image upload_texel_array(Context& ctx, const std::vector<T>& texels, Format format, const std::string& name) {
    return upload_texel_array(ctx, std::span<const T>(texels), format, name);
}

// The same for `count` texels that fill(std::span<T>) writes in place (the padding after them is
// zeros): no host array of them is made (Context::create_image says where they are written).
template <class T, class Fill>
Image upload_texel_array(Context& ctx, std::size_t count, Format format, const std::string& name, Fill&& fill) {
    if (sizeof(T) != bytes_per_pixel(format))
        throw Error(ErrorKind::InvalidArgument,
                    name + ": " + std::to_string(sizeof(T)) + "-byte elements in " + to_string(format) + " texels");
    check_texel_array_size(ctx, count, name);
    return ctx.create_image(texel_array_desc(count, format, name), [&](std::span<std::byte> bytes) {
        std::memset(bytes.data() + count * sizeof(T), 0, bytes.size() - count * sizeof(T));
        fill(std::span<T>(reinterpret_cast<T*>(bytes.data()), count));
    });
}

}  // namespace gimg
