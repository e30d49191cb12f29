#version 450
// The horizon map in time linear in the tile's size (Timonen & Westerholm 2010,
// "Scalable Height Field Self-Shadowing"): the same map as horizon.comp over the whole
// periodic row. On the periodic N x N tile every line of texels along one of the
// directions (axes, diagonals and, with 16, the knight's moves (2, 1) between them) is
// a cycle of N texels. An invocation takes one line and sweeps it backwards once
// round, keeping the upper convex hull of the heights ahead; the hull's top after
// popping what a texel sees past is its horizon. Texels beyond the line's highest one
// never set a horizon (the highest is nearer and at least as high, so it is seen more
// steeply), so one lap starting at the highest texel sees all that matters; the
// highest texel's own horizon (below zero: everything else is lower, and its own copy
// a lap ahead must not count) is the largest (h - highest) / k, taken as the sweep
// passes.
// The opposite direction's line is the same cycle stepped the other way, with the
// same highest texel: the same invocation sweeps it next (`sweep_line` twice), so the
// highest texel is found once for both and the second sweep reads what the scan and
// the first left in the cache (the map the same to the bit).
//
// What makes it fast on Mesa 22.3's llvmpipe, which runs 8 invocations as one SIMD
// program, runs the body of every `if` and every loop at least once whether or not
// an invocation takes it (under a mask), and reads or writes a storage buffer for
// the 8 as a loop over them (so every load or store in the sweep's loop costs its
// 8-step loop on every step, taken or not):
// - The hull's top eight entries live in registers; memory is touched to spill two of
//   them (one vec4) when the window fills, checked every other step (a full window
//   then always has room for the next push), and to refill two when pops run the
//   window down to its top with more below.
// - The pops of a step are computed at once, not in a loop: popping from the top
//   meets pair i's test with the same two entries as the window holds them, so the
//   pops are the prefix of the seven tests that hold, and the window shifts by that
//   count in three select stages (a loop would run as often as the most-popping of
//   the 8 lanes, each time masked).
// - The sweep runs in groups of four positions aligned to the line's storage, the
//   same in every invocation, and writes each group as one vec4: it starts at the end
//   of the highest texel's group a lap ahead (positions past the highest texel first,
//   with the peak pushed as it passes) and ends after that group a lap later (N + 4
//   steps), so that group is written twice and the second time right: its texels
//   beyond the peak see the whole lap, those behind it see the peak, and the peak's
//   own slot is written last. Extra entries beyond the peak on the hull are seen no
//   more steeply than the peak, so no horizon changes.
// - Each invocation writes its own line (the map is stored by line:
//   `planes_from_lines` in src/render/ripple_maps.rs reorders it for the CPU), and
//   lines steeper in y read a transposed copy of the heights, so that columns, like
//   rows, step one texel further in memory.
// - The heights are read as a texel buffer (one gather for the 8 lanes) where the
//   device's texel buffers hold both copies, else as a storage buffer (a loop over
//   the lanes): `HEIGHTS_AS_TEXELS`. Lines across rows step a whole row (4 KB at
//   N = 1024) a texel, which the prefetchers do not follow, so the reads wait on the
//   cache; a gather lets the next steps' loads start meanwhile.
// The refill stays because a cached pair or a larger window runs out on most lines of
// noise or of smooth profiles, and the heights are read in place because a copy of
// the lines in the sweep's order would read across rows and wait on the cache itself.
// The CPU twin is `horizon_map_linear_along` in src/model/ripple_maps.rs (one lap
// from the peak, as the paper's method reads: the same map to the bit on the tests'
// fields).

layout(local_size_x = 64) in;

// The heights (row-major), then the same heights transposed: as a storage buffer,
// and (where the device's texel buffers hold them, one float a texel) as a texel
// buffer, read instead when `HEIGHTS_AS_TEXELS`.
layout(set = 0, binding = 0, std430) readonly buffer Heights {
    float h[];
} heights;
layout(set = 0, binding = 3) uniform samplerBuffer height_texels;
layout(constant_id = 0) const bool HEIGHTS_AS_TEXELS = true;

float height_at(int i) {
    return HEIGHTS_AS_TEXELS ? texelFetch(height_texels, i).r : heights.h[i];
}

// By line: direction d's line l at (d * N + l) * N floats, position by position from
// the line's start, four positions to a vec4 (N is a power of two of at least 4).
layout(set = 0, binding = 1, std430) buffer Horizon {
    vec4 s[];
} horizon;

// The hull stacks below the entries held in registers: N entries for each invocation
// of a dispatch (a stack never holds more than a lap), two entries (position, height)
// to a vec4, the deeper first.
layout(set = 0, binding = 2, std430) buffer Hull {
    vec4 at[];
} hull;

layout(push_constant) uniform Params {
    uint size;
    // 8 (axes and diagonals) or 16 (and the knight's moves).
    uint directions;
    float height_scale;
    // This dispatch's first pair of opposite directions, d and d + directions / 2
    // (dispatches share the hull buffer).
    uint first_pair;
} pc;

