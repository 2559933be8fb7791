// Interactive editing of a quad region: re-cut, warm-started re-map and re-deform per corner move;
// only the deformation per offset change, from basis values kept per map.
#include "gimg/geometry/error.h"
#include "gimg/passes/quad_region.h"
#include "lattice_weights.h"

#include <limits>
#include <memory>

namespace gimg::passes {

QuadRegionEditor::QuadRegionEditor(Context* ctx, geo::Mesh mesh, const std::array<std::uint32_t, 4>& corners,
                                   QuadMapOptions options)
    : ctx_(ctx), mesh_(std::move(mesh)), cutter_(mesh_), corners_(corners), options_(options), deformed_(mesh_) {
    lattice_.offsets.assign(std::size_t(lattice_.columns) * lattice_.rows, glm::dvec3(0.0));
    remap({});
}

void QuadRegionEditor::remap(const std::vector<glm::dvec2>& previous_by_vertex) {
    QuadRegion region = cutter_.cut(corners_, false);  // no picture here: the outside mesh is not needed
    std::vector<glm::dvec2> warm;
    if (!previous_by_vertex.empty()) {
        warm.assign(region.mesh.vertex_count(), glm::dvec2(std::numeric_limits<double>::quiet_NaN()));
        for (std::size_t i = 0; i < warm.size(); ++i)
            if (region.original[i] != kInsertedNode) warm[i] = previous_by_vertex[region.original[i]];
    }
    QuadMap map = map_quad_region(ctx_, region, options_, warm);
    auto weights = std::make_shared<const LatticeWeights>(lattice_, map.uv);
    map_ = std::move(map);
    region_ = std::move(region);
    weights_ = std::move(weights);
    deform();
}

// deform_by_lattice(mesh_, region_, map_.uv, lattice_), the basis values taken from weights_.
void QuadRegionEditor::deform() {
    deformed_.positions = mesh_.positions;
    for (std::size_t i = 0; i < map_.uv.size(); ++i)
        if (region_.original[i] != kInsertedNode)
            deformed_.positions[region_.original[i]] += weights_->offset(i, lattice_);
}

const geo::Mesh& QuadRegionEditor::move_corner(int i, std::uint32_t vertex) {
    if (i < 0 || i > 3) throw geo::InputError("a quad region has corners 0 to 3, not " + std::to_string(i));
    // The last map's correction to its own accelerated start, per original vertex.
    std::vector<glm::dvec2> previous(mesh_.vertex_count(), glm::dvec2(std::numeric_limits<double>::quiet_NaN()));
    for (std::size_t k = 0; k < map_.uv.size(); ++k)
        if (region_.original[k] != kInsertedNode) previous[region_.original[k]] = map_.uv[k] - map_.accelerated[k];
    const std::array<std::uint32_t, 4> before = corners_;
    corners_[std::size_t(i)] = vertex;
    try {
        remap(previous);
    } catch (...) {
        corners_ = before;  // a refused corner leaves the editor as it was
        throw;
    }
    return deformed_;
}

const geo::Mesh& QuadRegionEditor::set_lattice(const OffsetLattice& lattice) {
    lattice.evaluate({0.5, 0.5});  // the lattice's own checks, before anything changes
    if (!weights_->fits(lattice)) weights_ = std::make_shared<const LatticeWeights>(lattice, map_.uv);
    lattice_ = lattice;
    deform();
    return deformed_;
}

}  // namespace gimg::passes
