// Shared by the cylindrical Z-buffer shaders and passes/cylinder/zbuffer.cpp.
// Pixel (u, v) of a W x H image sees theta_u = 2 pi (u + 0.5) / W and y_v = 1 - (v + 0.5) / H.
#define GIMG_CYL_EMPTY (-4.0)          // colour of pixels no triangle covers (d is in [-1, 1])
#define GIMG_CYL_RECTS_PER_FACE 4u     // two pieces (front, back) x two seam copies
#define GIMG_CYL_CLASSIFY_GROUP 64u
#define GIMG_CYL_JOB_BLOCK 256u        // faces a block of the job table (classify_body.glsl job_of)
#define GIMG_CYL_LARGE_GROUP 64u       // lanes sharing one large piece's pixels
#define GIMG_CYL_MAX_GROUPS 65535u     // workgroups of one indirect dispatch (maxComputeWorkGroupCount)
