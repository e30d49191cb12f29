#version 450
// Dune shadows (Onoue & Nishita 3.4) into a shadow map: from every texel's surface
// point a ray toward the sun, sampled where it crosses the grid lines (found
// incrementally); shadowed if the heightfield there rises above the ray. Each texel
// holds the sun's margin over the horizon so found (radians, within the range either
// way), not lit or not, so that the map interpolates to straight, soft edges. The CPU
// twin is `sun_margin` / `shadow_map` in src/model/dune_shadow.rs.

#extension GL_GOOGLE_include_directive : require
#include "periodic.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

const float NEVER = 3.0e38;

layout(set = 0, binding = 0, std430) readonly buffer Heights {
    float h[];
} heights;

layout(set = 0, binding = 1, std430) buffer Shadow {
    float margin[];
} shadow;

// The same heights as an R32F texel buffer, read instead of binding 0 when
// `HEIGHTS_AS_TEXELS` (where the device's texel buffers hold them): llvmpipe gathers a
// texel fetch for its 8 lanes at once but reads a storage buffer lane by lane.
layout(set = 0, binding = 2) uniform samplerBuffer height_texels;
layout(constant_id = 0) const bool HEIGHTS_AS_TEXELS = true;

layout(push_constant) uniform Params {
    vec4 sun;   // xy: horizontal unit direction toward the sun (x, z); z: rise per unit; w: the margins' range (radians)
    uint n;     // grid vertices per side
    uint res;   // shadow map texels per side
    uint unused0;
    uint unused1;
} pc;

// The field is periodic (the simulation's boundary condition).
float at(int x, int z) {
    int n = int(pc.n);
    int i = wrap_periodic(z, n) * n + wrap_periodic(x, n);
    return HEIGHTS_AS_TEXELS ? texelFetch(height_texels, i).r : heights.h[i];
}

float sample_height(float x, float z) {
    float x0 = floor(x);
    float z0 = floor(z);
    float fx = x - x0;
    float fz = z - z0;
    int xi = int(x0);
    int zi = int(z0);
    float a = at(xi, zi) + (at(xi + 1, zi) - at(xi, zi)) * fx;
    float b = at(xi, zi + 1) + (at(xi + 1, zi + 1) - at(xi, zi + 1)) * fx;
    return a + (b - a) * fz;
}

// Distance along the ray to the next grid line of one axis, and between lines.
vec2 first_step(float p, float d) {
    if (d > 1e-6) {
        return vec2((floor(p) + 1.0 - p) / d, 1.0 / d);
    } else if (d < -1e-6) {
        return vec2((p - (ceil(p) - 1.0)) / -d, -1.0 / d);
    }
    // Parallel to this axis's lines: never crosses one (a large finite stand-in for
    // infinity, which naga rejects as a literal).
    return vec2(NEVER, NEVER);
}

void main() {
    uvec2 id = gl_GlobalInvocationID.xy;
    if (id.x >= pc.res || id.y >= pc.res) {
        return;
    }
    // Rays are followed one period: beyond it they have cleared every crest.
    float reach = float(pc.n);
    float scale = reach / float(pc.res);
    float x = (float(id.x) + 0.5) * scale;
    float z = (float(id.y) + 0.5) * scale;
    float y = sample_height(x, z) + 1e-3;
    vec2 dir = pc.sun.xy;
    float rise = pc.sun.z;
    vec2 sx = first_step(x, dir.x);
    vec2 sz = first_step(z, dir.y);
    float tx = sx.x;
    float tz = sz.x;
    float range = pc.sun.w;
    float elevation = atan(rise);
    // A horizon this steep puts the sun out of the range: the march stops there.
    float deepest = elevation + range;
    float deep = deepest < 1.5707963 ? tan(deepest) : NEVER;
    // The horizon's slope toward the sun: the steepest (height - y) / distance seen.
    float horizon = -NEVER;
    // At most one crossing per grid line of each axis.
    for (uint i = 0u; i < 2u * pc.n + 2u; ++i) {
        float t = min(tx, tz);
        if (t >= NEVER) {
            break;
        }
        if (t > reach) {
            break;
        }
        float px = x + dir.x * t;
        float pz = z + dir.y * t;
        horizon = max(horizon, (sample_height(px, pz) - y) / t);
        if (horizon >= deep) {
            break;
        }
        if (tx <= tz) {
            tx += sx.y;
        } else {
            tz += sz.y;
        }
    }
    shadow.margin[id.y * pc.res + id.x] = clamp(elevation - atan(horizon), -range, range);
}
