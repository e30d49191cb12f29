// Wet calcite (Tortelli & Walter 4.2): the lamp's soft shadows (`shadow.glsl`), normal mapping for ruggedness (a mip chain, its
// strength `--bump`, Toksvig's factor where the filtered normals spread), the lamp,
// environment mapping of the chamber as sediment rendered it into a cube map
// (Schlick's Fresnel, blurrier mips where the surface is rough), tone mapping
// (Ashikhmin 2002 by default). The body of `surface.frag` (shaded once per pixel) and
// `surface_per_sample.frag` (once per sample: the bump detail and the highlights it
// makes alias inside the silhouette, where multisampling alone does not reach).
#include "lighting.glsl"
#include "tonemap.glsl"
#include "shadow.glsl"

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_proj;
    vec4 camera_pos;
    vec4 sun_dir;
    vec4 sun_color;
    vec4 sky_color;
    vec4 ground_color;
    vec4 params;
} frame;

layout(set = 0, binding = 2) uniform texture2D normal_map;
layout(set = 0, binding = 3) uniform sampler normal_sampler;
layout(set = 0, binding = 4) uniform textureCube environment;
layout(set = 0, binding = 5) uniform sampler environment_sampler;

layout(push_constant) uniform Surface {
    vec4 params;
    vec4 look;
} surface;

// `sample`-interpolated inputs make the stage run once per sample.
#ifdef PER_SAMPLE
#define SHADED sample in
#else
#define SHADED in
#endif
layout(location = 0) SHADED vec3 in_world;
layout(location = 1) SHADED vec3 in_normal;
layout(location = 2) SHADED vec3 in_tangent;
layout(location = 3) SHADED vec3 in_uv;
layout(location = 4) SHADED vec3 in_color;

layout(location = 0) out vec4 out_color;

const float SHININESS = 48.0;

void main() {
    vec3 n = normalize(gl_FrontFacing ? in_normal : -in_normal);
    vec3 geometric = n;
    vec3 t = normalize(in_tangent - n * dot(in_tangent, n));
    vec3 b = cross(n, t);
    // The seam-free u (Tarini): the copy whose screen-space change is smaller.
    vec2 uv_a = in_uv.xz;
    vec2 uv_b = in_uv.yz;
    bool a = fwidth(uv_a.x) <= fwidth(uv_b.x);
    vec2 uv = a ? uv_a : uv_b;
    vec2 dx = a ? dFdx(uv_a) : dFdx(uv_b);
    vec2 dy = a ? dFdy(uv_a) : dFdy(uv_b);
#ifdef PER_SAMPLE
    // Each of the n samples stands for 1/n of the pixel: the normal map is filtered
    // over that much, so the n shadings the resolve averages see the bump detail the
    // pixel holds (measured in tests/gpu/anti_aliasing.rs).
    float footprint = surface.look.w;
#else
    // Once per pixel: over the pixel, or under temporal anti-aliasing over this
    // frame's sample's share of it (`Jitter::lod_bias`).
    float footprint = exp2(frame.params.z);
#endif
    vec3 tn = textureGrad(sampler2D(normal_map, normal_sampler), uv, dx * footprint,
                          dy * footprint).xyz * 2.0 - 1.0;
    // A filtered normal is shorter where the normals it averages spread. Lambert's
    // and the ambient terms are linear in the normal, so they take the filtered one
    // as it is (the mean of the shading over the pixel, not the shading of a mean
    // direction, which would be too bright); the highlight takes its direction, with
    // Toksvig's (2005) lower shininess for the spread.
    float len = clamp(length(tn), 1e-3, 1.0);
    float spread = (1.0 - len) / len;
    float bump = surface.params.z;
    vec3 nf = t * (tn.x * bump) + b * (tn.y * bump) + n * tn.z;
    nf /= max(length(nf) / len, 1.0);
    n = normalize(nf);
    float shininess = SHININESS / (1.0 + SHININESS * spread * bump * bump);

    vec3 v = normalize(frame.camera_pos.xyz - in_world);
    vec3 l;
    vec3 radiance;
    light_at(frame.sun_dir, frame.sun_color.rgb, in_world, l, radiance);
    float visible = shadow_visibility(in_world, geometric);
    radiance *= visible;
    vec3 albedo = in_color;
    vec3 ambient = mix(frame.ground_color.rgb, frame.sky_color.rgb, 0.5 + 0.5 * nf.y);
    vec3 h = normalize(l + v);
    float spec = 0.35 * (shininess + 8.0) / 25.1327 * pow(max(dot(n, h), 0.0), shininess)
               * max(dot(n, l), 0.0);
    vec3 hdr = albedo * ambient + radiance * (albedo * max(dot(nf, l), 0.0) + vec3(spec));
    // Wet film: the chamber's reflection, Fresnel-weighted, from a mip whose blur
    // matches the surface's roughness.
    vec3 r = reflect(-v, n);
    float fresnel = 0.04 + 0.96 * pow(1.0 - max(dot(n, v), 0.0), 5.0);
    // Blinn-Phong shininess as a roughness (sqrt(2 / (s + 2))), spread over the chain.
    float lod = surface.look.y * sqrt(2.0 / (shininess + 2.0));
    vec3 env = textureLod(samplerCube(environment, environment_sampler), r, lod).rgb;
    // The cube holds the lamp: a surface in shadow does not see it mirrored either
    // (the reflection toward it takes the shadow, fading out over the blurred lamp).
    env *= mix(1.0, visible, smoothstep(0.75, 0.95, dot(r, l)));
    hdr += surface.look.x * fresnel * env;
    out_color = vec4(tonemap(hdr, frame.params.x), 1.0);
}
