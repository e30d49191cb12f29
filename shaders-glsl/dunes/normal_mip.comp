#version 450
// Onoue & Nishita 3.3.2: one level of the ripple normal-map chain — each texel the
// renormalised average of the 4 neighbouring normals of the level above. The CPU twin
// is `normal_mip_chain` in src/model/ripple_maps.rs.

layout(local_size_x = 8, local_size_y = 8) in;

// Every level, packed one after another (vec4: xyz normal, w unused).
layout(set = 0, binding = 0, std430) buffer Levels {
    vec4 texels[];
} levels;

layout(push_constant) uniform Level {
    uint src_offset;
    uint dst_offset;
    uint dst_size;
    uint unused;
} pc;

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= pc.dst_size || p.y >= pc.dst_size) {
        return;
    }
    uint s = pc.dst_size * 2u;
    uint base = pc.src_offset + (2u * p.y) * s + 2u * p.x;
    vec3 a = levels.texels[base].xyz;
    vec3 b = levels.texels[base + 1u].xyz;
    vec3 c = levels.texels[base + s].xyz;
    vec3 d = levels.texels[base + s + 1u].xyz;
    vec3 sum = (a + b) + (c + d);
    levels.texels[pc.dst_offset + p.y * pc.dst_size + p.x] = vec4(sum / sqrt(dot(sum, sum)), 0.0);
}
