// Soft shadows from a spherical lamp through one perspective shadow map: percentage-
// closer soft shadows (Fernando 2005). A blocker search near the receiver's texel gives
// the occluders' mean depth; by similar triangles a lamp of radius R makes a penumbra
// R (z_r - z_b) / z_b wide at the receiver, and a percentage-closer filter that wide
// (each tap the hardware's bilinear 2x2 comparison) gives the share of the lamp seen.
// Set 1 of every shadowed pass; `render::shadow_map` fills it.
#ifndef SEDIMENT_SHADOW_GLSL
#define SEDIMENT_SHADOW_GLSL

layout(set = 1, binding = 0) uniform Shadow {
    mat4 view_proj; // world to the lamp's clip space (depth 0..1 from near to far)
    vec4 params;    // x 1 on / 0 off, y a texel in uv, z uv per world unit at unit
                    // depth (1 / (2 tan(fov / 2))), w the lamp's radius
    vec4 range;     // x near, y far, z a texel's world size at unit depth, w the widest
                    // filter in uv
    vec4 light;     // xyz the lamp
} shadow;
layout(set = 1, binding = 1) uniform texture2D shadow_map;
layout(set = 1, binding = 2) uniform samplerShadow shadow_compare;
layout(set = 1, binding = 3) uniform sampler shadow_point;
// The same map again for the blocker search's plain reads: a texture is either
// compared or read in SPIR-V readers such as naga, not both.
layout(set = 1, binding = 4) uniform texture2D shadow_depth;

const int SHADOW_TAPS = 16;
// How much nearer the lamp than the receiver a texel must be to count as a blocker.
const float BLOCKER_GAP = 0.01;

// Distance along the lamp's axis of a stored depth (a Vulkan perspective: 0 at near, 1 at far).
float shadow_linear_depth(float d) {
    float n = shadow.range.x;
    float f = shadow.range.y;
    return n * f / (f - d * (f - n));
}

// The stored depth of a distance along the lamp's axis.
float shadow_ndc_depth(float z) {
    float n = shadow.range.x;
    float f = shadow.range.y;
    return f * (z - n) / ((f - n) * z);
}

// The distance of the receiver's plane at uv offset `o`: 1 / depth is affine in uv,
// `inv_r` at the receiver, changing by `grad` per unit of uv.
float shadow_plane_depth(float inv_r, vec2 grad, vec2 o) {
    return 1.0 / max(inv_r + dot(grad, o), 1e-6);
}

// The i-th of SHADOW_TAPS points of a Vogel disc of radius 1, turned by `phi`.
vec2 shadow_tap(int i, float phi) {
    float r = sqrt((float(i) + 0.5) / float(SHADOW_TAPS));
    float a = float(i) * 2.39996323 + phi;
    return r * vec2(cos(a), sin(a));
}

// Whether `world` (normal `n`) sees the lamp's centre, 0..1: one bilinear 2x2
// comparison, no penumbra. For light that is blurred anyway (through the calcite), at
// a fraction of `shadow_visibility`'s 32 taps (llvmpipe runs a branch's taps whether
// or not a pixel takes it).
float shadow_visibility_hard(vec3 world, vec3 n) {
    float dist = length(shadow.light.xyz - world);
    vec4 c = shadow.view_proj * vec4(world + n * (1.5 * shadow.range.z * dist), 1.0);
    vec3 ndc = c.xyz / max(c.w, 1e-6);
    vec2 uv = ndc.xy * 0.5 + 0.5;
    bool outside = c.w <= 0.0 || any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))
                || ndc.z >= 1.0 || shadow.params.x < 0.5;
    float lit = texture(sampler2DShadow(shadow_map, shadow_compare), vec3(uv, ndc.z));
    return outside ? 1.0 : lit;
}

