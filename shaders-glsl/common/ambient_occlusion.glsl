// Ground-truth-style ambient occlusion in screen space (Jimenez et al. 2016, "Practical
// Real-Time Strategies for Accurate Indirect Occlusion"): for a few slices through the
// view direction, the horizon on either side of the pixel is searched in the depth
// buffer within `radius` scene units, and the cosine-weighted visibility between the two
// horizons is integrated in closed form about the normal projected into the slice. The
// frame drawn is then darkened by it (src/render/ambient_occlusion.rs).
//
// The visibility is divided by the same integral with no horizon, so a surface with
// nothing around it keeps exactly its light whatever the number of slices (with few
// slices, the projected-normal weights of the paper do not sum to one). Occluders
// farther than `radius` fade out over its last quarter, as in the CPU reference
// (tests/gpu/ambient_occlusion.rs).
//
// The body of `ambient_occlusion.frag` (single-sampled depth) and
// `ambient_occlusion_ms.frag` (sample 0 of a multisampled depth).

#ifdef MULTISAMPLED
layout(set = 0, binding = 0) uniform texture2DMS depth;
#else
layout(set = 0, binding = 0) uniform texture2D depth;
#endif
layout(set = 0, binding = 1) uniform sampler nearest_sampler;

layout(push_constant) uniform Occlusion {
    // Clip space (as drawn, jitter included) to view space.
    mat4 clip_to_view;
    // x radius (scene units), y strength (0 none, 1 the visibility itself), z the
    // turn (0..16: which of the camera's samples in the pixel the frame takes, so
    // temporal anti-aliasing averages the turns), w largest search in pixels.
    vec4 params;
    // x, y the target's size in pixels, z pixels per scene unit at distance 1,
    // w unused.
    vec4 screen;
    // x slices per pixel (1, 2, 4 or 8; below 8 the set of them turns from pixel to
    // pixel and with the turn), y steps each way along a slice, zw unused.
    vec4 search;
} occlusion;

// 1: the pass writes the visibility itself (grey) instead of darkening the frame.
layout(constant_id = 0) const bool VISIBILITY_ONLY = false;

layout(location = 0) in vec2 in_ndc;
layout(location = 0) out vec4 out_color;

const float PI = 3.14159265;

float depth_at(ivec2 p) {
    p = clamp(p, ivec2(0), ivec2(occlusion.screen.xy) - 1);
#ifdef MULTISAMPLED
    return texelFetch(sampler2DMS(depth, nearest_sampler), p, 0).r;
#else
    return texelFetch(sampler2D(depth, nearest_sampler), p, 0).r;
#endif
}

// The view-space point on the ray through pixel position `p` (pixel centres at .5) at
// depth-buffer value `z`.
// A perspective projection (jitter included) leaves x and y apart and w depending on
// the depth alone: the few products of `clip_to_view` that are not zero, not all 16.
vec3 view_point(vec2 p, float z) {
    vec2 ndc = p / occlusion.screen.xy * 2.0 - 1.0;
    mat4 m = occlusion.clip_to_view;
    vec3 v = vec3(m[0][0] * ndc.x + m[2][0] * z + m[3][0],
                  m[1][1] * ndc.y + m[2][1] * z + m[3][1],
                  m[2][2] * z + m[3][2]);
    return v / (m[2][3] * z + m[3][3]);
}

#ifdef MULTISAMPLED
// Sample 0 of the standard four-sample pattern, where its depth was taken.
const vec2 SAMPLE = vec2(0.375, 0.125);
#else
const vec2 SAMPLE = vec2(0.5);
#endif

vec3 view_at(ivec2 p) {
    return view_point(vec2(p) + SAMPLE, depth_at(p));
}

// The slices' directions: steps of whole lattice vectors, ordered so that each pair
// is square and each four spread evenly.
const vec2 LATTICE[8] = vec2[8](
    vec2(1.0, 0.0), vec2(0.0, 1.0), vec2(1.0, 1.0), vec2(-1.0, 1.0),
    vec2(2.0, 1.0), vec2(-1.0, 2.0), vec2(1.0, 2.0), vec2(-2.0, 1.0));

// Jimenez's interleaved gradient noise: different step lengths in each pixel of a
// small neighbourhood, which the frames' average (and the eye) blends.
float gradient_noise(vec2 p) {
    return fract(52.9829189 * fract(dot(p, vec2(0.06711056, 0.00583715))));
}

