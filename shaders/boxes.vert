#version 330 core
// Wireframe boxes, one instance per box: the 12 edges of the unit cube as 24
// line vertices (gl_VertexID), stretched to [box_lo, box_hi]. One draw call
// draws every box, so 100,000+ boxes stay one call.
layout(location = 0) in vec3 box_lo;
layout(location = 1) in vec3 box_hi;
layout(location = 2) in vec4 box_colour;

uniform mat4 view_projection;
uniform float depth_bias;  // NDC units: pulls edges on a surface in front of it

out vec4 vertex_colour;

// Corner index (bit 0: x, bit 1: y, bit 2: z) of each edge end point.
const int kEdgeCorners[24] = int[24](0, 1, 2, 3, 4, 5, 6, 7,   // edges along x
                                     0, 2, 1, 3, 4, 6, 5, 7,   // edges along y
                                     0, 4, 1, 5, 2, 6, 3, 7);  // edges along z

void main() {
    int corner = kEdgeCorners[gl_VertexID];
    vec3 pick = vec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
    vec3 position = mix(box_lo, box_hi, pick);
    vertex_colour = box_colour;
    gl_Position = view_projection * vec4(position, 1.0);
    gl_Position.z -= depth_bias * gl_Position.w;
}
