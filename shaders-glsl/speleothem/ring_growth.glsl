// One growth pass (Tortelli & Walter 2009, section 4.1) for one input triangle, shared
// by the geometry shader (`ring_growth.geom`, the paper's path) and the compute path
// (`ring_growth.comp`) and by the append-only GS path. Every input triangle is
// re-emitted with its vertex IDs incremented by 2; a triangle of the growth front (all
// IDs <= 0 before the increment) also emits its copy in the new ring band,
// v' = v + height * g + r * N (+ wind), with the original IDs, and one triangle joining
// the old tip ring to it. The CPU twin is `grow_pass` in src/model/speleothem.rs: read
// both together.
//
// The growth plan: 4 vec4 per (pass, speleothem), pass-major (GrowthPlan::gpu_steps).
//   [0] height, radius step, thicken, action (0 idle, 1 grow, 2 close, 3 join)
//   [1] wind displacement xyz, growth direction sign (y)
//   [2] flank deposit vd, flank angle, flank half-width, thickening accumulated
//       through this pass
//   [3] target xyz (apex or meeting-ring centre), meeting-ring radius
// The including shader reads it through `plan_step`.
#ifndef SEDIMENT_RING_GROWTH_GLSL
#define SEDIMENT_RING_GROWTH_GLSL

struct V {
    vec4 pos_id;
    vec4 normal_sp;
    vec4 extra;
};

const float TAU = 6.28318530717958647692;

// Which part of a pass's output a draw captures. The paper's pass emits the whole next
// mesh (EMIT_ALL). The append-only passes split it: EMIT_FRONT emits only the next
// front band (the one part that changes), EMIT_FROZEN only what leaves the front this
// pass (the old band and its link to the new one), appended once to the mesh.
const uint EMIT_ALL = 0u;
const uint EMIT_FRONT = 1u;
const uint EMIT_FROZEN = 2u;

// Writes one output vertex; defined by the including shader (the GS emits it to
// transform feedback, the compute path stores it). Triangles go out as 3 consecutive
// calls, each followed by `end_triangle` (the GS ends its strip there).
void emit(V v);
void end_triangle();
// Step `i` of the growth plan; defined by the including shader.
vec4 plan_step(uint i);

struct Target {
    uint mode;
    // EMIT_FROZEN: the speleothem's thickening accumulated through this pass, and
    // 2 (pass + 1): subtracted so the draw brings a frozen vertex up to date with the
    // current totals (see `ring_growth_append.rs`), never re-streaming it.
    float accumulated;
    float id_shift;
};

V moved(V v, vec3 offset, float id_step) {
    return V(vec4(v.pos_id.xyz + offset, v.pos_id.w + id_step), v.normal_sp, v.extra);
}

// `v` thickened (moved along its radial normal) and its ID stepped: a triangle off a
// working front, behind it (`id_step` 2) or idle on it (0).
V thickened(V v, float thicken, float id_step) {
    return moved(v, v.normal_sp.xyz * thicken, id_step);
}

// Whether `t` is on the growth front (all its IDs <= 0).
bool on_front(V t[3]) {
    return t[0].pos_id.w <= 0.0 && t[1].pos_id.w <= 0.0 && t[2].pos_id.w <= 0.0;
}

// The first of the 4 plan steps of `t`'s speleothem in pass `pass_index`.
uint plan_base(V t[3], uint pass_index, uint speleothem_count) {
    return 4u * (pass_index * speleothem_count + uint(t[0].normal_sp.w + 0.5));
}

// The flank deposit's profile: 1 at `angle`, 0 beyond +-`width` radians.
float flank_profile(vec3 n, float angle, float width) {
    float theta = atan(n.z, n.x);
    float d = mod(abs(theta - angle), TAU);
    d = min(d, TAU - d);
    float x = d / width;
    return max(1.0 - x * x, 0.0);
}

// `a`, `b` or `c` for `s` 0, 1 or 2, member by member (naga rejects a select between
// structs).
V pick(uint s, V a, V b, V c) {
    return V(s == 0u ? a.pos_id : (s == 1u ? b.pos_id : c.pos_id),
             s == 0u ? a.normal_sp : (s == 1u ? b.normal_sp : c.normal_sp),
             s == 0u ? a.extra : (s == 1u ? b.extra : c.extra));
}

// Emits one vertex of a triangle the draw takes (EMIT_FROZEN: brought up to date).
void put(Target to, V v) {
    if (to.mode == EMIT_FROZEN) {
        v.pos_id = vec4(v.pos_id.xyz - v.normal_sp.xyz * to.accumulated, v.pos_id.w - to.id_shift);
    }
    emit(v);
}

