// Shared by the scan and reduction shaders and their C++ drivers (passes/primitives):
// each workgroup of 256 invocations handles 1024 consecutive elements, 4 per invocation.
#define GIMG_SCAN_THREADS 256
#define GIMG_SCAN_PER_THREAD 4
#define GIMG_SCAN_BLOCK (GIMG_SCAN_THREADS * GIMG_SCAN_PER_THREAD)
