#version 450
#extension GL_GOOGLE_include_directive : require
// The compute growth path: the same pass as the geometry shader (`ring_growth.glsl`),
// written compactly in input order so the result equals the GS capture vertex for
// vertex. Each invocation owns a run of CHUNK consecutive triangles. Three stages per
// pass, one pipeline each (specialized by `SUMS` and `OFFSETS`, so that each compiles
// only its own code: lavapipe would run the other stages' too, masked): 0 sums each
// run's output count, 1 (one workgroup) turns the sums into each run's offset and
// writes the draw count, 2 writes each run's vertices from its offset on. Runs instead
// of a per-triangle scan: on lavapipe the workgroup barriers of a scan cost as much as
// the growth itself.
// The plan and the input mesh are texel buffers, not storage buffers: llvmpipe (Mesa
// 22.3) reads a storage buffer for its 8 lanes as a loop over them, component by
// component, where a texel fetch gathers the lanes' texels with vector instructions,
// and a triangle makes nine vec4 reads. (The writes stay a storage buffer: nothing else
// can be written at an address per lane. The geometry shader reads its plan from a
// storage buffer still: there a texel buffer makes no difference.)

layout(local_size_x = 256) in;

// Triangles per invocation (ComputeGrowth::CHUNK on the Rust side).
const uint CHUNK = 32u;

// The growth plan (layout in ring_growth.glsl), one step a texel.
layout(set = 0, binding = 0) uniform samplerBuffer plan;

#include "ring_growth.glsl"

// The input mesh, a vertex (V) every three texels.
layout(set = 0, binding = 1) uniform samplerBuffer src;

layout(set = 0, binding = 2, std430) buffer Output {
    V v[];
} dst;

// Per run: the sum of its outputs (stage 0), then its offset (stage 1).
layout(set = 0, binding = 3, std430) buffer Runs {
    uint value[];
} runs;

// A VkDrawIndirectCommand: vertex count of the new mesh, then 1, 0, 0.
layout(set = 0, binding = 4, std430) buffer Draw {
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
} pc;

// The stage: 0 (SUMS), 1 (OFFSETS) or 2 (neither). Booleans: naga cannot read the
// SpecConstantOp a comparison of an integer constant becomes.
layout(constant_id = 0) const bool SUMS = true;
layout(constant_id = 1) const bool OFFSETS = false;

shared uint sums[256];

// Where stage 2 writes its next vertex.
uint cursor = 0u;

void emit(V v) {
    dst.v[cursor].pos_id = v.pos_id;
    dst.v[cursor].normal_sp = v.normal_sp;
    dst.v[cursor].extra = v.extra;
    cursor += 1u;
}

void end_triangle() {
}

vec4 plan_step(uint i) {
    return texelFetch(plan, int(i));
}

V[3] load(uint t) {
    V tri[3];
    for (uint k = 0u; k < 3u; ++k) {
        uint i = 3u * t + k;
        tri[k] = V(texelFetch(src, int(3u * i)), texelFetch(src, int(3u * i + 1u)),
                   texelFetch(src, int(3u * i + 2u)));
    }
    return tri;
}

void main() {
    uint run = gl_GlobalInvocationID.x;
    uint l = gl_LocalInvocationID.x;
    uint run_count = (pc.triangles + CHUNK - 1u) / CHUNK;
    if (SUMS) {
        if (run >= run_count) {
            return;
        }
        uint total = 0u;
        uint end = min((run + 1u) * CHUNK, pc.triangles);
        for (uint t = run * CHUNK; t < end; ++t) {
            total += output_count(load(t), pc.pass_index, pc.speleothem_count);
        }
        runs.value[run] = total;
    } else if (OFFSETS) {
        // One workgroup: each thread takes a stretch of runs, the stretches are scanned
        // in shared memory, then each thread writes its runs' offsets.
        uint per = (run_count + 255u) / 256u;
        uint begin = min(l * per, run_count);
        uint end = min(begin + per, run_count);
        uint own = 0u;
        for (uint i = begin; i < end; ++i) {
            own += runs.value[i];
        }
        sums[l] = own;
        barrier();
        for (uint step = 1u; step < 256u; step *= 2u) {
            uint add = l >= step ? sums[l - step] : 0u;
            barrier();
            sums[l] += add;
            barrier();
        }
        uint at = sums[l] - own;
        for (uint i = begin; i < end; ++i) {
            uint v = runs.value[i];
            runs.value[i] = at;
            at += v;
        }
        if (l == 255u) {
            draw.vertex_count = sums[255];
            draw.instance_count = 1u;
            draw.first_vertex = 0u;
            draw.first_instance = 0u;
        }
    } else {
        if (run >= run_count) {
            return;
        }
        // Two loops, because llvmpipe runs the body of every `if` for all 8 lanes
        // (masked): `grow_triangle` on every triangle paid for the working front's
        // branch (three more plan reads, the flank profile's atan, the new band) and an
        // emission loop run twice, though at most a few triangles of a run are on a
        // working front. The first loop emits each of the others (3 vertices,
        // `thickened` as `grow_triangle` makes them) at its place and only marks the
        // working-front ones; the second runs `grow_triangle` on the marked ones, at
        // the places the first left them (as often as the lane with most).
        uint start = runs.value[run];
        uint first = run * CHUNK;
        uint end = min(first + CHUNK, pc.triangles);
        // Bit i of `working`: triangle first + i is on a working front; of `six` and
        // `nine`: that triangle emits 6 or 9 vertices (their places follow from these).
        uint working = 0u;
        uint six = 0u;
        uint nine = 0u;
        cursor = start;
        // Do-whiles (tested at the end: a `for` tests at the top of one more iteration,
        // which llvmpipe runs masked; `ring_growth.glsl` says so too). first < end.
        uint t = first;
        do {
            V tri[3] = load(t);
            uint count = output_count(tri, pc.pass_index, pc.speleothem_count);
            vec4 s0 = plan_step(plan_base(tri, pc.pass_index, pc.speleothem_count));
            bool front = on_front(tri);
            uint bit = 1u << (t - first);
            if (front && uint(s0.w + 0.5) != 0u) {
                working |= bit;
                six |= count == 6u ? bit : 0u;
                nine |= count == 9u ? bit : 0u;
                cursor += count;
            } else {
                float id_step = front ? 0.0 : 2.0;
                for (int k = 0; k < 3; ++k) {
                    emit(thickened(tri[k], s0.z, id_step));
                }
            }
            t += 1u;
        } while (t < end);
        if (working != 0u) {
            do {
                // Lanes already done run this masked: keep their reads inside the run.
                uint i = min(uint(findLSB(working)) & 31u, end - 1u - first);
                working &= working - 1u;
                uint below = (1u << i) - 1u;
                cursor = start + 3u * i + 3u * uint(bitCount(six & below))
                       + 6u * uint(bitCount(nine & below));
                grow_triangle(load(first + i), pc.pass_index, pc.speleothem_count, pc.segments, EMIT_ALL);
            } while (working != 0u);
        }
    }
}
