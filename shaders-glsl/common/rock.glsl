// Limestone: its colour wanders between iron-stained ochre (the albedo given) and
// `grey` in beds and patches, speckled at the grain, with a relief of the same solid
// noise bent into the normal. Solid noise, not a projected texture: steep walls and
// floors are textured alike and no seam shows where projections would meet. The growth
// chamber's rock (`lit_mesh.glsl`) and the cave's walls (`cave_wall.frag`).
#ifndef SEDIMENT_ROCK_GLSL
#define SEDIMENT_ROCK_GLSL
#include "noise.glsl"

// `footprint`: the pixel's size on the surface, for `octave_weight`.
void limestone(vec3 p, float footprint, vec3 grey, inout vec3 n, inout vec3 albedo) {
    vec4 patches = value_noise(p * vec3(1.1, 2.6, 1.1));
    vec4 grain = value_noise(p * 9.0 + 13.0);
    vec4 fine = value_noise(p * 31.0 + 71.0);
    float g = octave_weight(9.0, footprint);
    float f = octave_weight(31.0, footprint);
    float stain = smoothstep(0.25, 0.8, patches.x);
    albedo = mix(grey, albedo, stain) * (0.91 + g * 0.46 * (grain.x - 0.5))
           * (1.0 + f * 0.36 * (fine.x - 0.5));
    vec3 slope = 0.05 * patches.yzw + g * 0.045 * grain.yzw + f * 0.02 * fine.yzw;
    n = normalize(n - (slope - dot(slope, n) * n));
}

#endif
