#pragma once
// What `gimg gim` and `gimg bench gim` report of a parameterization geometry image: the error of its
// reconstruction against the original, and the picture of the parameter domain.

#include "gimg/engine/context.h"
#include "gimg/geometry/image.h"
#include "gimg/geometry/mesh.h"
#include "gimg/geometry/surface_distance.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <vector>

namespace gimg::cli {

struct GimError {
    geo::SurfaceDistance distance;
    double rms = 0.0;        // the larger one-sided RMS, relative to the original's diagonal
    double hausdorff = 0.0;  // relative to the original's diagonal
    double psnr = 0.0;       // 20 log10(1 / rms)
};

GimError gim_error(const geo::Mesh& original, const geo::Mesh& reconstruction,
                   const geo::SurfaceDistanceOptions& options = {});
nlohmann::json gim_error_json(const GimError& e);

// The parameter domain drawn as a mesh with its edges, each vertex coloured by its sampling density
// log2((A_2D / A_3D) / mean), from -3 (blue: sampled sparsely) to +3 (red: densely).
geo::RgbaImage parameter_picture(Context& ctx, const geo::Mesh& mesh, const std::vector<glm::dvec2>& uv,
                                 std::uint32_t size);

}  // namespace gimg::cli