// Direction k of 16, counter-clockwise from +x: even k the axes and diagonals, odd k
// the knight's moves between them.
ivec2 direction16(int k) {
    int octant = k / 2;
    float angle = radians(45.0 * float(octant));
    ivec2 axis = ivec2(round(cos(angle)), round(sin(angle)));
    if (k % 2 == 0) {
        return axis;
    }
    float next = radians(45.0 * float(octant + 1));
    return axis + ivec2(round(cos(next)), round(sin(next)));
}

// One step past either end only (a line steps at most 2 texels): two selects, cheaper
// than common/periodic.glsl's wrap_periodic, which takes any index.
int wrap(int i, int n) {
    return i < 0 ? i + n : (i >= n ? i - n : i);
}

// The sweep of one line, shared by `sweep_step` and `main`.
int n;
// The line's step in its frame of the heights (see main), and where it stands.
int su;
int sv;
int frame;
int u;
int v;
// The highest texel's position and height.
int p;
float highest;
uint hull_base;
// The hull's top entries (position, height), r0 the top, w of them valid; m more in
// memory, moved two at a time (so m stays even and a pair is one aligned vec4).
vec2 r0, r1, r2, r3, r4, r5, r6, r7;
int w;
int m;
// The peak's own horizon, the largest (h - highest) / k, kept as a fraction.
float best_rise;
float best_k;

// 1 where the entry at `below` (relative to the texel) is seen at least as steeply as
// the one at `top`, so `top` pops (slopes compared by cross-multiplying: both runs
// are positive).
uint pops_past(vec2 top, vec2 below) {
    return uint(top.y * below.x <= below.y * top.x);
}

// One texel of the sweep at lap position t, of height `here`: pops what it sees
// past, pushes it, and returns its horizon as (rise, run).
// `spill`: whether this step may move two entries to memory (every other step: the
// window then never holds more than seven before a push).
vec2 sweep_step(int t, bool spill, float here) {
    float ft = float(t);
    // Pop while the entry below the top is seen at least as steeply: all seven tests
    // on the window as it is, the pops the prefix of those that hold.
    vec2 d0 = r0 - vec2(ft, here);
    vec2 d1 = r1 - vec2(ft, here);
    vec2 d2 = r2 - vec2(ft, here);
    vec2 d3 = r3 - vec2(ft, here);
    vec2 d4 = r4 - vec2(ft, here);
    vec2 d5 = r5 - vec2(ft, here);
    vec2 d6 = r6 - vec2(ft, here);
    vec2 d7 = r7 - vec2(ft, here);
    uint c0 = uint(w >= 2) & pops_past(d0, d1);
    uint c1 = c0 & uint(w >= 3) & pops_past(d1, d2);
    uint c2 = c1 & uint(w >= 4) & pops_past(d2, d3);
    uint c3 = c2 & uint(w >= 5) & pops_past(d3, d4);
    uint c4 = c3 & uint(w >= 6) & pops_past(d4, d5);
    uint c5 = c4 & uint(w >= 7) & pops_past(d5, d6);
    uint c6 = c5 & uint(w >= 8) & pops_past(d6, d7);
    uint pops = c0 + c1 + c2 + c3 + c4 + c5 + c6;
    bvec2 s = bvec2((pops & 1u) != 0u);
    r0 = mix(r0, r1, s);
    r1 = mix(r1, r2, s);
    r2 = mix(r2, r3, s);
    r3 = mix(r3, r4, s);
    r4 = mix(r4, r5, s);
    r5 = mix(r5, r6, s);
    r6 = mix(r6, r7, s);
    s = bvec2((pops & 2u) != 0u);
    r0 = mix(r0, r2, s);
    r1 = mix(r1, r3, s);
    r2 = mix(r2, r4, s);
    r3 = mix(r3, r5, s);
    r4 = mix(r4, r6, s);
    r5 = mix(r5, r7, s);
    s = bvec2((pops & 4u) != 0u);
    r0 = mix(r0, r4, s);
    r1 = mix(r1, r5, s);
    r2 = mix(r2, r6, s);
    r3 = mix(r3, r7, s);
    w -= int(pops);
    // The window popped down to its top with more in memory: two entries come back
    // and are tested, until a test fails or memory is empty.
    while (w == 1 && m > 0) {
        m -= 2;
        vec4 pair = hull.at[(hull_base + uint(m)) / 2u];
        r2 = pair.xy;
        r1 = pair.zw;
        d0 = r0 - vec2(ft, here);
        d1 = r1 - vec2(ft, here);
        d2 = r2 - vec2(ft, here);
        uint e0 = pops_past(d0, d1);
        uint e1 = e0 & pops_past(d1, d2);
        s = bvec2(e0 != 0u);
        r0 = mix(r0, r1, s);
        r1 = mix(r1, r2, s);
        r0 = mix(r0, r2, bvec2(e1 != 0u));
        w = 3 - int(e0 + e1);
    }
    vec2 rise_run = vec2(r0.y - here, r0.x - ft);
    int k = t - p;
    if (k > 0 && k < n && (here - highest) * best_k > best_rise * float(k)) {
        best_rise = here - highest;
        best_k = float(k);
    }
    if (spill && w >= 7) {
        // The window's bottom two onto memory, the deeper first.
        hull.at[(hull_base + uint(m)) / 2u] = w == 8 ? vec4(r7, r6) : vec4(r6, r5);
        m += 2;
        w -= 2;
    }
    r7 = r6;
    r6 = r5;
    r5 = r4;
    r4 = r3;
    r3 = r2;
    r2 = r1;
    r1 = r0;
    r0 = vec2(ft, here);
    w += 1;
    return rise_run;
}

