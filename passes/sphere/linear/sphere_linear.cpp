// `linear`: Choi, Lam & Lui's fast spherical conformal map of a closed genus-0 mesh (FLASH), three
// sparse direct solves' worth of work instead of thousands of gradient steps.
//
//   1. North pole: take out the most regular triangle; harmonic (cotangent) map of the remaining
//      disk into the plane with that triangle's corners pinned to a flat copy of it.
//   2. Inverse stereographic projection onto the sphere, after scaling the plane so that the
//      triangles at the two poles come out the same size. The big triangle lands at the north
//      pole; the harmonic map is accurate far from it (around the south pole) and distorted near
//      it, where the pinned boundary forced its shape.
//   3. South pole: project from the south pole instead, so the distorted region is now in the
//      middle of the plane. Pin the tenth of the vertices nearest the south pole (the accurate
//      part) and recompute the rest with the linear Beltrami solver, using the Beltrami
//      coefficient of the planar layout against the mesh, which cancels its distortion.
//      Project back.
//
// Not guaranteed one-to-one: obtuse triangles make cotangent weights negative and long
// protrusions squeeze into tiny regions, so flips are counted and reported, never hidden.
#include "sphere/linear/beltrami.h"
#include "sphere/linear/plane_harmonic_map.h"
#include "sphere/linear/stereographic.h"

#include "gimg/geometry/adjacency.h"
#include "gimg/geometry/cotangent.h"
#include "gimg/passes/sphere.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <string>

