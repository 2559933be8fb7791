// NumPy arrays to and from the library's types (module_support.h).
#include "module_support.h"

#include "gimg/geometry/error.h"

#include <cmath>
#include <cstring>

namespace gimg::python {

using Positions = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Faces = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

namespace {

// The checks and conversions of the arrays crossing into and out of the library, written as flat
// loops that vectorise; the AVX2 clones keep them a small part of a call's time (the call-overhead
// goal of docs/python.md).
__attribute__((target_clones("avx2", "default"))) bool all_finite(const double* p, std::size_t count) {
    bool finite = true;
    for (std::size_t i = 0; i < count; ++i) finite &= std::isfinite(p[i]);
    return finite;
}

// Narrows vertex indices to 32 bits; true when every index lies in [0, n) (a negative one wraps past n).
__attribute__((target_clones("avx2", "default"))) bool narrow_indices(const std::int64_t* f, std::size_t count,
                                                                      std::size_t n, std::uint32_t* out) {
    std::uint64_t outside = 0;
    for (std::size_t i = 0; i < count; ++i) {
        outside |= std::uint64_t(f[i]) >= n;
        out[i] = std::uint32_t(f[i]);
    }
    return outside == 0;
}

// distance where covered, NaN where not, and the mask as bool; the image is stored row by row
// (index(u, v) = v * width + u), as the arrays are.
__attribute__((target_clones("avx2", "default"))) void empty_as_nan(const float* distance, const std::uint8_t* covered,
                                                                    std::size_t count, float* out, bool* mask) {
    for (std::size_t i = 0; i < count; ++i) {
        out[i] = covered[i] ? distance[i] : NAN;
        mask[i] = covered[i] != 0;
    }
}

}  // namespace

// The mesh of two arrays, checked as the loaders check files.
geo::Mesh to_mesh(const Positions& positions, const Faces& faces) {
    if (positions.ndim() != 2 || positions.shape(1) != 3) throw geo::InputError("positions must be an N x 3 array");
    if (faces.ndim() != 2 || faces.shape(1) != 3)
        throw geo::InputError("faces must be an M x 3 array of vertex indices");
    // Both arrays are C-contiguous (forcecast): read as flat runs; the search for the culprit runs
    // only when a check fails.
    static_assert(sizeof(glm::dvec3) == 3 * sizeof(double) && sizeof(glm::uvec3) == 3 * sizeof(std::uint32_t));
    geo::Mesh m;
    const auto n = std::size_t(positions.shape(0));
    const double* p = positions.data();
    if (!all_finite(p, 3 * n))
        for (std::size_t i = 0; i < 3 * n; ++i)
            if (!std::isfinite(p[i])) throw geo::InputError("position " + std::to_string(i / 3) + " is not finite");
    m.positions.assign(reinterpret_cast<const glm::dvec3*>(p), reinterpret_cast<const glm::dvec3*>(p) + n);
    const std::int64_t* f = faces.data();
    const auto count = std::size_t(faces.shape(0));
    if (count == 0) throw geo::InputError("the mesh has no faces");
    m.triangles.resize(count);
    if (!narrow_indices(f, 3 * count, n, &m.triangles.front().x))
        for (std::size_t i = 0; i < 3 * count; ++i)
            if (std::uint64_t(f[i]) >= n)
                throw geo::InputError("face " + std::to_string(i / 3) + " names vertex " + std::to_string(f[i]) +
                                      " of " + std::to_string(n));
    return m;
}

py::array_t<double> positions_array(const std::vector<glm::dvec3>& p) {
    py::array_t<double> out({py::ssize_t(p.size()), py::ssize_t(3)});
    auto o = out.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < o.shape(0); ++i)
        for (int k = 0; k < 3; ++k) o(i, k) = p[std::size_t(i)][k];
    return out;
}

py::array_t<std::int64_t> faces_array(const std::vector<glm::uvec3>& t) {
    py::array_t<std::int64_t> out({py::ssize_t(t.size()), py::ssize_t(3)});
    auto o = out.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < o.shape(0); ++i)
        for (int k = 0; k < 3; ++k) o(i, k) = t[std::size_t(i)][k];
    return out;
}

py::array_t<double> uv_array(const std::vector<glm::dvec2>& uv) {
    py::array_t<double> out({py::ssize_t(uv.size()), py::ssize_t(2)});
    auto o = out.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < o.shape(0); ++i) o(i, 0) = uv[std::size_t(i)].x, o(i, 1) = uv[std::size_t(i)].y;
    return out;
}

