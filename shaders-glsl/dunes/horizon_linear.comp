#version 450
// The horizon map in time linear in the tile's size (Timonen & Westerholm 2010,
// "Scalable Height Field Self-Shadowing"): the same map as horizon.comp over the whole
// periodic row. One invocation per (direction, line): on the periodic N x N tile every
// line along an axis or a diagonal is a cycle of N texels. The line is swept backwards
// once round, starting just behind its highest texel, keeping the upper convex hull of
// the heights ahead on a stack (in the `hull` buffer, N entries per invocation); the
// hull's top after popping what a texel sees past is its horizon. Texels beyond the
// highest one never set a horizon (the highest is nearer and at least as high), so one
// lap sees all that matters; the highest texel itself is walked directly.
// The CPU twin is `horizon_map_linear` in src/model/ripple_maps.rs.

layout(local_size_x = 64) in;

layout(set = 0, binding = 0, std430) readonly buffer Heights {
    float h[];
} heights;

// Two planes of vec4 as floats: directions 0-3 for every texel, then directions 4-7.
layout(set = 0, binding = 1, std430) buffer Horizon {
    float s[];
} horizon;

// Scratch: N stack entries per invocation (2N reserved), each (position along the
// line, height), so the sweep never looks a popped-to height up again.
layout(set = 0, binding = 2, std430) buffer Hull {
    vec2 at[];
} hull;

layout(push_constant) uniform Params {
    uint size;
    uint unused0;
    float height_scale;
    uint unused1;
} pc;

int n;
int start_x;
int start_y;
int dir_x;
int dir_y;

void main() {
    n = int(pc.size);
    int id = int(gl_GlobalInvocationID.x);
    if (id >= 8 * n) {
        return;
    }
    int d = id / n;
    int line = id % n;
    float angle = radians(45.0 * float(d));
    dir_x = int(round(cos(angle)));
    dir_y = int(round(sin(angle)));
    // Rows start on the left edge, columns and diagonals on the bottom one: each
    // start is on a different line, and the n of them cover the tile.
    start_x = dir_y == 0 ? 0 : line;
    start_y = dir_y == 0 ? line : 0;
    float step_len = sqrt(float(dir_x * dir_x + dir_y * dir_y));
    uint base = uint(id) * uint(2 * n);
    uint plane = d < 4 ? 0u : uint(n * n) * 4u;
    uint component = uint(d % 4);

    // The line's highest texel (the first of equals), position p from the start.
    int x = start_x;
    int y = start_y;
    int peak = 0;
    int peak_x = x;
    int peak_y = y;
    float highest = heights.h[y * n + x];
    for (int t = 1; t < n; ++t) {
        x += dir_x;
        y += dir_y;
        x = x < 0 ? x + n : (x >= n ? x - n : x);
        y = y < 0 ? y + n : (y >= n ? y - n : y);
        float v = heights.h[y * n + x];
        if (v > highest) {
            highest = v;
            peak = t;
            peak_x = x;
            peak_y = y;
        }
    }
    // Sweep backwards from the texel behind the peak (position peak + n - 1) to the
    // one after it (peak + 1), the peak itself (at peak + n) first on the hull.
    int top = 1;
    hull.at[base] = vec2(float(peak + n), highest);
    x = peak_x - dir_x;
    y = peak_y - dir_y;
    x = x < 0 ? x + n : (x >= n ? x - n : x);
    y = y < 0 ? y + n : (y >= n ? y - n : y);
    for (int t = peak + n - 1; t > peak; --t) {
        int i = y * n + x;
        float here = heights.h[i];
        float ft = float(t);
        while (top >= 2) {
            vec2 a = hull.at[base + uint(top - 1)];
            vec2 b = hull.at[base + uint(top - 2)];
            // The same expression as the brute walk's (there - here) * s / (k * len).
            float to_a = (a.y - here) * pc.height_scale / ((a.x - ft) * step_len);
            float to_b = (b.y - here) * pc.height_scale / ((b.x - ft) * step_len);
            if (to_a <= to_b) {
                top -= 1;
            } else {
                break;
            }
        }
        vec2 a = hull.at[base + uint(top - 1)];
        horizon.s[plane + uint(i) * 4u + component] =
            (a.y - here) * pc.height_scale / ((a.x - ft) * step_len);
        hull.at[base + uint(top)] = vec2(ft, here);
        top += 1;
        x -= dir_x;
        y -= dir_y;
        x = x < 0 ? x + n : (x >= n ? x - n : x);
        y = y < 0 ? y + n : (y >= n ? y - n : y);
    }

    // The peak: its horizon over the n - 1 texels ahead, walked (its own copy must not
    // count, and the hull has dropped what it would need).
    {
        float best = -3.402823e38;
        x = peak_x;
        y = peak_y;
        for (int k = 1; k < n; ++k) {
            x += dir_x;
            y += dir_y;
            x = x < 0 ? x + n : (x >= n ? x - n : x);
            y = y < 0 ? y + n : (y >= n ? y - n : y);
            float there = heights.h[y * n + x];
            best = max(best, (there - highest) * pc.height_scale / (float(k) * step_len));
        }
        horizon.s[plane + uint(peak_y * n + peak_x) * 4u + component] = best;
    }
}
