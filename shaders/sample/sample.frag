#version 460
layout(location = 0) noperspective in vec3 position;
layout(location = 0) out vec4 color;  // xyz, and 1 for covered
void main() { color = vec4(position, 1.0); }
