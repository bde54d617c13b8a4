#version 330 core
// The 3D view's mesh as the CPU ray caster drew it: its colour, and its depth
// written to the z-buffer (the hit distances converted to depth-buffer values on
// the CPU), so the overlay drawn after it is hidden behind the surface exactly as
// behind the rasterized mesh. Pixels whose ray hit nothing (depth 1) are left to
// the background, unless `far_pixels` is set (a picture of the whole view copied,
// whose background and what was drawn over it are part of the picture).
// `opacity` < 1: the x-ray view, blended like the mesh.
in vec2 texcoord;

uniform sampler2D image;
uniform sampler2D depth;
uniform float opacity;
uniform bool far_pixels;

out vec4 colour;

void main() {
    float d = texture(depth, texcoord).r;
    if (d >= 1.0 && !far_pixels) discard;
    gl_FragDepth = d;
    colour = vec4(texture(image, texcoord).rgb, opacity);
}
