#pragma once
// Replays a progressive mesh one vertex split at a time, keeping the faces around every vertex, so
// a solver can look at the one-rings of the two vertices each split touches.

#include "gimg/geometry/progressive_mesh.h"

#include <span>

namespace gimg::geo {

class ProgressiveReplay {
public:
    // Starts at the intermediate mesh of `active_count` vertices.
    ProgressiveReplay(const ProgressiveMesh& pm, std::size_t active_count);

    std::size_t active_count() const { return active_; }
    bool complete() const { return active_ == pm_.vertex_count; }

    // Applies the next split and returns it. Precondition: !complete().
    const VertexSplit& split_next();

    // Live faces around v (ids into triangles()).
    std::span<const std::uint32_t> faces_of(std::uint32_t v) const { return vfaces_[v]; }
    // Current corners of every face of the full mesh, indexed by face id; only the live ones mean
    // anything. Corner order is the input's.
    const std::vector<glm::uvec3>& triangles() const { return tri_; }
    // The live faces' corners, in face order (equals triangles_at(pm, active_count())).
    std::vector<glm::uvec3> live_triangles() const;

private:
    const ProgressiveMesh& pm_;
    std::size_t active_;
    std::vector<glm::uvec3> tri_;
    std::vector<std::uint8_t> alive_;
    std::vector<std::vector<std::uint32_t>> vfaces_;
};

}  // namespace gimg::geo
