#version 330 core
// Lines wider than one pixel (core profile allows only glLineWidth(1)): each
// segment becomes a screen-aligned quad line_width pixels wide, for boxes and
// segments that must read on a projector. The segment is first clipped to the
// near plane (z >= -w), where the division by w is safe.
layout(lines) in;
layout(triangle_strip, max_vertices = 4) out;

uniform vec2 viewport_size;  // pixels
uniform float line_width;    // pixels

in vec4 vertex_colour[];
out vec4 line_colour;

void main() {
    vec4 a = gl_in[0].gl_Position, b = gl_in[1].gl_Position;
    float da = a.z + a.w, db = b.z + b.w;  // signed distance to the near plane
    if (da < 0.0 && db < 0.0) return;
    if (da < 0.0) a = mix(a, b, da / (da - db));
    if (db < 0.0) b = mix(b, gl_in[0].gl_Position, db / (db - da));

    vec2 pa = a.xy / a.w * 0.5 * viewport_size, pb = b.xy / b.w * 0.5 * viewport_size;  // pixels from centre
    vec2 dir = pb - pa;
    dir = length(dir) > 1e-6 ? normalize(dir) : vec2(1.0, 0.0);
    vec2 side = vec2(-dir.y, dir.x) * 0.5 * line_width;
    vec2 along = dir * 0.5 * line_width;  // square caps: corners of boxes meet cleanly
    vec2 to_ndc = 2.0 / viewport_size;

    line_colour = vertex_colour[0];
    gl_Position = vec4((pa - along + side) * to_ndc * a.w, a.z, a.w); EmitVertex();
    gl_Position = vec4((pa - along - side) * to_ndc * a.w, a.z, a.w); EmitVertex();
    line_colour = vertex_colour[1];
    gl_Position = vec4((pb + along + side) * to_ndc * b.w, b.z, b.w); EmitVertex();
    gl_Position = vec4((pb + along - side) * to_ndc * b.w, b.z, b.w); EmitVertex();
    EndPrimitive();
}
