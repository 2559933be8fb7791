#version 460
// Gu's mass-centre normalisation: moves the points so that their area-weighted centre is the
// sphere's centre, y' = normalize(y - c), into a separate buffer; the host keeps the result only
// if it flipped nothing.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Points { double pos[]; };
layout(std430, binding = 1) readonly buffer Sums { double sums[]; };  // level_stats, reduced
layout(std430, binding = 2) writeonly buffer Moved { double moved[]; };
layout(push_constant) uniform Push {
    double total_area;
    uint vertex_count;
};

void main() {
    const uint v = gl_GlobalInvocationID.x;
    if (v >= vertex_count) return;
    const dvec3 centre = dvec3(sums[0], sums[1], sums[2]) / total_area;
    const dvec3 y = normalize(dvec3(pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]) - centre);
    moved[3 * v] = y.x;
    moved[3 * v + 1] = y.y;
    moved[3 * v + 2] = y.z;
}