// The share of the lamp seen from `world` (normal `n`, facing the lamp), 0..1.
float shadow_visibility(vec3 world, vec3 n) {
    if (shadow.params.x < 0.5) {
        return 1.0;
    }
    // Normal offset: a texel and a half of the map's footprint at this distance, so
    // a surface does not shadow itself where it slopes away from the lamp.
    float dist = length(shadow.light.xyz - world);
    vec3 q = world + n * (1.5 * shadow.range.z * dist);
    vec4 c = shadow.view_proj * vec4(q, 1.0);
    if (c.w <= 0.0) {
        return 1.0;
    }
    vec3 ndc = c.xyz / c.w;
    vec2 uv = ndc.xy * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || ndc.z >= 1.0) {
        return 1.0;
    }
    float z_r = c.w;
    float k = shadow.params.z;
    float lamp = shadow.params.w;
    float widest = shadow.range.w;
    // One disc for every pixel: a per-pixel turn (interleaved gradient noise) trades
    // the taps' faint banding for grain that multisampling does not average.
    const float phi = 0.0;
    // The blockers that can hide part of the lamp lie, on the map, within the lamp's
    // disc seen from the receiver and projected on the near plane.
    float search = clamp(lamp * k * (z_r - shadow.range.x) / (z_r * shadow.range.x),
                         2.0 * shadow.params.y, widest);
    // The receiver's own plane on the map: 1 / depth is affine in uv over a plane,
    // its gradient found from two points beside the receiver along the surface.
    // A texel is a blocker only where it lies nearer the lamp than that plane does
    // (Isidoro 2006's receiver plane): a floor at a grazing angle is not its own
    // blocker.
    vec3 t1 = normalize(cross(n, abs(n.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0)));
    vec3 t2 = cross(n, t1);
    float step = 0.01 * dist;
    vec4 c1 = shadow.view_proj * vec4(q + t1 * step, 1.0);
    vec4 c2 = shadow.view_proj * vec4(q + t2 * step, 1.0);
    vec2 d1 = c1.xy / c1.w * 0.5 + 0.5 - uv;
    vec2 d2 = c2.xy / c2.w * 0.5 + 0.5 - uv;
    float inv_r = 1.0 / z_r;
    mat2 rows = mat2(d1.x, d2.x, d1.y, d2.y);
    float det = determinant(rows);
    vec2 grad = abs(det) > 1e-12 ? inverse(rows) * vec2(1.0 / c1.w - inv_r, 1.0 / c2.w - inv_r)
                                 : vec2(0.0);
    // The farthest blocker sets the penumbra: the silhouette's edge nearest the
    // receiver (an average over a round occluder's near side widens it).
    float z_b = 0.0;
    for (int i = 0; i < SHADOW_TAPS; i++) {
        vec2 o = shadow_tap(i, phi) * search;
        float d = textureLod(sampler2D(shadow_depth, shadow_point), uv + o, 0.0).r;
        float z = shadow_linear_depth(d);
        float plane = shadow_plane_depth(inv_r, grad, o);
        if (z < min(plane, z_r) * (1.0 - BLOCKER_GAP)) {
            z_b = max(z_b, z);
        }
    }
    float penumbra = lamp * (z_r - z_b) / max(z_b, 1e-6) * k / z_r;
    float width = clamp(penumbra, 2.0 * shadow.params.y, widest);
    float lit = 0.0;
    // No blocker over the whole search: the lamp is wholly seen (most of a lit frame
    // ends here, half the taps spent). The filter's loop runs no taps rather than the
    // function returning early: llvmpipe leaves a loop once no pixel of a block
    // still runs it, but runs both sides of a branch (10-15 % of the growth viewer's
    // shading).
    int taps = z_b == 0.0 ? 0 : SHADOW_TAPS;
    for (int i = 0; i < taps; i++) {
        // Each tap compared with the receiver's plane there, not with the receiver
        // itself: a wide filter over a sloping floor would shadow the floor.
        vec2 o = shadow_tap(i, phi + 1.0) * width;
        float plane = shadow_ndc_depth(min(shadow_plane_depth(inv_r, grad, o), z_r));
        lit += texture(sampler2DShadow(shadow_map, shadow_compare), vec3(uv + o, plane));
    }
    return z_b == 0.0 ? 1.0 : lit / float(SHADOW_TAPS);
}

#endif
