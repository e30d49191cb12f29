#version 450
// Sand dust: a spherical blob whose grain density falls off from the centre; the
// light it absorbs is proportional to the density (alpha blended over the scene, as
// the paper has it), its colour the blob's light (dust.vert). Beyond the paper: the
// blob fades out over the last metres above the sand, so the billboards meet the
// dunes without a hard line (soft particles; the terrain is a heightfield, so the
// distance to it is its height here rather than a depth-buffer read).

layout(set = 0, binding = 0) uniform Light {
    vec4 sun_dir;
    vec4 sun;
    vec4 sky;      // w peak opacity
    vec4 albedo;   // w fade height (m)
    vec4 eye;      // w dune cell size (m)
    vec4 tone;     // z dune grid side, w the dunes' highest point (m)
} light;
// One period of dune heights over the highest (8-bit: lavapipe filters those on its
// fast path, 32-bit float textures off it).
layout(set = 0, binding = 1) uniform texture2D dune_heights;
layout(set = 0, binding = 2) uniform sampler repeat_sampler;

layout(location = 0) in vec2 in_disc;
layout(location = 1) in vec3 in_world;
layout(location = 2) flat in vec4 in_color;  // a the blob's opacity
layout(location = 0) out vec4 out_color;

const float EDGE = 0.018315639;  // exp(-4): the Gaussian at the disc's edge

void main() {
    float r2 = dot(in_disc, in_disc);
    // Density through a Gaussian blob, integrated along the view ray, cut off at the
    // disc's edge (where it has fallen to 2 %) by going to zero there, not by a
    // discard, which lavapipe pays for in every pixel.
    float density = max(exp(-4.0 * r2) - EDGE, 0.0) / (1.0 - EDGE);
    float n = light.tone.z;
    vec2 cell = in_world.xz / light.eye.w;
    float ground = light.tone.w
        * textureLod(sampler2D(dune_heights, repeat_sampler), (cell + 0.5) / n, 0.0).r;
    float soft = smoothstep(0.0, light.albedo.w, in_world.y - ground);
    out_color = vec4(in_color.rgb, light.sky.w * in_color.a * density * soft);
}
