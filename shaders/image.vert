#version 330 core
// A textured rectangle on the screen (a CPU image shown as a texture): four
// corners from gl_VertexID, drawn as a triangle strip. `rect` is
// (left, top, right, bottom) in normalised device coordinates.
uniform vec4 rect;

out vec2 texcoord;

void main() {
    vec2 corner = vec2(gl_VertexID & 1, gl_VertexID >> 1);  // (0,0) (1,0) (0,1) (1,1)
    texcoord = corner;  // images are uploaded top row first: v = 0 is the top
    gl_Position = vec4(mix(rect.x, rect.z, corner.x), mix(rect.y, rect.w, corner.y), 0.0, 1.0);
}
