#version 330 core
// Wireframe boxes, one instance per box: the 8 corners of the unit cube
// (gl_VertexID = corner, bit 0: x, bit 1: y, bit 2: z), stretched to
// [box_lo, box_hi]; an index list of 24 (the 12 edges) joins them. One draw
// call draws every box, and each corner is transformed once, not once per edge
// (a software rasterizer such as llvmpipe is bound by vertex work here).
layout(location = 0) in vec3 box_lo;
layout(location = 1) in vec3 box_hi;
layout(location = 2) in vec4 box_colour;

uniform mat4 view_projection;
uniform float depth_bias;  // NDC units: pulls edges on a surface in front of it

out vec4 vertex_colour;

void main() {
    int corner = gl_VertexID;
    vec3 pick = vec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
    vec3 position = mix(box_lo, box_hi, pick);
    vertex_colour = box_colour;
    gl_Position = view_projection * vec4(position, 1.0);
    gl_Position.z -= depth_bias * gl_Position.w;
}