py::dict position_image_dict(const passes::PositionImage& image) {
    py::array_t<float> xyz({py::ssize_t(image.height), py::ssize_t(image.width), py::ssize_t(3)});
    py::array_t<bool> covered({py::ssize_t(image.height), py::ssize_t(image.width)});
    auto x = xyz.mutable_unchecked<3>();
    auto c = covered.mutable_unchecked<2>();
    for (std::uint32_t b = 0; b < image.height; ++b)
        for (std::uint32_t a = 0; a < image.width; ++a) {
            const std::size_t o = image.index(a, b);
            for (int k = 0; k < 3; ++k) x(b, a, k) = image.xyz[3 * o + std::size_t(k)];
            c(b, a) = image.covered[o] != 0;
        }
    py::dict d;
    d["image"] = xyz;
    d["covered"] = covered;
    return d;
}

// The mesh's own parameters for `sample`: N x 2 in [0, 1]^2.
std::vector<glm::dvec2> to_uv(const py::array_t<double, py::array::c_style | py::array::forcecast>& uv, std::size_t n) {
    if (uv.ndim() != 2 || uv.shape(1) != 2 || std::size_t(uv.shape(0)) != n)
        throw geo::InputError("texture coordinates must be an N x 2 array, one row per vertex");
    const auto a = uv.unchecked<2>();
    std::vector<glm::dvec2> out(n);
    for (std::size_t i = 0; i < n; ++i) {
        out[i] = {a(py::ssize_t(i), 0), a(py::ssize_t(i), 1)};
        if (!std::isfinite(out[i].x) || !std::isfinite(out[i].y))
            throw geo::InputError("texture coordinate " + std::to_string(i) + " is not finite");
    }
    return out;
}

// The vertex-per-pixel position image of an H x W x 3 array and an H x W mask.
passes::PositionImage to_position_image(const py::array_t<float, py::array::c_style | py::array::forcecast>& xyz,
                                        const py::array_t<bool, py::array::c_style | py::array::forcecast>& covered) {
    if (xyz.ndim() != 3 || xyz.shape(2) != 3) throw geo::InputError("image must be an H x W x 3 array");
    if (covered.ndim() != 2 || covered.shape(0) != xyz.shape(0) || covered.shape(1) != xyz.shape(1))
        throw geo::InputError("covered must be an H x W array matching the image");
    passes::PositionImage image(std::uint32_t(xyz.shape(1)), std::uint32_t(xyz.shape(0)));
    const auto x = xyz.unchecked<3>();
    const auto c = covered.unchecked<2>();
    for (std::uint32_t b = 0; b < image.height; ++b)
        for (std::uint32_t a = 0; a < image.width; ++a) {
            const std::size_t o = image.index(a, b);
            image.covered[o] = c(b, a) ? 1 : 0;
            for (int k = 0; k < 3; ++k) image.xyz[3 * o + std::size_t(k)] = x(b, a, k);
        }
    return image;
}

// A cylinder frame as a dict: rotation (3 x 3), translation, scale.
py::dict frame_dict(const passes::CylinderFrame& frame) {
    py::array_t<double> rotation({3, 3});
    auto r = rotation.mutable_unchecked<2>();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r(i, j) = frame.rotation[j][i];  // row i, column j
    py::dict f;
    f["rotation"] = rotation;
    f["translation"] = py::make_tuple(frame.translation.x, frame.translation.y, frame.translation.z);
    f["scale"] = frame.scale;
    return f;
}

// A cylindrical image and its frame as cylinder() returns them: (distance H x W, NaN where empty;
// mask; frame dict).
py::tuple cylinder_result(const passes::CylinderImage& image, const passes::CylinderFrame& frame) {
    const py::ssize_t height = image.height, width = image.width;
    py::array_t<float> distance({height, width});
    py::array_t<bool> mask({height, width});
    empty_as_nan(image.distance.data(), image.covered.data(), image.distance.size(), distance.mutable_data(),
                 mask.mutable_data());
    return py::make_tuple(distance, mask, frame_dict(frame));
}

// A list of (positions, faces) pairs as meshes, each checked as to_mesh checks one.
std::vector<geo::Mesh> to_meshes(const py::list& meshes) {
    std::vector<geo::Mesh> out;
    for (const py::handle item : meshes) {
        const auto pair = item.cast<py::tuple>();
        if (pair.size() != 2) throw geo::InputError("meshes: a list of (positions, faces) pairs");
        out.push_back(to_mesh(pair[0].cast<Positions>(), pair[1].cast<Faces>()));
    }
    return out;
}

}  // namespace gimg::python
