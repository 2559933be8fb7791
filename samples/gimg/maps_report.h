#pragma once
// What `gimg maps` and `gimg bench maps` compute after the remesh: the wavelet decomposition, the
// one-level-down and compressed meshes, the errors against the original, the pictures and the
// wavelets.bin file (its format in docs/maps.md).

#include "progress_line.h"

#include "gimg/engine/context.h"
#include "gimg/geometry/mesh.h"
#include "gimg/geometry/surface_distance.h"
#include "gimg/passes/maps.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace gimg::cli {

// "lazy" -> -1, "0".."2" -> k.
int parse_wavelet_k(const std::string& text);

struct MapsWavelets {
    int k = 1;
    bool on_gpu = false;                   // false also when the remesh exceeds one device binding
    std::vector<glm::dvec3> coefficients;  // c^0 and every level's details (maps.h)
    geo::Mesh coarse;                      // c^{J-1} on level J-1's connectivity (fig. 11f)
    geo::Mesh compressed;                  // level J from the kept details (with a fraction > 0)
    std::size_t kept = 0, details = 0;
    double reconstruction_error = 0.0;  // max |synthesis(analysis(x)) - x| / diagonal
    double filter_seconds = 0.0, analysis_seconds = 0.0, synthesis_seconds = 0.0;
};

// Wavelets of the remesh on the GPU (ctx) or the CPU twin (nullptr); `fraction` > 0 also builds
// the compressed mesh from that share of the details.
MapsWavelets maps_wavelets(Context* ctx, const passes::SemiRegularMesh& remesh, int k, double fraction);

struct MapsErrors {
    std::vector<geo::SurfaceDistance> levels;  // remesh level j = 1..J against the original
    geo::SurfaceDistance coarse, compressed;
};
MapsErrors maps_errors(const geo::Mesh& mesh, const passes::MapsRemesh& r, const MapsWavelets& w,
                       const geo::SurfaceDistanceOptions& options, ProgressLine* line);

void write_wavelets(const passes::SemiRegularMesh& remesh, int k, const std::vector<glm::dvec3>& coefficients,
                    const std::filesystem::path& path);

// base.png: the original coloured by base triangle beside the base domain; remesh.png: the remesh
// levels 1..J and the one-level-down mesh, with their edges (those of at most a million faces).
void write_maps_pictures(Context& ctx, const geo::Mesh& mesh, const passes::MapsRemesh& r, const MapsWavelets& w,
                         std::uint32_t panel, const std::filesystem::path& dir);

void print_maps_report(const geo::Mesh& mesh, const passes::MapsRemesh& r, const MapsWavelets& w, const MapsErrors& e);
nlohmann::json maps_json(const geo::Mesh& mesh, const passes::MapsRemesh& r, const MapsWavelets& w,
                         const MapsErrors& e);

}  // namespace gimg::cli
