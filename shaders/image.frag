#version 330 core
in vec2 texcoord;

uniform sampler2D image;

out vec4 colour;

void main() { colour = vec4(texture(image, texcoord).rgb, 1.0); }
