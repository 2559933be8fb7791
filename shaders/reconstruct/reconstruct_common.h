// Shared by the reconstruction shaders: the grid rules of passes/reconstruct/reconstruct_rules.h,
// operation for operation. Points are vec4 (xyz, w = 1 valid / 0 empty); empty pixels of the
// input images are NaN.
#define GIMG_RECON_GROUP 16u

// Block (u, v) of a W x H grid: corners a, b, c, d at (u, v), (u+1, v), (u, v+1), (u+1, v+1),
// u + 1 wrapping when the image wraps (cylindrical).
void block_corners(uint u, uint v, uint width, out uint c[4]) {
    const uint u1 = (u + 1u) % width;
    c[0] = v * width + u;
    c[1] = v * width + u1;
    c[2] = (v + 1u) * width + u;
    c[3] = (v + 1u) * width + u1;
}

// Exact in double for float inputs: differences of floats and sums of three of their squares.
double squared_distance(vec4 a, vec4 b) {
    const double x = double(a.x) - double(b.x), y = double(a.y) - double(b.y), z = double(a.z) - double(b.z);
    return x * x + y * y + z * z;
}
