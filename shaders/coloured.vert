#version 330 core
// Line segments and translucent quads: a position and a colour per vertex.
layout(location = 0) in vec3 position;
layout(location = 1) in vec4 colour;

uniform mat4 view_projection;
uniform float depth_bias;  // NDC units: pulls edges on a surface in front of it

out vec4 vertex_colour;

void main() {
    vertex_colour = colour;
    gl_Position = view_projection * vec4(position, 1.0);
    gl_Position.z -= depth_bias * gl_Position.w;
}
