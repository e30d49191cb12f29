#version 450
// Horizon map (Max 1988; Onoue & Nishita 3.5.1): for every ripple texel and the 8
// directions (axes and diagonals, counter-clockwise from +x), the largest elevation
// slope to the texels along that direction on the periodic tile. The CPU twin is
// `horizon_map` in src/model/ripple_maps.rs.

#extension GL_GOOGLE_include_directive : require
#include "periodic.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, std430) readonly buffer Heights {
    float h[];
} heights;

// Two planes of vec4: directions 0-3 for every texel, then directions 4-7.
layout(set = 0, binding = 1, std430) buffer Horizon {
    vec4 slopes[];
} horizon;

// The same heights as an R32F texel buffer, read instead of binding 0 when
// `HEIGHTS_AS_TEXELS` (where the device's texel buffers hold them): llvmpipe gathers a
// texel fetch for its 8 lanes at once but reads a storage buffer lane by lane.
layout(set = 0, binding = 2) uniform samplerBuffer height_texels;
layout(constant_id = 0) const bool HEIGHTS_AS_TEXELS = true;

float height_at(int i) {
    return HEIGHTS_AS_TEXELS ? texelFetch(height_texels, i).r : heights.h[i];
}

layout(push_constant) uniform Params {
    uint size;
    uint steps;
    float height_scale;
    uint unused;
} pc;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    int n = int(pc.size);
    if (p.x >= n || p.y >= n) {
        return;
    }
    float here = height_at(p.y * n + p.x);
    float s[8];
    for (int d = 0; d < 8; ++d) {
        // Direction d at d * 45 degrees: exact unit steps along axes and diagonals.
        float angle = radians(45.0 * float(d));
        ivec2 dir = ivec2(round(cos(angle)), round(sin(angle)));
        float step_len = sqrt(float(dir.x * dir.x + dir.y * dir.y));
        float best = -3.402823e38;
        for (int k = 1; k <= int(pc.steps); ++k) {
            int qx = wrap_periodic(p.x + dir.x * k, n);
            int qy = wrap_periodic(p.y + dir.y * k, n);
            float there = height_at(qy * n + qx);
            best = max(best, (there - here) * pc.height_scale / (float(k) * step_len));
        }
        s[d] = best;
    }
    uint i = uint(p.y * n + p.x);
    horizon.slopes[i] = vec4(s[0], s[1], s[2], s[3]);
    horizon.slopes[uint(n * n) + i] = vec4(s[4], s[5], s[6], s[7]);
}