// One growth pass over one input triangle `t`, emitting (through `emit`) the part of
// its output that `mode` selects (the plan read through `plan_step`).
//
// The output is up to three triangles, built into fixed slots and emitted in this
// order where the mode takes them:
//   0: a triangle behind the front, moved on (EMIT_ALL only), or the old front
//      re-emitted (EMIT_ALL, EMIT_FROZEN);
//   1: the new front band, or a front waiting out the pass (EMIT_ALL, EMIT_FRONT);
//   2: the link from the old tip ring to the new band, the apex or the meeting ring
//      (EMIT_ALL, EMIT_FROZEN).
// Why slots and not an emit where each vertex is made: llvmpipe (Mesa 22.3) runs the
// body of every `if` whether or not an invocation takes it (masked), so each emit in
// the source costs on every triangle, and an emit in every branch would multiply them.
void grow_triangle(V t[3], uint pass_index, uint speleothem_count, uint segments, uint mode) {
    uint base = plan_base(t, pass_index, speleothem_count);
    vec4 s0 = plan_step(base);
    float thicken = s0.z;
    V slot[9];
    bool take[3] = bool[3](false, false, false);
    Target to = Target(mode, 0.0, 2.0 * float(pass_index + 1u));

    bool front = on_front(t);
    uint action = uint(s0.w + 0.5);
    if (!front) {
        // Behind the front (most triangles): only the paper's pass re-streams it, and
        // it needs nothing of the plan but the thickening.
        for (int k = 0; k < 3; ++k) {
            slot[k] = thickened(t[k], thicken, 2.0);
        }
        take[0] = mode == EMIT_ALL;
    } else if (action == 0u) {
        // A front waiting out a pass (PIL 0, a stalagmite before dripping starts, or
        // stopped at the cave boundary) stays the front: IDs unchanged, so it grows
        // again when the parameters allow.
        for (int k = 0; k < 3; ++k) {
            slot[3 + k] = thickened(t[k], thicken, 0.0);
        }
        take[1] = mode != EMIT_FROZEN;
    } else {
        vec4 s1 = plan_step(base + 1u);
        vec4 s2 = plan_step(base + 2u);
        vec4 s3 = plan_step(base + 3u);
        float height = s0.x;
        float radius = s0.y;
        vec3 wind = s1.xyz;
        float sign = s1.w;
        vec3 g = vec3(0.0, sign, 0.0);
        to.accumulated = s2.w;

        // The old front, re-emitted; a flank deposit bumps its tip ring (ID -1) only.
        V old[3];
        for (int k = 0; k < 3; ++k) {
            V v = t[k];
            vec3 bump = vec3(0.0);
            if (action == 1u && v.pos_id.w < -0.5 && s2.x > 0.0) {
                bump = v.normal_sp.xyz * (s2.x * flank_profile(v.normal_sp.xyz, s2.y, s2.z));
            }
            old[k] = moved(v, bump, 2.0);
            slot[k] = old[k];
        }
        take[0] = mode != EMIT_FRONT;

        // Roles: A = (b_i, t_i, b_i+1) has two base-ring (ID 0) vertices, B = (b_i+1,
        // t_i, t_i+1) has two tip-ring (ID -1) vertices; order each pair by segment.
        int base_k[3];
        int tip_k[3];
        int nb = 0;
        int nt = 0;
        for (int k = 0; k < 3; ++k) {
            if (t[k].pos_id.w > -0.5) { base_k[nb++] = k; } else { tip_k[nt++] = k; }
        }
        bool is_a = nb == 2;
        // The pair to order (A: its base vertices, B: its tip vertices); x comes first
        // when y is the next segment round. Segments are below `segments`, so the wrap
        // is a compare (an integer % is eight scalar divisions on llvmpipe).
        int x = is_a ? base_k[0] : tip_k[0];
        int y = is_a ? base_k[1] : tip_k[1];
        uint after_x = uint(t[x].extra.x + 0.5) + 1u;
        bool xy = (after_x == segments ? 0u : after_x) == uint(t[y].extra.x + 0.5);
        int first = xy ? x : y;
        int second = xy ? y : x;
        int b_i = is_a ? first : -1;
        int b_i1 = is_a ? second : base_k[0];
        int t_i = is_a ? tip_k[0] : first;
        int t_i1 = is_a ? -1 : second;

        // The link's three corners before ordering: A triangles reach two new
        // vertices (b_i, b_i+1), B triangles one (b_i+1) beside the old t_i+1.
        V far[3];
        bool link = false;
        if (action == 1u) {
            // The new band: v' = v + height g + r N + wind, original IDs.
            for (int k = 0; k < 3; ++k) {
                V v = t[k];
                vec3 p = v.pos_id.xyz + g * height + v.normal_sp.xyz * radius + wind;
                far[k] = V(vec4(p, v.pos_id.w), v.normal_sp,
                           vec4(v.extra.x, v.extra.y + height, radius / height, v.extra.w + 1.0));
                slot[3 + k] = far[k];
            }
            take[1] = mode != EMIT_FROZEN;
            link = true;
        } else if (action == 2u) {
            // Close the tip: a cone from the old tip ring to one apex point (B only).
            V tv = t[t_i];
            V apex = V(vec4(s3.xyz, 0.0), vec4(0.0, 0.0, 0.0, tv.normal_sp.w),
                       vec4(tv.extra.x, tv.extra.y + height, -1.0, tv.extra.w + 1.0));
            far[0] = apex;
            far[1] = apex;
            far[2] = apex;
            link = !is_a;
        } else if (action == 3u) {
            // Column: join the old tip ring to the meeting ring both fronts share.
            for (int k = 0; k < 3; ++k) {
                V v = t[k];
                vec3 p = s3.xyz + v.normal_sp.xyz * s3.w;
                far[k] = V(vec4(p, 0.0), v.normal_sp,
                           vec4(v.extra.x, v.extra.y + abs(s3.y - v.pos_id.y), 0.0, v.extra.w + 1.0));
            }
            link = true;
        }
        // Triangles are built counter-clockwise for growth along +y; stalactites (-y)
        // mirror the band, so their triangles are reversed to keep facing outward.
        V b;
        V c;
        if (is_a) {
            b = far[b_i];
            c = far[b_i1];
        } else {
            b = far[b_i1];
            c = old[t_i1];
        }
        slot[6] = old[t_i];
        // (An if, not `?:`: naga rejects a select between structs.)
        if (sign < 0.0) {
            slot[7] = c;
            slot[8] = b;
        } else {
            slot[7] = b;
            slot[8] = c;
        }
        take[2] = link && mode != EMIT_FRONT;
    }

    // The taken triangles in slot order, from one place in a loop that runs as often
    // as the most-emitting lane (every lane through each, masked, on llvmpipe): a
    // triangle off the front takes one slot, so most groups of lanes emit 3 vertices
    // here, not 9 (the geometry stage stores every emit for all 8 lanes, taken or
    // not). The slot is picked by selects on constant indices, so the slots stay
    // registers.
    uint t0 = uint(take[0]);
    uint t1 = uint(take[1]);
    uint count = t0 + t1 + uint(take[2]);
    // A do-while under an if: tested at its end, the loop stops when no lane goes on,
    // where a `for` tests at the top of an iteration that then runs masked.
    if (count > 0u) {
        uint k = 0u;
        do {
            // The k-th taken slot: 0, 1 or 2.
            uint s = k == 0u ? (t0 == 1u ? 0u : (t1 == 1u ? 1u : 2u))
                             : (k == 1u && t0 + t1 == 2u ? 1u : 2u);
            put(to, pick(s, slot[0], slot[3], slot[6]));
            put(to, pick(s, slot[1], slot[4], slot[7]));
            put(to, pick(s, slot[2], slot[5], slot[8]));
            end_triangle();
            k += 1u;
        } while (k < count);
    }
}

// How many vertices `grow_triangle` emits for `t`, without building them: 3 for a
// triangle off the front or of an idle speleothem; on the front, 9 when a band grows,
// 6 when a B triangle closes a tip or any front triangle joins a column, else 3.
uint output_count(V t[3], uint pass_index, uint speleothem_count) {
    uint action = uint(plan_step(plan_base(t, pass_index, speleothem_count)).w + 0.5);
    if (!on_front(t) || action == 0u) {
        return 3u;
    }
    uint on_base = 0u;
    for (int k = 0; k < 3; ++k) {
        if (t[k].pos_id.w > -0.5) {
            on_base += 1u;
        }
    }
    bool is_a = on_base == 2u;
    if (action == 1u) {
        return 9u;
    }
    if (action == 2u) {
        return is_a ? 3u : 6u;
    }
    return 6u;
}


#endif