namespace gimg::passes {

namespace {

using linear_sphere::Complex;

class Stopwatch {
public:
    double lap() {
        const auto now = std::chrono::steady_clock::now();
        const double s = std::chrono::duration<double>(now - last_).count();
        last_ = now;
        return s;
    }

private:
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

// The paper's conformal energy of a sphere map: sum over edges of w_uv |y(u) - y(v)|^2.
double conformal_energy(const geo::MeshAdjacency& adj, const std::vector<double>& cot,
                        const std::vector<glm::dvec3>& y) {
    double energy = 0.0;
    for (std::size_t e = 0; e < adj.edge_count(); ++e) {
        const glm::dvec3 d = y[adj.edges[2 * e]] - y[adj.edges[2 * e + 1]];
        energy += cot[e] * glm::dot(d, d);
    }
    return energy;
}

void add_note(SphereResult& result, const std::string& text) {
    if (!result.note.empty()) result.note += "; ";
    result.note += text;
}

// The `count` vertices nearest the south pole (smallest z).
std::vector<std::uint8_t> nearest_south_pole(const std::vector<glm::dvec3>& sphere, std::size_t count) {
    std::vector<std::uint32_t> order(sphere.size());
    std::iota(order.begin(), order.end(), 0u);
    count = std::min(count, order.size());
    std::nth_element(order.begin(), order.begin() + std::ptrdiff_t(count) - 1, order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return sphere[a].z < sphere[b].z; });
    std::vector<std::uint8_t> pinned(sphere.size(), 0);
    for (std::size_t i = 0; i < count; ++i) pinned[order[i]] = 1;
    return pinned;
}

}  // namespace

SphereResult sphere_linear(const geo::Mesh& mesh) {
    check_sphere_input(mesh);
    const std::size_t n = mesh.vertex_count();
    SphereResult result;
    Stopwatch clock;

    // 1. North pole: harmonic map of the mesh minus the big triangle into the plane.
    const geo::MeshAdjacency adj = geo::build_adjacency(mesh);
    const std::vector<double> cot = geo::cotangent_weights(mesh, adj);
    const std::uint32_t big = linear_sphere::most_regular_face(mesh);
    std::vector<double> weights = cot;
    linear_sphere::DirichletSolution plane = linear_sphere::harmonic_map_to_plane(mesh, adj, weights, big);
    if (!plane.ok) {
        // Uniform weights make it a Tutte embedding, one-to-one in the plane whatever the angles:
        // a usable start for step 3, but no longer the paper's map.
        result.converged = false;
        add_note(result, "cotangent harmonic map failed (" + plane.why + "); used Tutte (uniform) weights instead");
        weights.assign(adj.edge_count(), 1.0);
        plane = linear_sphere::harmonic_map_to_plane(mesh, adj, weights, big);
        if (!plane.ok) {
            add_note(result, "Tutte map failed too (" + plane.why + ")");
            result.positions.assign(n, glm::dvec3(std::nan("")));
            return result;
        }
    }
    result.stages.push_back({"north pole: harmonic map to the plane", n - 3, 0, clock.lap(),
                             linear_sphere::dirichlet_energy(adj, weights, plane.z)});

    // 2. Balanced inverse stereographic projection: the plane's origin goes to the south pole.
    const double scale = linear_sphere::balancing_scale(mesh, plane.z, big);
    std::vector<glm::dvec3> sphere(n);
    for (std::size_t v = 0; v < n; ++v) sphere[v] = linear_sphere::sphere_from_south_chart(scale * plane.z[v]);
    result.stages.push_back(
        {"inverse stereographic projection (balanced)", n, 0, clock.lap(), conformal_energy(adj, cot, sphere)});

    // 3. South pole: Beltrami correction around the big triangle in the chart centred on it.
    // Projecting the sphere points from the south pole gives q = 1 / w exactly; taking that
    // directly keeps the precision that 1 + z loses near the south pole.
    std::vector<Complex> q(n);
    for (std::size_t v = 0; v < n; ++v) q[v] = linear_sphere::north_from_south_chart(scale * plane.z[v]);
    // A tenth of the vertices pinned, as in the paper's code; if the solve breaks down, five times
    // as many (a larger accurate region to lean on), then give up and keep step 2's map.
    std::size_t pin_count = std::max<std::size_t>((n + 5) / 10, 3);
    linear_sphere::DirichletSolution corrected;
    std::vector<std::uint8_t> pinned;
    for (int attempt = 0; attempt < 2 && !corrected.ok; ++attempt, pin_count *= 5) {
        pinned = nearest_south_pole(sphere, pin_count);
        std::vector<std::uint8_t> needed(mesh.face_count(), 0);
        for (std::size_t f = 0; f < mesh.face_count(); ++f) {
            const glm::uvec3 t = mesh.triangles[f];
            needed[f] = !(pinned[t.x] && pinned[t.y] && pinned[t.z]);
        }
        const std::vector<Complex> mu = linear_sphere::beltrami_coefficients(mesh, q, needed);
        corrected = linear_sphere::linear_beltrami_solve(mesh, q, mu, pinned, q);
        if (!corrected.ok)
            add_note(result,
                     "Beltrami solve with " + std::to_string(pin_count) + " pinned vertices failed: " + corrected.why);
    }
    std::size_t free_count = 0;
    if (corrected.ok) {
        for (std::size_t v = 0; v < n; ++v) {
            if (pinned[v]) continue;  // keeps its step-2 point exactly (also when q is infinite there)
            sphere[v] = glm::normalize(linear_sphere::sphere_from_north_chart(corrected.z[v]));
            ++free_count;
        }
    } else {
        result.converged = false;
        add_note(result, "kept the uncorrected projection");
    }
    result.stages.push_back(
        {"south pole: linear Beltrami correction", free_count, 0, clock.lap(), conformal_energy(adj, cot, sphere)});

    result.positions = std::move(sphere);
    // A NaN point would not even count as a flip (every comparison with it is false): say so.
    const auto nonfinite = std::count_if(result.positions.begin(), result.positions.end(), [](const glm::dvec3& p) {
        return !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z);
    });
    if (nonfinite) {
        result.converged = false;
        add_note(result, std::to_string(nonfinite) + " vertices have NaN or infinite sphere points");
    }
    const SphereMetrics metrics = sphere_metrics(mesh, result.positions);
    if (metrics.flips)
        add_note(result, std::to_string(metrics.flips) + " of " + std::to_string(mesh.face_count()) +
                             " faces flipped (the linear method does not guarantee a one-to-one map)");
    return result;
}

}  // namespace gimg::passes
