// Fitting a model into the unit cylinder (the cylindrical-projection thesis, 2.5.1): PCA alignment, then one uniform scale
// and a translation. One scale for all axes keeps the shape, so distances and facing stay true.
#include "gimg/passes/cylinder.h"

#include "gimg/geometry/error.h"
#include "gimg/geometry/pca.h"

#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>

namespace gimg::passes {

namespace {
constexpr double kMargin = 0.999;  // no point exactly on the wall, where t = 1 would be a tie
}

glm::dvec3 CylinderFrame::to_model(const glm::dvec3& q) const {
    return glm::transpose(rotation) * ((q - translation) / scale);
}

CylinderFrame fit_cylinder_frame(const geo::Mesh& mesh, bool align) {
    if (mesh.positions.empty()) throw geo::InputError("cannot fit an empty mesh into the cylinder");
    // Only vertices some face uses count: a stray point far away must not shrink the model.
    std::vector<std::uint8_t> used(mesh.vertex_count(), mesh.triangles.empty() ? 1 : 0);
    for (const glm::uvec3& t : mesh.triangles) used[t.x] = used[t.y] = used[t.z] = 1;
    CylinderFrame frame;
    glm::dvec3 centre{0.0};
    if (align) {
        geo::Mesh faces_only;  // the paper's vertex-weighted PCA, over the vertices faces use
        if (std::find(used.begin(), used.end(), 0) != used.end()) {
            std::vector<std::uint32_t> index(used.size(), 0);
            for (std::size_t i = 0; i < used.size(); ++i)
                if (used[i])
                    index[i] = std::uint32_t(faces_only.positions.size()),
                    faces_only.positions.push_back(mesh.positions[i]);
            for (const glm::uvec3& t : mesh.triangles)
                faces_only.triangles.push_back({index[t.x], index[t.y], index[t.z]});
        }
        const geo::PcaAlignment pca = geo::compute_pca_alignment(faces_only.positions.empty() ? mesh : faces_only);
        frame.rotation = pca.transform.rotation;
        centre = pca.centroid;
    } else {
        std::size_t n = 0;
        for (std::size_t i = 0; i < used.size(); ++i)
            if (used[i]) centre += mesh.positions[i], ++n;
        centre /= double(n);
    }
    // In the rotated frame, around the centroid: the axis goes through the centroid.
    double r2_max = 0.0, y_min = 1e300, y_max = -1e300;
    for (std::size_t i = 0; i < used.size(); ++i) {
        if (!used[i]) continue;
        const glm::dvec3 q = frame.rotation * (mesh.positions[i] - centre);
        r2_max = std::max(r2_max, q.x * q.x + q.z * q.z);  // one square root at the end, not one a vertex
        y_min = std::min(y_min, q.y);
        y_max = std::max(y_max, q.y);
    }
    const double extent = std::max(std::sqrt(r2_max), y_max - y_min);
    if (!(extent > 0.0) || !std::isfinite(extent))
        throw geo::InputError("the mesh has no extent to fit into the cylinder");
    frame.scale = kMargin / extent;
    // p_cyl = s R (p - c) + (0, y0, 0) with the model centred in height.
    const double y0 = 0.5 - frame.scale * 0.5 * (y_min + y_max);
    frame.translation = glm::dvec3(0.0, y0, 0.0) - frame.scale * (frame.rotation * centre);
    return frame;
}

CylinderMesh make_cylinder_mesh(const geo::Mesh& mesh, const CylinderFrame& frame) {
    CylinderMesh out;
    out.positions.reserve(3 * mesh.positions.size());
    for (const auto& p : mesh.positions) {
        const glm::dvec3 q = frame.to_cylinder(p);
        out.positions.insert(out.positions.end(), {float(q.x), float(q.y), float(q.z)});
    }
    out.triangles.reserve(3 * mesh.triangles.size());
    for (const auto& t : mesh.triangles) out.triangles.insert(out.triangles.end(), {t.x, t.y, t.z});
    return out;
}

CylinderTransform to_cylinder_transform(const glm::dmat4& m) {
    CylinderTransform t{};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) t[4 * r + c] = float(m[c][r]);
    return t;
}

std::array<std::uint32_t, 2> auto_cylinder_size(std::size_t faces) {
    // 2 W H = 2 (2H) H = 4 H^2 = faces.
    const auto h = std::uint32_t(std::max(1.0, std::round(std::sqrt(double(faces) / 4.0))));
    return {2 * h, h};
}

}  // namespace gimg::passes
