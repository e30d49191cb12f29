#version 450
// Sand dust: each blob becomes a camera-facing billboard (two triangles) carrying the
// blob's disc coordinates for the density falloff and its world position, where the
// fragment shader finds the sand below.

layout(points) in;
layout(triangle_strip, max_vertices = 4) out;

layout(push_constant) uniform Dust {
    mat4 view_proj;
    vec4 right;  // camera right, world space
    vec4 up;     // camera up, world space
} dust;

layout(location = 0) in vec4 in_blob[];
layout(location = 0) out vec2 out_disc;
layout(location = 1) out vec3 out_world;

void main() {
    vec3 c = in_blob[0].xyz;
    float r = in_blob[0].w;
    if (r <= 0.0) {
        return;
    }
    for (int i = 0; i < 4; ++i) {
        vec2 corner = vec2(float(i & 1) * 2.0 - 1.0, float(i >> 1) * 2.0 - 1.0);
        vec3 p = c + (dust.right.xyz * corner.x + dust.up.xyz * corner.y) * r;
        out_disc = corner;
        out_world = p;
        gl_Position = dust.view_proj * vec4(p, 1.0);
        EmitVertex();
    }
    EndPrimitive();
}
