// Temporal anti-aliasing (src/frame/temporal.rs): every frame is drawn with one sample
// a pixel at one of the 16 positions of a 4x4 grid inside the pixel (the camera's
// jitter), and this pass averages it into the history, the running mean of the frames
// before, so a still camera converges on the 4x4-supersampled frame in 16 frames.
// Where the camera moved, each pixel's history is fetched where its surface point was
// in the last frame (reprojected through the depth). Where the surface under a pixel
// is not the one its history saw (a disocclusion, growth), the depths differ and the
// mean starts over from this frame.
//
// The body of `temporal.frag` (the camera moved: reprojection), `temporal_still.frag`
// (it did not, but the scene changed: the history at the same pixel, kept where the
// depth shows the same surface) and `temporal_settled.frag` (nothing moved: every
// history kept, no depth read or written).

layout(set = 0, binding = 0) uniform texture2D current;        // this frame, linear (sRGB view)
layout(set = 0, binding = 1) uniform texture2D depth;          // this frame's depth
layout(set = 0, binding = 2) uniform texture2D history;        // rgb the mean, a frames in it
layout(set = 0, binding = 3) uniform texture2D history_depth;  // the last frame's depth
layout(set = 0, binding = 4) uniform sampler clamp_sampler;
layout(set = 0, binding = 5) uniform sampler nearest_sampler;  // depth has no filter

layout(push_constant) uniform Resolve {
    // This frame's clip space (without jitter) to the last frame's.
    mat4 reproject;
    // x most frames the mean keeps (1 / (x + 1) the least weight of a new frame),
    // y how many times the depth's change to the next pixel the history's depth may
    // lie outside this frame's quad of depths (infinite: the scene stood still, keep
    // the history), z 1: start over (the first frame, a changed scene), w unused.
    vec4 params;
} resolve;

layout(location = 0) in vec2 in_ndc;

#if !defined(STILL) && !defined(SETTLED)
// The history at `uv` through a Catmull-Rom filter in five bilinear fetches (the four
// corner taps, whose weights are small, left out): bilinear resampling every frame
// would blur the mean a little more with each frame the camera moves.
vec4 history_at(vec2 uv) {
    vec2 size = vec2(textureSize(sampler2D(history, clamp_sampler), 0));
    vec2 pos = uv * size;
    vec2 centre = floor(pos - 0.5) + 0.5;
    vec2 f = pos - centre;
    vec2 f2 = f * f;
    vec2 f3 = f2 * f;
    vec2 w0 = -0.5 * f3 + f2 - 0.5 * f;
    vec2 w1 = 1.5 * f3 - 2.5 * f2 + 1.0;
    vec2 w2 = -1.5 * f3 + 2.0 * f2 + 0.5 * f;
    vec2 w3 = 0.5 * f3 - 0.5 * f2;
    vec2 w12 = w1 + w2;
    vec2 t12 = (centre + w2 / w12) / size;
    vec2 t0 = (centre - 1.0) / size;
    vec2 t3 = (centre + 2.0) / size;
    vec4 sum = textureLod(sampler2D(history, clamp_sampler), vec2(t12.x, t0.y), 0.0) * (w12.x * w0.y)
        + textureLod(sampler2D(history, clamp_sampler), vec2(t0.x, t12.y), 0.0) * (w0.x * w12.y)
        + textureLod(sampler2D(history, clamp_sampler), t12, 0.0) * (w12.x * w12.y)
        + textureLod(sampler2D(history, clamp_sampler), vec2(t3.x, t12.y), 0.0) * (w3.x * w12.y)
        + textureLod(sampler2D(history, clamp_sampler), vec2(t12.x, t3.y), 0.0) * (w12.x * w3.y);
    float weight = w12.x * w0.y + w0.x * w12.y + w12.x * w12.y + w3.x * w12.y + w12.x * w3.y;
    return clamp(sum / weight, 0.0, 1.0);
}

#endif

#ifndef SETTLED
// Variance clipping (Salvi 2016) of the reprojected history against this frame's
// five-pixel cross (a 3x3 square clipped no better in tests/gpu/anti_aliasing.rs and
// reads 4 more texels): the history is pulled along the line to the box's centre
// (Karis 2014: a clip keeps its hue where a clamp per channel would shift it) until it
// lies in the box of the neighbourhood's mean +- CLIP_SIGMA standard deviations, cut
// by its minimum and maximum. A history that passed the depth test but is not what this
// frame sees there (a surface's edge reprojected a pixel off, a highlight or a
// reflection that moved with the view) is brought to a colour this frame could hold,
// so no ghost of the last view stays in the mean; under a still camera over a scene
// that changes (growth), what changed is followed within a frame or two instead of
// trailing. Not when nothing moves: a still picture keeps its whole mean, which the
// neighbourhood of one jittered sample would cut at every edge.
const float CLIP_SIGMA = 1.0;

