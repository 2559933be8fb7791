// glm's double-precision cross, dot and length term for term, `precise` so that no multiply-add
// is fused: shaders that must give the CPU's results bit for bit use these.
#ifndef GIMG_DOUBLE_CPU_GLSL
#define GIMG_DOUBLE_CPU_GLSL

dvec3 cross_cpu(dvec3 x, dvec3 y) {  // glm::cross
    precise dvec3 r = dvec3(x.y * y.z - y.y * x.z, x.z * y.x - y.z * x.x, x.x * y.y - y.x * x.y);
    return r;
}

double dot_cpu(dvec3 x, dvec3 y) {  // glm::dot: (x.x y.x + x.y y.y) + x.z y.z
    precise double r = (x.x * y.x + x.y * y.y) + x.z * y.z;
    return r;
}

double length_cpu(dvec3 x) { return sqrt(dot_cpu(x, x)); }  // glm::length

#endif
