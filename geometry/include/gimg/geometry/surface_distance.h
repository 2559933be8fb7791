#pragma once
// Metro-style distance between two triangle surfaces (DESIGN.md, "Metrics"): area-weighted
// stratified samples of one surface (surface_sampling.h; at least 10 per face or 1M, whichever
// is larger, fixed seed), each one's exact distance to the closest point of the other surface
// (TriangleBvh::closest_point: the nearest point anywhere on a face, never just the nearest
// vertex), summarised as mean, RMS and max.
//
// Definitions:
//  - one-sided A -> B: mean and RMS over A's area samples (each sample stands for an equal share
//    of A's area). max is the largest distance over the area samples *and A's vertices* (those
//    in at least one face): the farthest point of a triangle from a convex or smooth B is often a
//    corner, which a sample almost never hits. Vertices do not enter mean and RMS, which would
//    otherwise be biased towards finely tessellated regions.
//  - symmetric: mean and RMS over the union of both sample sets (sum of distances over all
//    samples of A and B divided by their total count, likewise for squares); max = the larger
//    of the two one-sided maxima (the Hausdorff distance).
//  - relative figures divide by the bounding-box diagonal of A (the reference).
// Results are bit-identical for any thread count: work is split into fixed chunks of faces whose
// partial sums are combined in chunk order.

#include "gimg/geometry/bvh.h"
#include "gimg/geometry/mesh.h"
#include "gimg/geometry/surface_sampling.h"

#include <cstddef>
#include <functional>

namespace gimg::geo {

struct DistanceStats {
    double mean = 0.0;
    double rms = 0.0;
    double max = 0.0;
    std::size_t samples = 0;  // area samples behind mean and rms

    DistanceStats scaled(double factor) const { return {mean * factor, rms * factor, max * factor, samples}; }
};

struct SurfaceDistance {
    DistanceStats a_to_b;
    DistanceStats b_to_a;
    DistanceStats symmetric;
    double bbox_diagonal = 0.0;  // of A

    // The figures above divided by bbox_diagonal (all zero when the diagonal is 0).
    DistanceStats relative(const DistanceStats& s) const {
        return s.scaled(bbox_diagonal > 0.0 ? 1.0 / bbox_diagonal : 0.0);
    }
};

struct SurfaceDistanceOptions {
    SurfaceSamplingOptions sampling;  // used for both directions
    unsigned threads = 0;             // 0: default_thread_count()
    // Called now and then with the share of the work done, in [0, 1], one call at a time (from
    // worker threads); surface_distance reports both directions as one.
    std::function<void(double done)> progress;
};

// One direction: samples of `from` against the surface held by `to`.
DistanceStats one_sided_distance(const Mesh& from, const TriangleBvh& to, const SurfaceDistanceOptions& options = {});

// Both directions and the symmetric figures. Throws InputError when either mesh has no face of
// positive area (there is no surface to sample or to measure against).
SurfaceDistance surface_distance(const Mesh& a, const Mesh& b, const SurfaceDistanceOptions& options = {});

}  // namespace gimg::geo
