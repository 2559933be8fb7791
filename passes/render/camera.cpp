#include "gimg/passes/render.h"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace gimg::passes {

namespace {
constexpr double kMargin = 0.92;  // the model fills at most this share of the frame
}

Camera fit_camera(const std::vector<glm::dvec3>& points, const View& view, double aspect) {
    geo::Bounds bounds;
    if (!points.empty()) {
        bounds = {points.front(), points.front()};
        for (const auto& p : points) bounds.min = glm::min(bounds.min, p), bounds.max = glm::max(bounds.max, p);
    }
    const glm::dvec3 center = 0.5 * (bounds.min + bounds.max);
    const double radius = std::max(0.5 * bounds.diagonal(), 1e-9);
    const double az = glm::radians(view.azimuth_deg), el = glm::radians(view.elevation_deg);
    const glm::dvec3 back{std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el)};
    const glm::dvec3 world_up = std::abs(back.y) > 0.999 ? glm::dvec3(0.0, 0.0, -1.0) : glm::dvec3(0.0, 1.0, 0.0);
    const glm::dvec3 right = glm::normalize(glm::cross(world_up, back));
    const glm::dvec3 up = glm::cross(back, right);
    const double tan_y = std::tan(0.5 * glm::radians(view.fov_deg)) * kMargin;
    const double tan_x = tan_y * aspect;
    // Each point at depth z (towards the camera) and offsets x, y from the axis is in frame when
    // the camera stands at distance >= z + |x| / tan_x and >= z + |y| / tan_y.
    double distance = 0.0;
    for (const auto& p : points) {
        const glm::dvec3 d = p - center;
        const double z = glm::dot(d, back);
        distance =
            std::max({distance, z + std::abs(glm::dot(d, right)) / tan_x, z + std::abs(glm::dot(d, up)) / tan_y});
    }
    distance = std::max(distance, 1e-3 * radius + radius);
    Camera c;
    c.target = center;
    c.eye = center + distance * back;
    c.fov_y_deg = view.fov_deg;
    c.near_plane = std::max(distance - 1.1 * radius, 1e-3 * distance);
    c.far_plane = distance + 1.1 * radius;
    return c;
}

glm::mat4 Camera::view_projection(double aspect) const {
    const glm::dvec3 forward = glm::normalize(target - eye);
    // Looking straight up or down: "up" must not be parallel to the view direction.
    const glm::dvec3 up = std::abs(forward.y) > 0.999 ? glm::dvec3(0.0, 0.0, -1.0) : glm::dvec3(0.0, 1.0, 0.0);
    glm::dmat4 view = glm::lookAtRH(eye, target, up);
    glm::dmat4 projection = glm::perspectiveRH_ZO(glm::radians(fov_y_deg), aspect, near_plane, far_plane);
    projection[1][1] *= -1.0;  // Vulkan's clip space has y pointing down
    return glm::mat4(projection * view);
}

}  // namespace gimg::passes
