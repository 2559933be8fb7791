#pragma once
// How the planar solves keep their vectors and sparse matrices on the GPU: in storage images, one
// texel an element, kTexelArrayRowWidth texels a row (shaders/solvers/texels.glsl is the shader side).
//
// Why images and not storage buffers: gimg/engine/texel_array.h.
//
// Layouts: the conjugate gradients' vectors of dvec2 in RGBA32UI, element i in texel i (x bits in
// .xy, y bits in .zw); the multigrid cycle's vectors of vec2 in RG32F. A matrix in compressed rows
// is two images: its rows in RGBA32UI (begin, end, and one double per row: 1 / a_ii on multigrid
// levels, else 0) and its entries, in RGBA32UI (column, 0, double value) for the conjugate
// gradients' q = A p, in RG32UI (column, float value's bits) for the cycle. The dense level's
// inverse is an RG32UI image of doubles, row-major.
#include "solvers/multigrid.h"
#include "gimg/engine/texel_array.h"

#include "gimg/engine/context.h"

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace gimg::passes::detail {

// An RGBA32UI image of at least `count` texels: a vector of dvec2.
inline ImageDesc texel_image_desc(std::size_t count, const std::string& name) {
    return texel_array_desc(count, Format::RGBA32U, name);
}

// An RG32UI image of `values`, one double a texel (the dense level's inverse).
inline Image upload_double_texels(Context& ctx, const std::vector<double>& values, const std::string& name) {
    std::vector<glm::uvec2> texels(std::max<std::size_t>(values.size(), 1), glm::uvec2(0u));
    std::memcpy(texels.data(), values.data(), values.size() * sizeof(double));
    return upload_texel_array(ctx, std::move(texels), Format::RG32U, name);
}

// An RG32F image of at least `count` texels: a vector of vec2 (the multigrid cycle's).
inline ImageDesc float_vector_desc(std::size_t count, const std::string& name) {
    return texel_array_desc(count, Format::RG32F, name);
}

inline glm::uvec4 texel_of(std::uint32_t a, std::uint32_t b, double value) {
    std::uint64_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    return {a, b, std::uint32_t(bits), std::uint32_t(bits >> 32)};
}

inline glm::uvec4 texel_of(const glm::dvec2& v) {
    std::uint64_t x, y;
    std::memcpy(&x, &v.x, sizeof x);
    std::memcpy(&y, &v.y, sizeof y);
    return {std::uint32_t(x), std::uint32_t(x >> 32), std::uint32_t(y), std::uint32_t(y >> 32)};
}

// A device image holding `texels`, padded to whole rows.
inline Image upload_texels(Context& ctx, std::vector<glm::uvec4> texels, const std::string& name) {
    return upload_texel_array(ctx, std::move(texels), Format::RGBA32U, name);
}

inline Image upload_vector_texels(Context& ctx, const std::vector<glm::dvec2>& v, const std::string& name) {
    std::vector<glm::uvec4> texels(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) texels[i] = texel_of(v[i]);
    return upload_texels(ctx, std::move(texels), name);
}

inline std::vector<glm::dvec2> download_vector_texels(Context& ctx, Image& image, std::size_t n) {
    const std::vector<std::byte> bytes = ctx.download(image);
    std::vector<glm::dvec2> v(n);
    std::memcpy(v.data(), bytes.data(), n * sizeof(glm::dvec2));  // texel i holds x then y, as a dvec2
    return v;
}

// A matrix's entries as texels (column, 0, value) in double.
inline std::vector<glm::uvec4> entry_texels(const CsrMatrix& m) {
    std::vector<glm::uvec4> entries(m.values.size());
    for (std::size_t k = 0; k < entries.size(); ++k) entries[k] = texel_of(m.columns[k], 0u, m.values[k]);
    return entries;
}

// A matrix's entries as texels (column, value's bits) in float, the values given already rounded
// (MultigridLevel's, which the CPU cycle reads too).
inline Image upload_float_entries(Context& ctx, const CsrMatrix& m, const std::vector<float>& values,
                                  const std::string& name) {
    std::vector<glm::uvec2> entries(values.size());
    for (std::size_t k = 0; k < entries.size(); ++k) {
        std::uint32_t bits;
        std::memcpy(&bits, &values[k], sizeof bits);
        entries[k] = {m.columns[k], bits};
    }
    return upload_texel_array(ctx, std::move(entries), Format::RG32U, name);
}

// The two images of a matrix of the multigrid cycle in compressed rows, its entries in float;
// `row_values` (one per row, or empty for zeros) rides in the rows image.
struct TexelMatrix {
    Image rows, entries;
    std::uint32_t row_count = 0;
};

inline Image upload_rows(Context& ctx, const CsrMatrix& m, const std::vector<double>& row_values,
                         const std::string& name) {
    std::vector<glm::uvec4> rows(m.rows());
    for (std::size_t i = 0; i < m.rows(); ++i)
        rows[i] = texel_of(m.offsets[i], m.offsets[i + 1], row_values.empty() ? 0.0 : row_values[i]);
    return upload_texels(ctx, std::move(rows), name + " rows");
}

inline TexelMatrix upload_matrix_texels(Context& ctx, const CsrMatrix& m, const std::vector<float>& values,
                                        const std::vector<double>& row_values, const std::string& name) {
    return {upload_rows(ctx, m, row_values, name), upload_float_entries(ctx, m, values, name + " entries"),
            std::uint32_t(m.rows())};
}

}  // namespace gimg::passes::detail
