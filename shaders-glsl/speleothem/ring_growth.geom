#version 450
#extension GL_GOOGLE_include_directive : require
// Tortelli & Walter 2009, section 4.1: one growth pass on the geometry shader, the
// paper's path. What a pass does to each triangle is in `ring_growth.glsl` (shared
// with the compute path); its CPU twin is `grow_pass` in src/model/speleothem.rs. The
// output is captured by transform feedback on stream 0 and is the next pass's input;
// the append-only path runs the same shader twice per pass, once per `mode`.
//
// At most 3 triangles (9 vertices x 12 captured components) per invocation = 108
// output components, well under maxGeometryTotalOutputComponents. No gl_Position: the
// pipeline discards rasterisation, and without it lavapipe's geometry stage has one
// output fewer to store for every vertex emitted.

layout(triangles) in;
layout(triangle_strip, max_vertices = 9) out;

// The growth plan (layout in ring_growth.glsl).
layout(set = 0, binding = 0, std430) readonly buffer Plan {
    vec4 steps[];
} plan;

layout(push_constant) uniform Pass {
    uint pass_index;
    uint speleothem_count;
    uint segments;
    uint mode;  // EMIT_ALL, EMIT_FRONT or EMIT_FROZEN (ring_growth.glsl)
} pc;

// xyz position, w ID: gl_in[k].gl_Position (ring_growth.vert says why)
layout(location = 1) in vec4 in_normal_sp[];  // xyz radial normal N, w speleothem
layout(location = 2) in vec4 in_extra[];      // segment, axial distance, slope, ring

layout(location = 0, xfb_buffer = 0, xfb_offset = 0, xfb_stride = 48) out vec4 out_pos_id;
layout(location = 1, xfb_buffer = 0, xfb_offset = 16, xfb_stride = 48) out vec4 out_normal_sp;
layout(location = 2, xfb_buffer = 0, xfb_offset = 32, xfb_stride = 48) out vec4 out_extra;

#include "ring_growth.glsl"

void emit(V v) {
    out_pos_id = v.pos_id;
    out_normal_sp = v.normal_sp;
    out_extra = v.extra;
    EmitVertex();
}

void end_triangle() {
    EndPrimitive();
}

vec4 plan_step(uint i) {
    return plan.steps[i];
}

void main() {
    V t[3];
    for (int k = 0; k < 3; ++k) {
        t[k] = V(gl_in[k].gl_Position, in_normal_sp[k], in_extra[k]);
    }
    grow_triangle(t, pc.pass_index, pc.speleothem_count, pc.segments, pc.mode);
}