// The height at (u, v), which then steps back along the line.
float height_back() {
    float here = height_at(frame + v * n + u);
    u = wrap(u - su, n);
    v = wrap(v - sv, n);
    return here;
}

// Sweeps the line whose frame (su, sv, frame, n) is set, its highest texel at
// position p, (pu, pv), writing its horizons from out_base.
void sweep_line(uint out_base, float step_len, int pu, int pv) {
    // From the last position of the peak's group of four, a lap ahead (q0 + N), down
    // to the first of that group (N + 4 steps), the hull empty at first.
    int q0 = p | 3;
    u = pu;
    v = pv;
    for (int j = p; j < q0; ++j) {
        u = wrap(u + su, n);
        v = wrap(v + sv, n);
    }
    r0 = vec2(0.0);
    r1 = vec2(0.0);
    r2 = vec2(0.0);
    r3 = vec2(0.0);
    r4 = vec2(0.0);
    r5 = vec2(0.0);
    r6 = vec2(0.0);
    r7 = vec2(0.0);
    w = 0;
    m = 0;
    best_rise = -3.402823e38;
    best_k = 1.0;
    int t = q0 + n;
    for (int g = 0; g <= n / 4; ++g) {
        // The group's four heights read together, so that their waits on the cache
        // overlap.
        float h3 = height_back();
        float h2 = height_back();
        float h1 = height_back();
        float h0 = height_back();
        vec2 a3 = sweep_step(t, true, h3);
        vec2 a2 = sweep_step(t - 1, false, h2);
        vec2 a1 = sweep_step(t - 2, true, h1);
        vec2 a0 = sweep_step(t - 3, false, h0);
        // The same expression as the brute walk's (there - here) * s / (k * len).
        horizon.s[(out_base + uint((t - 3) & (n - 1))) / 4u] =
            vec4(a0.x, a1.x, a2.x, a3.x) * pc.height_scale
            / (vec4(a0.y, a1.y, a2.y, a3.y) * step_len);
        t -= 4;
    }
    horizon.s[(out_base + uint(p)) / 4u][p & 3] =
        best_rise * pc.height_scale / (best_k * step_len);
}

void main() {
    n = int(pc.size);
    int id = int(gl_GlobalInvocationID.x);
    int half_turn = int(pc.directions) / 2;
    int d = int(pc.first_pair) + id / n;
    if (d >= half_turn) {
        return;
    }
    int line = id % n;
    ivec2 dir = direction16(pc.directions == 8u ? 2 * d : d);
    // The line's frame: the heights transposed where the direction is steeper in y,
    // so that a line steps +-1 along rows (axes: one texel further in memory) or
    // +-1 row and su along it (diagonals, knight's moves).
    bool transposed = abs(dir.y) > abs(dir.x);
    su = transposed ? dir.y : dir.x;
    sv = transposed ? dir.x : dir.y;
    frame = transposed ? n * n : 0;
    float step_len = sqrt(float(dir.x * dir.x + dir.y * dir.y));
    // Along a row, line k is row k; across rows, the line through (k, 0).
    u = sv == 0 ? 0 : line;
    v = sv == 0 ? line : 0;
    hull_base = uint(id) * uint(n);

    // The line's highest texel (the first of equals), position p.
    p = 0;
    int pu = u;
    int pv = v;
    highest = height_at(frame + v * n + u);
    for (int t = 1; t < n; ++t) {
        u = wrap(u + su, n);
        v = wrap(v + sv, n);
        float here = height_at(frame + v * n + u);
        if (here > highest) {
            highest = here;
            p = t;
            pu = u;
            pv = v;
        }
    }
    sweep_line(uint(d * n + line) * uint(n), step_len, pu, pv);
    // The opposite direction: the same line stepped the other way, from the same
    // start, so position t is this one's N - t, and the same highest texel.
    su = -su;
    sv = -sv;
    p = (n - p) & (n - 1);
    sweep_line(uint((d + half_turn) * n + line) * uint(n), step_len, pu, pv);
}
