#include "gimg/geometry/pca.h"

#include <Eigen/Eigenvalues>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace gimg::geo {

namespace {

// The samples' first three moments about their centroid, as one weighted list of either points
// (vertex weighting) or triangles (area weighting, integrated exactly).
class MomentSource {
public:
    MomentSource(const Mesh& mesh, PcaWeighting weighting) : mesh_(mesh), weighting_(weighting) {
        glm::dvec3 sum(0.0);
        if (weighting_ == PcaWeighting::SurfaceArea) {
            areas_.assign(mesh.face_count(), 0.0);
            for (std::size_t f = 0; f < mesh.face_count(); ++f) {
                const glm::uvec3& t = mesh.triangles[f];
                const glm::dvec3 &a = mesh.positions[t.x], &b = mesh.positions[t.y], &c = mesh.positions[t.z];
                areas_[f] = 0.5 * glm::length(glm::cross(b - a, c - a));
                total_weight_ += areas_[f];
                sum += areas_[f] * (a + b + c) / 3.0;
            }
        } else {
            total_weight_ = double(mesh.vertex_count());
            for (const glm::dvec3& p : mesh_.positions) sum += p;
        }
        centroid_ = sum / total_weight_;
    }

    double total_weight() const { return total_weight_; }
    glm::dvec3 centroid() const { return centroid_; }

    // E[(x - c)(x - c)^T]. Over a triangle with corners a, b, c (relative to the centroid):
    // E[x x^T] = (a a^T + b b^T + c c^T + s s^T) / 12 with s = a + b + c.
    Eigen::Matrix3d covariance(const glm::dvec3& center) const {
        double cov[3][3] = {};  // the upper triangle; mirrored at the end
        if (weighting_ == PcaWeighting::Vertices) {
            for (const glm::dvec3& p : mesh_.positions) {
                const glm::dvec3 d = p - center;
                for (int i = 0; i < 3; ++i)
                    for (int j = i; j < 3; ++j) cov[i][j] += d[i] * d[j];
            }
        } else {
            for (std::size_t f = 0; f < mesh_.face_count(); ++f) {
                const glm::uvec3& t = mesh_.triangles[f];
                const glm::dvec3 a = mesh_.positions[t.x] - center, b = mesh_.positions[t.y] - center,
                                 c = mesh_.positions[t.z] - center, s = a + b + c;
                const double w = areas_[f] / 12.0;
                for (int i = 0; i < 3; ++i)
                    for (int j = i; j < 3; ++j)
                        cov[i][j] += w * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j]);
            }
        }
        Eigen::Matrix3d out;
        for (int i = 0; i < 3; ++i)
            for (int j = i; j < 3; ++j) out(i, j) = out(j, i) = cov[i][j] / total_weight_;
        return out;
    }

    // E[((x - c) . axis)^3] for two axes. Over a triangle with projections p, q, r of its corners:
    // E[(l1 p + l2 q + l3 r)^3] = h3(p, q, r) / 10, h3 the sum of all ten cubic monomials
    // (moments of the uniform barycentric distribution, Dirichlet(1, 1, 1)).
    glm::dvec2 third_moments(const glm::dvec3& center, const glm::dvec3& first, const glm::dvec3& second) const {
        glm::dvec2 sum(0.0);
        const glm::dvec3 axes[2] = {first, second};
        if (weighting_ == PcaWeighting::Vertices) {
            for (const glm::dvec3& p : mesh_.positions)
                for (int k = 0; k < 2; ++k) {
                    const double d = glm::dot(p - center, axes[k]);
                    sum[k] += d * d * d;
                }
        } else {
            for (std::size_t f = 0; f < mesh_.face_count(); ++f) {
                const glm::uvec3& t = mesh_.triangles[f];
                const glm::dvec3 a = mesh_.positions[t.x] - center, b = mesh_.positions[t.y] - center,
                                 c = mesh_.positions[t.z] - center;
                for (int k = 0; k < 2; ++k) {
                    const double p = glm::dot(a, axes[k]), q = glm::dot(b, axes[k]), r = glm::dot(c, axes[k]);
                    const double h3 = p * p * p + q * q * q + r * r * r + p * p * (q + r) + q * q * (p + r) +
                                      r * r * (p + q) + p * q * r;
                    sum[k] += areas_[f] * h3 / 10.0;
                }
            }
        }
        return sum / total_weight_;
    }

private:
    const Mesh& mesh_;
    PcaWeighting weighting_;
    std::vector<double> areas_;
    double total_weight_ = 0.0;
    glm::dvec3 centroid_{0.0};
};

// Picks the sign of `axis` as documented in pca.h, from its third moment m3.
glm::dvec3 oriented(double m3, glm::dvec3 axis, double variance) {
    const double sigma = std::sqrt(std::max(variance, 0.0));
    if (std::abs(m3) > 1e-6 * sigma * sigma * sigma && sigma > 0.0) return m3 > 0.0 ? axis : -axis;
    int largest = 0;
    for (int i = 1; i < 3; ++i)
        if (std::abs(axis[i]) > std::abs(axis[largest])) largest = i;
    return axis[largest] < 0.0 ? -axis : axis;
}

}  // namespace

PcaAlignment compute_pca_alignment(const Mesh& mesh, PcaWeighting weighting) {
    PcaAlignment result;
    MomentSource source(mesh, weighting);
    if (!(source.total_weight() > 0.0)) {
        if (mesh.vertex_count() > 0) result.centroid = MomentSource(mesh, PcaWeighting::Vertices).centroid();
        result.transform.translation = -result.centroid;
        return result;
    }
    result.centroid = source.centroid();
    const Eigen::Matrix3d cov = source.covariance(result.centroid);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
    const Eigen::Vector3d values = solver.eigenvalues();  // ascending
    const Eigen::Matrix3d vectors = solver.eigenvectors();
    if (solver.info() != Eigen::Success || !(values[2] > 0.0)) {
        result.transform.translation = -result.centroid;
        return result;
    }
    auto column = [&](int i) { return glm::dvec3(vectors(0, i), vectors(1, i), vectors(2, i)); };
    glm::dvec3 main = glm::normalize(column(2));
    glm::dvec3 second = column(1);
    second = glm::normalize(second - glm::dot(second, main) * main);  // exact orthogonality
    const glm::dvec2 m3 = source.third_moments(result.centroid, main, second);
    main = oriented(m3[0], main, values[2]);
    second = oriented(m3[1], second, values[1]);
    // Eq. A.9: the third axis is the cross product of the second and the main axis, never an
    // independently signed eigenvector; with x = second, y = main this is z = x cross y, a proper
    // rotation. (Read literally, the paper's R = [v1, v2, v2 x v1] with v1 -> x, v2 -> y has
    // determinant -1 in a right-handed frame; its point is fixing the third axis by a cross
    // product, and putting the main axis on y, as its cylinder needs, makes that order right.)
    const glm::dvec3 third = glm::cross(second, main);

    result.main_axis = main;
    result.second_axis = second;
    result.third_axis = third;
    result.variances = glm::dvec3(values[2], values[1], values[0]);
    // Rows (second, main, third): rotation * p = (second . p, main . p, third . p).
    result.transform.rotation = glm::transpose(glm::dmat3(second, main, third));
    result.transform.translation = -(result.transform.rotation * result.centroid);
    return result;
}

}  // namespace gimg::geo
