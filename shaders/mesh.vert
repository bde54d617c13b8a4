#version 330 core
// The scene mesh: positions only; the fragment shader finds the face normal.
layout(location = 0) in vec3 position;

uniform mat4 view_projection;

out vec3 world_position;

void main() {
    world_position = position;
    gl_Position = view_projection * vec4(position, 1.0);
}
