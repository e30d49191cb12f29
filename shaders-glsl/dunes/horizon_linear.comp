#version 450
// The horizon map in time linear in the tile's size (Timonen & Westerholm 2010,
// "Scalable Height Field Self-Shadowing"): the same map as horizon.comp over the whole
// periodic row. On the periodic N x N tile every line of texels along one of the
// directions (axes, diagonals and, with 16, the knight's moves (2, 1) between them) is
// a cycle of N texels. One invocation per line sweeps it backwards once round,
// starting just behind its highest texel, keeping the upper convex hull of the heights
// ahead; the hull's top after popping what a texel sees past is its horizon. Texels
// beyond the highest one never set a horizon (the highest is nearer and at least as
// high), so one lap sees all that matters; the highest texel's own horizon (below zero:
// everything else is lower) is taken as the sweep passes.
//
// What makes it fast on llvmpipe, which reads or writes a storage buffer for 8
// invocations as a loop over the 8 (measured in one process, 1024 x 1024 noise, 8
// directions: 175 ms before these, about 80 after): the hull's top eight entries live
// in registers and memory is touched only to spill or refill two of them (a window
// of four: 10 % slower; the top two, as before: twice as slow); each invocation writes
// its own line position by position (the map is stored by line: `planes_from_lines`
// in src/render/ripple_maps.rs reorders it for the CPU); and lines steeper in y read a
// transposed copy of the heights, so that columns, like rows, step one texel further
// in memory.
// Mesa 22.3's llvmpipe runs the body of an `if` even when no invocation takes it
// (masked), so every load or store in the sweep's loop costs its 8-step loop on every
// step, taken or not: the spill and the refill are one vec4 (two entries) each.
// 1024 x 1024 x 16 directions, variants alternated in one process (medians): four
// entries moved as four vec2 loads and four stores 203 ms against 158 for this; four
// moved as two vec4s 266 against 213 (a slower hour); two spilled at a window of 4, 6
// or 10 entries 281, 230, 238 against 213. Without hull memory at all (wrong, only to
// size it) 150 against 167: the rest is the hull's registers, the height read and the
// horizon written each step (about 20 ms each), and writing four horizons as one vec4
// gained nothing.
// The CPU twin is `horizon_map_linear_along` in src/model/ripple_maps.rs.

layout(local_size_x = 64) in;

// The heights (row-major), then the same heights transposed.
layout(set = 0, binding = 0, std430) readonly buffer Heights {
    float h[];
} heights;

// By line: direction d's line l at (d * N + l) * N, position by position from the
// line's start.
layout(set = 0, binding = 1, std430) buffer Horizon {
    float s[];
} horizon;

// The hull stacks below the entries held in registers: N entries for each invocation
// of a dispatch (a stack never holds more than a lap), two entries (position, height)
// to a vec4.
layout(set = 0, binding = 2, std430) buffer Hull {
    vec4 at[];
} hull;

layout(push_constant) uniform Params {
    uint size;
    // 8 (axes and diagonals) or 16 (and the knight's moves).
    uint directions;
    float height_scale;
    // The direction of this dispatch's first line (dispatches share the hull buffer).
    uint first_direction;
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

int wrap(int i, int n) {
    return i < 0 ? i + n : (i >= n ? i - n : i);
}

void main() {
    int n = int(pc.size);
    int id = int(gl_GlobalInvocationID.x);
    int d = int(pc.first_direction) + id / n;
    if (d >= int(pc.directions)) {
        return;
    }
    int line = id % n;
    ivec2 dir = direction16(pc.directions == 8u ? 2 * d : d);
    // The line's frame: the heights transposed where the direction is steeper in y,
    // so that a line steps +-1 along rows (axes: one texel further in memory) or
    // +-1 row and su along it (diagonals, knight's moves).
    bool transposed = abs(dir.y) > abs(dir.x);
    int su = transposed ? dir.y : dir.x;
    int sv = transposed ? dir.x : dir.y;
    int frame = transposed ? n * n : 0;
    float step_len = sqrt(float(dir.x * dir.x + dir.y * dir.y));
    // Along a row, line k is row k; across rows, the line through (k, 0).
    int u = sv == 0 ? 0 : line;
    int v = sv == 0 ? line : 0;
    // This invocation's hull stack and its line of the map, position by position.
    uint hull_base = uint(id) * uint(n);
    uint out_base = uint(d * n + line) * uint(n);

    // The line's highest texel (the first of equals), position p.
    int p = 0;
    int pu = u;
    int pv = v;
    float highest = heights.h[frame + v * n + u];
    for (int t = 1; t < n; ++t) {
        u = wrap(u + su, n);
        v = wrap(v + sv, n);
        float here = heights.h[frame + v * n + u];
        if (here > highest) {
            highest = here;
            p = t;
            pu = u;
            pv = v;
        }
    }

    // One lap backwards from the texel behind the peak (position p + N - 1) to the
    // one after it (p + 1), the peak's copy at p + N first on the hull.
    // The hull's top eight entries in registers (r0 the top; w of them valid), the
    // m below them in memory, moved two at a time (so m stays even and a pair is one
    // aligned vec4): memory is touched only when the window is full before a push (two
    // spilled) or down to one entry with more below (two refilled), so a hull that
    // grows and shrinks by a few entries, as it does over ripples and noise, stays in
    // registers.
    vec2 r0 = vec2(float(p + n), highest);
    vec2 r1 = vec2(0.0);
    vec2 r2 = vec2(0.0);
    vec2 r3 = vec2(0.0);
    vec2 r4 = vec2(0.0);
    vec2 r5 = vec2(0.0);
    vec2 r6 = vec2(0.0);
    vec2 r7 = vec2(0.0);
    int w = 1;
    int m = 0;
    // The peak's own horizon, the largest (h - highest) / k, kept as a fraction.
    float best_rise = -3.402823e38;
    float best_k = 1.0;
    u = pu;
    v = pv;
    for (int t = p + n - 1; t > p; --t) {
        u = wrap(u - su, n);
        v = wrap(v - sv, n);
        float here = heights.h[frame + v * n + u];
        float ft = float(t);
        // Pop the top while the one below it is seen at least as steeply (slopes
        // compared by cross-multiplying: both distances are positive).
        // The pops touch registers only; where a line's window runs down to its top
        // with more below, two entries come back from memory and the pops go on.
        bool refill;
        do {
            while (w >= 2 && (r0.y - here) * (r1.x - ft) <= (r1.y - here) * (r0.x - ft)) {
                r0 = r1;
                r1 = r2;
                r2 = r3;
                r3 = r4;
                r4 = r5;
                r5 = r6;
                r6 = r7;
                w -= 1;
            }
            refill = w == 1 && m > 0;
            if (refill) {
                // The pair below the window, the top last.
                m -= 2;
                vec4 pair = hull.at[(hull_base + uint(m)) / 2u];
                r2 = pair.xy;
                r1 = pair.zw;
                w = 3;
            }
        } while (refill);
        // The same expression as the brute walk's (there - here) * s / (k * len).
        horizon.s[out_base + uint(t >= n ? t - n : t)] =
            (r0.y - here) * pc.height_scale / ((r0.x - ft) * step_len);
        float k = float(t - p);
        if ((here - highest) * best_k > best_rise * k) {
            best_rise = here - highest;
            best_k = k;
        }
        if (w == 8) {
            // The window's bottom two onto memory, the lower first.
            hull.at[(hull_base + uint(m)) / 2u] = vec4(r7, r6);
            m += 2;
            w = 6;
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
    }
    horizon.s[out_base + uint(p)] = best_rise * pc.height_scale / (best_k * step_len);
}