// The cosine-weighted visibility of one slice between horizon angles h0 <= 0 <= h1
// (from the view direction), about the projected normal at angle `n`.
float slice_visibility(float h0, float h1, float n) {
    float a = -cos(2.0 * h0 - n) + cos(n) + 2.0 * h0 * sin(n);
    float b = -cos(2.0 * h1 - n) + cos(n) + 2.0 * h1 * sin(n);
    return 0.25 * (a + b);
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    float z = depth_at(pixel);
    float visibility = 1.0;
    if (z < 1.0) {
        vec2 centre = vec2(pixel) + SAMPLE;
        vec3 p = view_point(centre, z);
        // The normal from the depth, each way from the nearer neighbour (no normal
        // across a silhouette).
        vec3 l = view_at(pixel - ivec2(1, 0)), r = view_at(pixel + ivec2(1, 0));
        vec3 u = view_at(pixel - ivec2(0, 1)), d = view_at(pixel + ivec2(0, 1));
        vec3 dx = abs(r.z - p.z) < abs(p.z - l.z) ? r - p : p - l;
        vec3 dy = abs(d.z - p.z) < abs(p.z - u.z) ? d - p : p - u;
        vec3 v = normalize(-p);
        vec3 normal = normalize(cross(dx, dy));
        if (dot(normal, v) < 0.0) {
            normal = -normal;
        }
        float radius = occlusion.params.x;
        float radius_px = min(radius * occlusion.screen.z / max(-p.z, 1e-6), occlusion.params.w);
        if (radius_px >= 1.0) {
            // The slices run along pixel lattice directions so that every step lands
            // on a pixel's centre (its sample) inside the slice: a sample beside the
            // slice would rise above a plane's horizon in it and darken flat ground.
            // Fewer than eight slices take one set of them per pixel, the sets
            // interleaved over pixels (every set in each 2x2 block with two, in each 4x2 block with one) and
            // turning with the camera's sample.
            int SLICES = int(occlusion.search.x), STEPS = int(occlusion.search.y);
            int sets = 8 / SLICES;
            int first = ((pixel.x + 2 * pixel.y + int(occlusion.params.z)) % sets) * SLICES;
            // Step lengths vary from pixel to pixel (and with the turn): even steps
            // would draw the horizon's misses as streaks beside a silhouette, where a
            // grain softens them (and the frames' average removes it).
            vec2 frame = vec2(5.588238 * occlusion.params.z);
            float shift = gradient_noise(vec2(pixel) + frame);
            float seen = 0.0, open = 0.0;
            for (int i = 0; i < SLICES; i++) {
                vec2 lattice = LATTICE[first + i];
                float lattice_px = length(lattice);
                // The slice's direction in view space: toward the point one step
                // along it at the pixel's own depth, square to the view direction.
                vec3 q = view_point(centre + lattice, z);
                vec3 along = q - p;
                along = normalize(along - v * dot(along, v));
                vec3 axis = cross(along, v);
                vec3 projected = normal - axis * dot(normal, axis);
                float length_n = length(projected);
                if (length_n < 1e-4) {
                    continue;
                }
                float cos_n = clamp(dot(projected, v) / length_n, -1.0, 1.0);
                float n = sign(dot(projected, along)) * acos(cos_n);
                // The cosine of the highest horizon each way (-1: none).
                float high_plus = -1.0, high_minus = -1.0;
                for (int s = 0; s < STEPS; s++) {
                    float t = (float(s) + shift) / float(STEPS);
                    float k = max(floor(t * t * radius_px / lattice_px), float(s) + 1.0);
                    if (k * lattice_px > radius_px) {
                        break;
                    }
                    ivec2 offset = ivec2(lattice * k);
                    for (int side = 0; side < 2; side++) {
                        ivec2 o = side == 0 ? offset : -offset;
                        ivec2 at = pixel + o;
                        vec3 w = view_at(at) - p;
                        float dist = length(w);
                        float c = dot(w, v) / max(dist, 1e-6);
                        float fade = clamp((radius - dist) / (0.25 * radius), 0.0, 1.0);
                        // Nothing is known beyond the frame's edge: no occluder there
                        // (the edge's own depth, repeated, would stand as a wall).
                        bool inside = all(greaterThanEqual(at, ivec2(0)))
                            && all(lessThan(at, ivec2(occlusion.screen.xy)));
                        fade = inside ? fade : 0.0;
                        c = mix(-1.0, c, fade);
                        if (side == 0) {
                            high_plus = max(high_plus, c);
                        } else {
                            high_minus = max(high_minus, c);
                        }
                    }
                }
                float h1 = n + min(acos(high_plus) - n, 0.5 * PI);
                float h0 = n + max(-acos(high_minus) - n, -0.5 * PI);
                seen += length_n * slice_visibility(h0, h1, n);
                open += length_n * slice_visibility(n - 0.5 * PI, n + 0.5 * PI, n);
            }
            if (open > 0.0) {
                visibility = clamp(seen / open, 0.0, 1.0);
            }
        }
    }
    if (VISIBILITY_ONLY) {
        out_color = vec4(vec3(visibility), 1.0);
    } else {
        // Black "over" the frame with alpha 1 - visibility * strength multiplies it.
        out_color = vec4(0.0, 0.0, 0.0, (1.0 - visibility) * occlusion.params.y);
    }
}
