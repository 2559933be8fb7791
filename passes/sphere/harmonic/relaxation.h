#pragma once
// The relaxation of one hierarchy level as iterative compute dispatches (GpuRelaxation),
// and the same steps on the CPU (relax_and_check_cpu), which tests compare it with.
//
// One call runs `iterations` sweeps (one dispatch per colour each), then reduces the level's
// energy, flip count and mass centre on the GPU, moves the mass centre towards the origin by a
// Moebius transformation into a second image and reduces again. Only the two small sums come
// back to the host, once per call: the caller reads them every K iterations, never every
// iteration. The recentred points are kept when no more triangles are flipped or fail the kernel
// test than before; otherwise the next call tries half the move.
#include "sphere/harmonic/relaxation_mesh.h"

#include "gimg/engine/context.h"
#include "gimg/engine/plan.h"

#include <glm/geometric.hpp>

#include <map>
#include <memory>
#include <tuple>

namespace gimg::passes::detail {

struct RelaxCheck {
    MapStats relaxed;    // after the sweeps
    MapStats recentred;  // after the Moebius move of the mass centre
    bool recentre_kept = false;
};

// The first Moebius move is a = 3/4 c: to first order the one that centres evenly spread points.
inline constexpr double kRecentreScale = 0.75;

// The a of one recentring step from the mass centre c: scale c, at most 1/2 long (big drifts go in
// several steps). shaders/sphere/recentre.comp computes the same.
inline glm::dvec3 recentring_point(const glm::dvec3& c, double scale) {
    glm::dvec3 a = scale * c;
    if (glm::length(a) > 0.5) a *= 0.5 / glm::length(a);
    return a;
}

struct CentreRun {
    std::size_t steps = 0;  // Moebius steps made
    bool kept = true;       // false: they would have flipped triangles, and y is unchanged
    MapStats stats;         // of y as it is now
};

// The recentring step repeated on the CPU, points only, until the mass centre is within
// `tolerance` of the origin or `max_steps` are made. The steps compose to one Moebius
// transformation, which flips a triangle or not whatever the path, so flips are judged once at
// the end: kept when no more triangles are flipped or fail the kernel test than before. The
// relaxation's checks make one step each and judge each with a fan pass; from a map crowded to
// one side (the planar polish's: mass centre 0.91 from the origin on armadillo_loop1) they need
// about 20 checks.
// `now` is map_stats_cpu(level, y), which the caller has at hand.
CentreRun centre_mass_cpu(const RelaxationMesh& level, std::vector<glm::dvec3>& y, const MapStats& now,
                          double tolerance = 1e-6, std::size_t max_steps = 64);

RelaxCheck relax_and_check_cpu(const RelaxationMesh& level, std::vector<glm::dvec3>& y, std::uint32_t iterations,
                               bool uniform_weights, double recentre_scale = kRecentreScale);

class GpuRelaxation {
public:
    GpuRelaxation(Context& ctx, const RelaxationMesh& level, const std::vector<glm::dvec3>& y);
    RelaxCheck run(std::uint32_t iterations, bool uniform_weights);
    std::vector<glm::dvec3> positions();
    // GPU time of the last run, when timestamps are on (0 otherwise).
    double last_gpu_ms() const { return last_gpu_ms_; }
    void set_timestamps(bool on) { timestamps_ = on; }

private:
    Plan& plan_for(std::uint32_t iterations, bool uniform_weights);

    Context& ctx_;
    const RelaxationMesh& level_;
    Image points_[2], ring_offsets_, spokes_, members_;  // shaders/sphere/sphere_common.glsl's layouts
    Buffer sums_relaxed_, sums_recentred_, control_;
    double recentre_scale_ = kRecentreScale;
    int current_ = 0;  // which points_ image holds the points
    bool timestamps_ = false;
    double last_gpu_ms_ = 0.0;
    std::map<std::tuple<std::uint32_t, bool, int>, std::unique_ptr<Plan>> plans_;
};

}  // namespace gimg::passes::detail
