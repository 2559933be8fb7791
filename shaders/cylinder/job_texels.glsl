// The batch's jobs for compute passes, five RGBA32UI texels a job (CylinderJob's 80 bytes) in the
// image job_texels, which the includer declares: a gather per texel, where loading the struct
// from a storage buffer would make lavapipe load its 80 bytes lane by lane.
CylinderJob load_job(uint k) {
    CylinderJob job;
    for (uint r = 0; r < 3; ++r) job.rows[r] = uintBitsToFloat(imageLoad(job_texels, texel(5 * k + r)));
    const uvec4 faces = imageLoad(job_texels, texel(5 * k + 3)), tile = imageLoad(job_texels, texel(5 * k + 4));
    job.first_face = faces.x;
    job.face_count = faces.y;
    job.face_prefix = faces.z;
    job.vertex_offset = faces.w;
    job.tile_x = tile.x;
    job.tile_y = tile.y;
    job.pad0 = job.pad1 = 0;
    return job;
}

uint job_face_prefix(uint k) { return imageLoad(job_texels, texel(5 * k + 3)).z; }
// After the job_count jobs, four a texel: the job of face b * GIMG_CYL_JOB_BLOCK, for every block b.
uint job_of_block(uint b, uint job_count) { return imageLoad(job_texels, texel(5 * job_count + b / 4))[b % 4]; }
