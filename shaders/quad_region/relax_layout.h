// Shared by shaders/quad_region/relax.comp and passes/quad_region/relaxation.h.
#ifndef GIMG_RELAX_LAYOUT_H
#define GIMG_RELAX_LAYOUT_H
#define GIMG_RELAX_GROUP 256   // invocations per field's workgroup
#define GIMG_RELAX_SWEEPS 8    // sweeps per dispatch, and per application of the stopping rule
#define GIMG_RELAX_DISPATCHES 4  // dispatches per submission
#endif
