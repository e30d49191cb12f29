// The desert beyond the simulated period (src/model/dune_world.rs, the CPU reference
// of everything here): around the middle period, the highest of randomly offset
// copies of it on a lattice, each bent by a smooth warp; the ripple tile's copies on
// a lattice of their own.
#ifndef SEDIMENT_DUNE_WORLD_GLSL
#define SEDIMENT_DUNE_WORLD_GLSL

// render::dune_surface::DuneWorldUniforms.
layout(set = 0, binding = 9) uniform World {
    // xy wave vector (radians per metre), z phase, w amplitude (m): the warp's x then
    // z component (three waves each).
    vec4 waves[6];
    // x period, y how far beyond it the lattice takes over, z how deep a copy of no
    // weight lies, w the lattice's spacing (metres).
    vec4 params;
    // The ripple tile's lattice of copies: x its spacing (m), y the weights' power,
    // zw the salt added to a corner before hashing.
    vec4 ripples;
    // The bedrock under the sand: x its height (m), y the depth of sand that hides it
    // (0: none drawn); and its albedo (rgb).
    vec4 bedrock;
    vec4 bedrock_albedo;
} world;

// Warp::at.
vec2 warp_at(vec2 p) {
    vec2 d = vec2(0.0);
    for (int k = 0; k < 3; ++k) {
        vec4 a = world.waves[k];
        vec4 b = world.waves[3 + k];
        d.x += a.w * sin(dot(a.xy, p) + a.z);
        d.y += b.w * sin(dot(b.xy, p) + b.z);
    }
    return d;
}

// DesertWorld::lattice_share (surface.frag calls it only with the world on: a branch
// on a uniform would cost lavapipe both sides).
float lattice_share(vec2 p) {
    vec2 outside = max(max(-p, p - vec2(world.params.x)), vec2(0.0));
    return smoothstep(0.0, world.params.y, length(outside));
}

// Three uniform numbers in [0, 1) for an integer lattice cell (PCG-style hash;
// dune_world::hash2 is its first two).
vec3 hash3(ivec2 c) {
    uvec3 v = uvec3(uint(c.x), uint(c.y), uint(c.x) ^ uint(c.y) * 747796405u);
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v ^= v >> 16u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    return vec3(v & 0xFFFFFFu) / 16777216.0;
}

// dune_world::simplex_corners: the corners of the lattice triangle around `u` (in
// spacings) and their weights.
void simplex_corners(vec2 u, out ivec2 corner[3], out float weight[3]) {
    const float SKEW = 0.36602540378;    // (sqrt 3 - 1) / 2
    const float UNSKEW = 0.21132486540;  // (3 - sqrt 3) / 6
    float s = (u.x + u.y) * SKEW;
    vec2 cell = floor(u + vec2(s));
    float t = (cell.x + cell.y) * UNSKEW;
    vec2 d0 = u - (cell - vec2(t));
    ivec2 step = d0.x > d0.y ? ivec2(1, 0) : ivec2(0, 1);
    vec2 d1 = d0 - vec2(step) + vec2(UNSKEW);
    vec2 d2 = d0 - vec2(1.0) + vec2(2.0 * UNSKEW);
    ivec2 base = ivec2(cell);
    corner[0] = base;
    corner[1] = base + step;
    corner[2] = base + ivec2(1);
    weight[0] = max(0.5 - dot(d0, d0), 0.0);
    weight[1] = max(0.5 - dot(d1, d1), 0.0);
    weight[2] = max(0.5 - dot(d2, d2), 0.0);
}

#endif
