// Shared by the mesh renderer's shaders and passes/render/render_mesh.cpp.
#define GIMG_COLOR_PLAIN 0u
#define GIMG_COLOR_NORMAL 1u
#define GIMG_COLOR_CHECKER 2u
#define GIMG_COLOR_SCALAR 3u
#define GIMG_COLOR_DIVERGING 4u

#define GIMG_RENDER_WIREFRAME 1u
#define GIMG_RENDER_HAS_TEXCOORDS 2u
#define GIMG_RENDER_SMOOTH 4u
