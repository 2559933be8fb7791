// One image of a batch: which faces, which transform into the cylinder frame, which tile.
// std430 layout, mirrored by CylinderJobGpu in passes/cylinder/zbuffer.cpp.
struct CylinderJob {
    vec4 rows[3];        // model -> cylinder frame, row-major 3x4 (rotation * scale | translation)
    uint first_face;     // into the batch's triangle list
    uint face_count;
    uint face_prefix;    // faces of all earlier jobs (the classify thread -> job map)
    uint vertex_offset;  // added to the triangle's indices
    uint tile_x;         // pixel origin of this image in the atlas
    uint tile_y;
    uint pad0, pad1;
};

vec3 to_cylinder(const CylinderJob job, vec3 p) {
    const vec4 h = vec4(p, 1.0);
    return vec3(dot(job.rows[0], h), dot(job.rows[1], h), dot(job.rows[2], h));
}
