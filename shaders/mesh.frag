#version 330 core
// Headlight shading, the same formula as the CPU renderers (core/render/shading.h):
// a light at the eye, brightness 0.15 + 0.85 |cos(normal, view ray)|, so back
// faces are lit too. The geometric normal comes from the screen-space
// derivatives of the position: exact for a flat triangle, no normals needed.
in vec3 world_position;

uniform vec3 eye;
uniform vec3 base_colour;  // (225, 205, 170) / 255 in the CPU renderers
uniform float opacity;

out vec4 colour;

void main() {
    vec3 normal = cross(dFdx(world_position), dFdy(world_position));
    vec3 view_ray = world_position - eye;
    float len = length(normal) * length(view_ray);
    float c = len > 0.0 ? abs(dot(normal, view_ray)) / len : 0.0;
    colour = vec4(base_colour * (0.15 + 0.85 * c), opacity);
}
