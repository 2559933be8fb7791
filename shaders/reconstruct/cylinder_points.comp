#version 460
// Reconstruction, step 1 for cylindrical images: a pixel's point (d cos theta_u, y_v, d sin theta_u)
// in the cylinder frame, carried back to the model: R^T (p - t) / s, in double, then float.
#extension GL_GOOGLE_include_directive : require
#include "reconstruct/reconstruct_common.h"

layout(local_size_x = GIMG_RECON_GROUP, local_size_y = GIMG_RECON_GROUP) in;
layout(std430, binding = 0) readonly buffer Distance { float d[]; };
layout(std430, binding = 1) readonly buffer Directions { dvec2 dirs[]; };
layout(std430, binding = 2) readonly buffer Frame { double frame[16]; };  // R rows, t, s
layout(std430, binding = 3) writeonly buffer Points { vec4 points[]; };
layout(std430, binding = 4) writeonly buffer Valid { uint valid[]; };
layout(push_constant) uniform Push { uint width; uint height; };

void main() {
    const uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= width || p.y >= height) return;
    const uint i = p.y * width + p.x;
    const float dv = d[i];
    if (isnan(dv)) {
        points[i] = vec4(0.0);
        valid[i] = 0u;
        return;
    }
    const double y = 1.0LF - (double(p.y) + 0.5LF) / double(height);
    const dvec2 cs = dirs[p.x];
    const double q0 = double(dv) * cs.x - frame[9], q1 = y - frame[10], q2 = double(dv) * cs.y - frame[11];
    // frame[3 r + c] is R[r][c]; R^T q sums down the columns.
    const double x = frame[0] * q0 + frame[3] * q1 + frame[6] * q2;
    const double yy = frame[1] * q0 + frame[4] * q1 + frame[7] * q2;
    const double z = frame[2] * q0 + frame[5] * q1 + frame[8] * q2;
    points[i] = vec4(float(x / frame[12]), float(yy / frame[12]), float(z / frame[12]), 1.0);
    valid[i] = 1u;
}