vec4 clip_history(vec4 history, ivec2 p) {
    vec3 h = history.rgb;
    ivec2 top = textureSize(sampler2D(current, clamp_sampler), 0) - 1;
    vec3 m1 = vec3(0.0);
    vec3 m2 = vec3(0.0);
    vec3 lo = vec3(1e9);
    vec3 hi = vec3(-1e9);
    const ivec2 TAPS[5] = ivec2[5](ivec2(0, 0), ivec2(-1, 0), ivec2(1, 0), ivec2(0, -1), ivec2(0, 1));
    for (int i = 0; i < 5; ++i) {
        ivec2 q = clamp(p + TAPS[i], ivec2(0), top);
        vec3 s = texelFetch(sampler2D(current, clamp_sampler), q, 0).rgb;
        m1 += s;
        m2 += s * s;
        lo = min(lo, s);
        hi = max(hi, s);
    }
    vec3 mean = m1 / 5.0;
    vec3 sigma = sqrt(max(m2 / 5.0 - mean * mean, vec3(0.0)));
    vec3 box_lo = max(lo, mean - CLIP_SIGMA * sigma);
    vec3 box_hi = min(hi, mean + CLIP_SIGMA * sigma);
    vec3 centre = 0.5 * (box_lo + box_hi);
    vec3 extent = 0.5 * (box_hi - box_lo) + 1e-4;
    vec3 v = h - centre;
    vec3 a = abs(v / extent);
    float m = max(a.x, max(a.y, a.z));
    return vec4(m > 1.0 ? centre + v / m : h, history.a);
}
#endif
layout(location = 0) out vec4 out_color;
layout(location = 1) out vec4 out_history;
layout(location = 2) out float out_depth;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 c = texelFetch(sampler2D(current, clamp_sampler), p, 0).rgb;
#ifdef SETTLED
    vec4 h = texelFetch(sampler2D(history, clamp_sampler), p, 0);
    bool kept = resolve.params.z < 0.5;
#else
    float d = texelFetch(sampler2D(depth, nearest_sampler), p, 0).r;
#ifdef STILL
    vec4 h = clip_history(texelFetch(sampler2D(history, clamp_sampler), p, 0), p);
    float seen = texelFetch(sampler2D(history_depth, nearest_sampler), p, 0).r;
    float expected = d;
    bool inside = true;
#else
    vec4 last = resolve.reproject * vec4(in_ndc, d, 1.0);
    vec2 uv = last.xy / last.w * 0.5 + 0.5;
    float expected = last.z / last.w;
    bool inside = last.w > 0.0 && all(greaterThanEqual(uv, vec2(0.0)))
        && all(lessThanEqual(uv, vec2(1.0)));
    float seen = textureLod(sampler2D(history_depth, nearest_sampler), uv, 0.0).r;
#endif
#ifdef STILL
    // The surface the history saw is still there if its depth lies within the depths
    // of this frame's 2x2 quad (the other three through fine derivatives: the quad is
    // shaded together, so they cost no fetch), widened by their change from pixel to
    // pixel: the samples of successive frames lie up to a pixel apart, and at an edge
    // they fall on either side of it.
    float sx = (p.x & 1) == 0 ? 1.0 : -1.0;
    float sy = (p.y & 1) == 0 ? 1.0 : -1.0;
    float ex = dFdxFine(expected);
    float ey = dFdyFine(expected);
    float exy = dFdyFine(expected + ex * sx);
    float lo = min(min(expected, expected + ex * sx), min(expected + ey * sy, expected + ex * sx + exy * sy));
    float hi = max(max(expected, expected + ex * sx), max(expected + ey * sy, expected + ex * sx + exy * sy));
    float widen = resolve.params.y * (abs(ex) + abs(ey)) + 1e-6;
    bool same = seen >= lo - widen && seen <= hi + widen;
#else
    // While the camera moves, the quad's range is too wide at an edge: a pixel the
    // move uncovered (its sample on the far side, the quad holding both) would keep
    // the near surface's history, and the neighbourhood's box (which holds both sides
    // there too) would let most of it through: the ghost a move leaves. So the history
    // must lie on this pixel's own surface, within its depth's change toward the
    // neighbour on the same side of any edge (the smaller of the two, each way).
    ivec2 top = textureSize(sampler2D(depth, nearest_sampler), 0) - 1;
    float dl = texelFetch(sampler2D(depth, nearest_sampler), max(p - ivec2(1, 0), ivec2(0)), 0).r;
    float dr = texelFetch(sampler2D(depth, nearest_sampler), min(p + ivec2(1, 0), top), 0).r;
    float dd = texelFetch(sampler2D(depth, nearest_sampler), max(p - ivec2(0, 1), ivec2(0)), 0).r;
    float du = texelFetch(sampler2D(depth, nearest_sampler), min(p + ivec2(0, 1), top), 0).r;
    float own = min(abs(dr - d), abs(d - dl)) + min(abs(du - d), abs(d - dd));
    bool same = abs(seen - expected) <= resolve.params.y * own + 1e-6;
    vec4 h = clip_history(history_at(uv), p);
#endif
    bool kept = inside && same && resolve.params.z < 0.5;
#endif
    // (A select, not a weight of 0: a history never written may hold NaNs.)
    float n = kept ? min(round(h.a * 256.0), resolve.params.x) : 0.0;
    vec3 mean = kept ? mix(h.rgb, c, 1.0 / (n + 1.0)) : c;
    out_color = vec4(mean, 1.0);
    out_history = vec4(mean, (n + 1.0) / 256.0);
#ifndef SETTLED
    out_depth = d;
#endif
}
