#version 450
#extension GL_GOOGLE_include_directive : require
// The compute growth path: the same pass as the geometry shader (`ring_growth.glsl`),
// one invocation per input triangle, written compactly in input order so the result
// equals the GS capture vertex for vertex. Three stages per pass (push constant
// `stage`): 0 counts each triangle's output and scans the counts within a workgroup,
// 1 (one workgroup) turns the workgroups' sums into their offsets and writes the draw
// count, 2 writes every triangle's vertices at its offset. lavapipe runs compute on
// every core, its geometry stage on one.

layout(local_size_x = 256) in;

layout(set = 0, binding = 0, std430) readonly buffer Plan {
    vec4 steps[];
} plan;

#include "ring_growth.glsl"

layout(set = 0, binding = 1, std430) readonly buffer Input {
    V v[];
} src;

layout(set = 0, binding = 2, std430) buffer Output {
    V v[];
} dst;

// Per triangle: its output offset within its workgroup.
layout(set = 0, binding = 3, std430) buffer Local {
    uint offset[];
} local_scan;

// Per workgroup: the sum of its outputs (stage 0), then its offset (stage 1).
layout(set = 0, binding = 4, std430) buffer Blocks {
    uint value[];
} blocks;

// A VkDrawIndirectCommand: vertex count of the new mesh, then 1, 0, 0.
layout(set = 0, binding = 5, std430) buffer Draw {
    uint vertex_count;
    uint instance_count;
    uint first_vertex;
    uint first_instance;
} draw;

layout(push_constant) uniform Pass {
    uint pass_index;
    uint speleothem_count;
    uint segments;
    uint triangles;
    uint stage;
    uint pad0;
    uint pad1;
    uint pad2;
} pc;

shared uint sums[256];

V[3] load(uint t) {
    V tri[3];
    // Member by member: a whole-struct copy between buffer and local layouts becomes
    // OpCopyLogical, which naga does not read.
    for (uint k = 0u; k < 3u; ++k) {
        uint i = 3u * t + k;
        tri[k] = V(src.v[i].pos_id, src.v[i].normal_sp, src.v[i].extra);
    }
    return tri;
}

// Inclusive scan of `sums` across the workgroup (Hillis-Steele).
void scan_shared(uint l) {
    for (uint step = 1u; step < 256u; step *= 2u) {
        uint add = l >= step ? sums[l - step] : 0u;
        barrier();
        sums[l] += add;
        barrier();
    }
}

void main() {
    uint t = gl_GlobalInvocationID.x;
    uint l = gl_LocalInvocationID.x;
    if (pc.stage == 0u) {
        uint count = 0u;
        if (t < pc.triangles) {
            count = output_count(load(t), pc.pass_index, pc.speleothem_count);
        }
        sums[l] = count;
        barrier();
        scan_shared(l);
        if (t < pc.triangles) {
            local_scan.offset[t] = sums[l] - count;
        }
        if (l == 255u) {
            blocks.value[gl_WorkGroupID.x] = sums[l];
        }
    } else if (pc.stage == 1u) {
        uint groups = (pc.triangles + 255u) / 256u;
        uint per = (groups + 255u) / 256u;
        uint begin = min(l * per, groups);
        uint end = min(begin + per, groups);
        uint own = 0u;
        for (uint i = begin; i < end; ++i) {
            own += blocks.value[i];
        }
        sums[l] = own;
        barrier();
        scan_shared(l);
        uint running = sums[l] - own;
        for (uint i = begin; i < end; ++i) {
            uint v = blocks.value[i];
            blocks.value[i] = running;
            running += v;
        }
        if (l == 255u) {
            draw.vertex_count = sums[255];
            draw.instance_count = 1u;
            draw.first_vertex = 0u;
            draw.first_instance = 0u;
        }
    } else {
        if (t >= pc.triangles) {
            return;
        }
        uint at = blocks.value[gl_WorkGroupID.x] + local_scan.offset[t];
        V tri[3] = load(t);
        Emitted e = grow_triangle(tri, pc.pass_index, pc.speleothem_count, pc.segments);
        for (int i = 0; i < e.count; ++i) {
            uint o = at + uint(i);
            dst.v[o].pos_id = e.v[i].pos_id;
            dst.v[o].normal_sp = e.v[i].normal_sp;
            dst.v[o].extra = e.v[i].extra;
        }
    }
}
