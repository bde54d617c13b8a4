#version 330 core
in vec2 frag_uv;
in vec4 frag_colour;

uniform sampler2D atlas;

out vec4 colour;

void main() { colour = frag_colour * texture(atlas, frag_uv); }
