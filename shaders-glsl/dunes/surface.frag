#version 450
// Onoue & Nishita section 3: ripples bump mapped onto every dune quad (normals from our
// own LOD chain, tilted into the dune surface's frame), sand grain under the bump map,
// dune shadows from the precomputed shadow map (3.4), ripple shadows from the horizon
// map (3.5), sun and sky light from the atmosphere (src/model/atmosphere.rs) and its
// aerial perspective, tone mapping. Beyond the paper: the sky's light from every
// direction, hidden by the dunes (src/model/sky_light.rs), and the sand's specular
// sheen and grain glints.
#extension GL_GOOGLE_include_directive : require
#include "atmosphere.glsl"
#include "tonemap.glsl"
#include "world.glsl"

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_proj;
    vec4 camera_pos;
    vec4 sun_dir;      // xyz unit direction toward the sun
    vec4 sun_color;
    vec4 sky_color;
    vec4 ground_color;
    vec4 params;       // x exposure, z texture LOD bias (the tone-mapping operator is the pipeline's)
} frame;

// Our LOD chain as mips: rg the ripple normal's x, y; b the horizon toward the sun as
// an elevation angle over a right angle, a its spread under a mip texel (DuneTextures).
layout(set = 0, binding = 1) uniform texture2D ripple_normals;
// One period of the dune field: rg the dune normal's x, z; b the dune shadow map's sun
// margin over its range (0.5: the sun's centre on the horizon, above it lit);
// a the share of the sky the dunes leave (sky_visibility).
layout(set = 0, binding = 2) uniform texture2D dune_field;
// r the sand's grain; the bedrock's desert pavement on the same tile: g its tone over
// 2, ba its slopes (d height / dx, dz) over PAVEMENT_SLOPE_RANGE as n * 0.5 + 0.5
// (model::pavement, scene::dunes::frame::sand_grain).
layout(set = 0, binding = 3) uniform texture2D sand_grain;
const float PAVEMENT_SLOPE_RANGE = 4.0;
const float PATCH_M = 2.5;      // the pavement's patches, their size
const float PATCH_TONE = 0.35;  // and tone either side of its mean
const float PEBBLE_M = 0.032;   // a pebble's width: the grain tile over model::pavement::PEBBLES_PER_SIDE
layout(set = 0, binding = 4) uniform sampler repeat_sampler;
layout(set = 0, binding = 5) uniform texture2D dune_heights;    // one period, cell units
layout(set = 0, binding = 6) uniform texture2D detail_map;      // footprints: slopes, trodden, lit
// The paper's LOD: one ripple level per quad of the 3x3-tiled field (row-major from
// its corner at -period, -period), from the quad's projected area.
layout(set = 0, binding = 7, std430) readonly buffer Levels {
    float level[];
} quads;
// The sky's irradiance over pi (SkyIrradiance) as nine spherical harmonics,
// cosine-convolved (the whole sphere, sand below the horizon, without the circumsolar
// sky), the radiance of the sand that hides the sky from an occluded point (from a
// sunlit point and from one in a dune's shadow), and the circumsolar sky as a wide sun
// (render::dune_surface::DuneSkyLight).
layout(set = 0, binding = 8) uniform SkyLight {
    vec4 sh[9];
    vec4 occluder;
    vec4 occluder_shaded;
    vec4 circumsolar;            // rgb irradiance over pi facing it
    vec4 circumsolar_direction;  // xyz
} skylight;

// The pass's switches, fixed per pipeline (render::dune_surface::DuneSwitches): a CPU
// rasteriser runs both sides of a branch on a uniform, so a switched-off pass such as
// the per-pixel shadow march would still cost its full price.
layout(constant_id = 0) const bool LOD_ON = true;          // else ripple level 0 only
layout(constant_id = 1) const bool LOD_PER_QUAD = false;   // the paper's level per quad
layout(constant_id = 2) const bool DUNE_SHADOWS = true;
layout(constant_id = 3) const bool DUNE_SHADOWS_MARCHED = false;  // per pixel, not the map
layout(constant_id = 4) const bool RIPPLE_SHADOWS = true;
layout(constant_id = 5) const bool FOOTPRINTS = false;
layout(constant_id = 6) const bool SHADOW_MASK = false;    // the dune-shadow term alone (tests)
layout(constant_id = 7) const bool SKY_OCCLUSION = true;   // else every point sees all the sky
layout(constant_id = 8) const bool SPARKLE = true;         // specular sheen and grain glints
layout(constant_id = 9) const bool FAR = false;            // the far rings: one ripple copy
layout(constant_id = 10) const bool ENDLESS = true;        // the world beyond the period (world.glsl)
layout(constant_id = 11) const bool GRAINFLOWS = true;     // avalanche tongues on the slip faces
layout(constant_id = 12) const bool BEDROCK = true;        // the floor where the sand runs out

layout(push_constant) uniform Dune {
    vec4 tile;     // x world size of a ripple tile, y ripple strength, z grain tile size, w field period
    vec4 wind;     // xy cos/sin of the wind direction
    vec4 shadows;  // xy slopes over which the ripples fade on slip faces, z ripple-shadow softness, w the sun's angular radius (radians)
    vec4 albedo;   // rgb sand albedo
    vec4 air_extinction;  // rgb per metre at the ground, w aerosol g
    vec4 air_scattering;  // rgb Rayleigh per metre, w aerosol
    vec4 detail_rect;     // footprints' detail field: world x, z of its corner, its size
    vec4 detail;          // x the shadow map's range of sun margins (radians), y slope range of the encoding, w dune grid side
} dune;

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_transmit;
layout(location = 2) in vec3 in_inscatter;
layout(location = 3) in vec2 in_warped;   // the dune copies' warped point (world.glsl)
layout(location = 0) out vec4 out_color;

const float NEVER = 3.0e38;

// The paper's dune-shadow march (3.4) per pixel, for comparison with the precomputed
// map: crossings of the grid lines toward the sun, the periodic heightfield sampled
// there (bilinear, in cell units) against the ray's height. Returns the sun's margin
// over the horizon so found, radians within the map's range (as dune_shadow.comp).
float march_sun_margin(vec3 world, vec3 l) {
    float n = float(textureSize(sampler2D(dune_heights, repeat_sampler), 0).x);
    float cell = dune.tile.w / n;
    vec2 p = world.xz / cell;
    // From the heightfield point under the pixel (bilinear, as the map's texels start),
    // not the drawn triangle's: the two methods then differ only by the map's
    // resolution, and a grazing sun does not shadow the points where the triangulated
    // mesh dips below the heightfield.
    float y = textureLod(sampler2D(dune_heights, repeat_sampler), (p + 0.5) / n, 0.0).r + 1e-3;
    vec2 h = vec2(l.x, l.z);
    float len = max(length(h), 1e-6);
    vec2 dir = h / len;
    float rise = l.y / len;
    float range = dune.detail.x;
    float elevation = atan(rise);
    float deepest = elevation + range;
    float deep = deepest < 0.5 * PI ? tan(deepest) : NEVER;
    float horizon = -NEVER;
    vec2 next = vec2(NEVER);
    vec2 delta = vec2(NEVER);
    for (int a = 0; a < 2; ++a) {
        float d = dir[a];
        if (d > 1e-6) {
            next[a] = (floor(p[a]) + 1.0 - p[a]) / d;
            delta[a] = 1.0 / d;
        } else if (d < -1e-6) {
            next[a] = (p[a] - (ceil(p[a]) - 1.0)) / -d;
            delta[a] = -1.0 / d;
        }
    }
    for (int i = 0; i < 2 * int(n) + 2; ++i) {
        float t = min(next.x, next.y);
        if (t >= NEVER || t > n) {
            break;
        }
        vec2 q = p + dir * t;
        float ground = textureLod(sampler2D(dune_heights, repeat_sampler), (q + 0.5) / n, 0.0).r;
        horizon = max(horizon, (ground - y) / t);
        if (horizon >= deep) {
            break;
        }
        if (next.x <= next.y) {
            next.x += delta.x;
        } else {
            next.y += delta.y;
        }
    }
    return clamp(elevation - atan(horizon), -range, range);
}

// The share of the sun's disc above a straight horizon its centre stands `margin`
// radians above, the disc widened to `soft` where a pixel spans more margin than the
// sun (model::dune_shadow::sun_share).
float sun_share(float margin, float soft) {
    float u = clamp(margin / max(dune.shadows.w, soft), -1.0, 1.0);
    return 0.5 + (u * sqrt(1.0 - u * u) + asin(u)) / PI;
}

// The point of the periodic field that world point `p` shows (DesertWorld::height):
// on the middle period `p` itself; beyond it the highest of the copies, each lowered
// by how much lighter it is than the heaviest.
vec2 field_point(vec2 p, vec2 warped) {
    if (ENDLESS) {
    } else {
        return p;
    }
    float share = lattice_share(p);
    if (share <= 0.0) {
        return p;
    }
    ivec2 corner[3];
    float weight[3];
    simplex_corners(p / world.params.w, corner, weight);
    vec2 q[4];
    float w[4];
    q[0] = p;
    w[0] = 1.0 - share;
    float corner_max = max(max(weight[0], weight[1]), weight[2]);
    for (int k = 0; k < 3; ++k) {
        q[k + 1] = warped + hash3(corner[k]).xy * world.params.x;
        w[k + 1] = share * weight[k] / corner_max;
    }
    float heaviest = max(max(w[0], w[1]), max(w[2], w[3]));
    float n = float(textureSize(sampler2D(dune_heights, repeat_sampler), 0).x);
    float cell = world.params.x / n;
    vec2 best = p;
    float highest = -3.0e38;
    for (int k = 0; k < 4; ++k) {
        if (w[k] <= 0.0) {
            continue;
        }
        float sink = 1.0 - w[k] / heaviest;
        float h = textureLod(sampler2D(dune_heights, repeat_sampler), (q[k] / cell + 0.5) / n, 0.0).r * cell
            - sink * sink * world.params.z;
        if (h > highest) {
            highest = h;
            best = q[k];
        }
    }
    return best;
}

// The sky's irradiance over pi on a surface facing unit direction d
// (model::sky_light::sh_basis; the harmonics' z axis is world y).
vec3 sky_irradiance(vec3 d) {
    float x = d.x;
    float y = d.z;
    float z = d.y;
    vec3 e = skylight.sh[0].rgb * 0.282095
        + skylight.sh[1].rgb * (0.488603 * y)
        + skylight.sh[2].rgb * (0.488603 * z)
        + skylight.sh[3].rgb * (0.488603 * x)
        + skylight.sh[4].rgb * (1.092548 * x * y)
        + skylight.sh[5].rgb * (1.092548 * y * z)
        + skylight.sh[6].rgb * (0.315392 * (3.0 * z * z - 1.0))
        + skylight.sh[7].rgb * (1.092548 * x * z)
        + skylight.sh[8].rgb * (0.546274 * (x * x - y * y));
    return max(e, vec3(0.0));
}

// Sand's specular: quartz's Fresnel (index 1.54: F0 0.045, Schlick) on grains whose
// facets spread as GGX with this roughness (Walter et al. 2007). Seen toward a low
// sun it is the sheen on the slopes and the bright rim of back-lit crests.
const float SAND_F0 = 0.045;
const float SAND_ROUGHNESS = 0.45;
// Glints (after Journey's sand, Edwards 2013): facets on a lattice at least this fine
// (metres), coarsened by powers of two to the pixel's footprint so that a glint is a
// pixel or more wherever it is, as a camera sees a sunlit grain that outshines the
// rest of its pixel; a share of the cells hold a facet tilted up to GLINT_TILT from
// the surface, which mirrors the sun when it lies within GLINT_ANGLE (radians) of the
// half vector.
const float GLINT_CELL_M = 0.015;
const float GLINT_TILT = 0.35;
const float GLINT_ANGLE = 0.05;
const float GLINT_SHARE = 0.2;

float fresnel(float vh) {
    return SAND_F0 + (1.0 - SAND_F0) * pow(1.0 - vh, 5.0);
}

// Grainflows, beyond the paper: a slip face grows by avalanches that run down it as
// tongues a few decimetres wide and a few centimetres thick, lobes side by side along
// the fall line, each of sand sorted a little finer or coarser than its neighbours
// (Hunter 1977, grainflow strata). Where the ripples fade out on a slip face these
// take their place. Two staggered rows of tongues GRAINFLOW_WIDTH metres wide (and
// 0.62 of it), each waxing and waning over about GRAINFLOW_LENGTH metres down the
// face, 0.5 to 1.5 GRAINFLOW_THICKNESS metres thick, its sand up to GRAINFLOW_TONE
// lighter or darker.
const float GRAINFLOW_WIDTH = 0.7;
const float GRAINFLOW_LENGTH = 8.0;
const float GRAINFLOW_THICKNESS = 0.03;
const float GRAINFLOW_TONE = 0.16;

// The tongues at world point `p` on a face falling along unit `down` (world x, z):
// xy the slope of their surface (d height / dx, dz), z the albedo factor less 1.
// `dx`, `dy` (the point's screen derivatives) fade them out where a tongue is finer
// than a few pixels across.
vec3 grainflows(vec2 p, vec2 down, vec2 dx, vec2 dy) {
    vec2 across = vec2(-down.y, down.x);
    float pixel = abs(dot(dx, across)) + abs(dot(dy, across));
    float a = dot(p, down);
    float along_slope = 0.0;
    float across_slope = 0.0;
    float tone = 0.0;
    for (int row = 0; row < 2; ++row) {
        float width = GRAINFLOW_WIDTH * (row == 0 ? 1.0 : 0.62);
        float s = dot(p, across) / width + 0.5 * float(row);
        float cell = floor(s);
        vec3 h = hash3(ivec2(int(cell), 7 + row));
        // Across the tongue u in [-1, 1], its profile (1 - u^2)^2.
        float u = 2.0 * (s - cell) - 1.0;
        float bump = (1.0 - u * u) * (1.0 - u * u);
        float dbump = -4.0 * u * (1.0 - u * u) * 2.0 / width;
        // Down the face it waxes and wanes, each tongue at its own pace and phase.
        float wave = 6.2831853 / (GRAINFLOW_LENGTH * (0.6 + 0.8 * h.y));
        float phase = a * wave + 6.2831853 * h.x;
        float grown = 0.5 + 0.5 * sin(phase);
        float dgrown = 0.5 * cos(phase) * wave;
        float size = GRAINFLOW_THICKNESS * (0.5 + h.z);
        across_slope += size * grown * dbump;
        along_slope += size * dgrown * bump;
        tone += (2.0 * fract(h.x * 7.31 + h.z) - 1.0) * bump * grown;
    }
    float seen = 1.0 - smoothstep(0.3, 0.7, pixel / GRAINFLOW_WIDTH);
    return seen * vec3(across * across_slope + down * along_slope, GRAINFLOW_TONE * 0.5 * tone);
}

// Smooth value noise in [0, 1] on the integer lattice.
float value_noise(vec2 p) {
    vec2 i = floor(p);
    vec2 f = p - i;
    f = f * f * (3.0 - 2.0 * f);
    ivec2 c = ivec2(i);
    return mix(mix(hash3(c).x, hash3(c + ivec2(1, 0)).x, f.x),
               mix(hash3(c + ivec2(0, 1)).x, hash3(c + ivec2(1, 1)).x, f.x), f.y);
}

// A unit normal from its two bytes (`n * 0.5 + 0.5`) across the surface; the third
// component points out of it.
vec3 unpack_normal(vec2 across) {
    vec2 v = across * 2.0 - 1.0;
    return vec3(v, sqrt(max(1.0 - dot(v, v), 0.0)));
}

// One fetch of the ripple chain at `level` (the sampler clamps it to the chain's
// four), or at level 0 with LOD off.
vec4 ripple_sample(vec2 uv, float level) {
    return textureLod(sampler2D(ripple_normals, repeat_sampler), uv, LOD_ON ? level : 0.0);
}

void main() {
    // The dune's own normal and shadow from one period of the field (not the drawn
    // triangles': far away they are a simplified mesh).
    // Beyond the middle period, the copy that shows here (world.glsl); the mip level
    // from the world's own footprint, which does not jump where the copy changes.
    vec2 at = field_point(in_world.xz, in_warped);
    vec4 field = textureGrad(sampler2D(dune_field, repeat_sampler), at / dune.tile.w,
                             dFdx(in_world.xz) / dune.tile.w, dFdy(in_world.xz) / dune.tile.w);
    vec3 nd = normalize(unpack_normal(field.rg).xzy);
    // The sun's margin over the dunes' horizon from the map, and its spread over the
    // pixel (derivatives: here, before any branch).
    float map_margin = (field.b * 2.0 - 1.0) * dune.detail.x;
    float map_soft = 0.5 * fwidth(map_margin);
    // Sand over the bedrock (the wind law's floor): 1 where it lies deeper than the
    // cover depth, 0 on bare rock (render::dune_surface::Bedrock::sand); without a
    // bedrock, sand everywhere.
    float sand = 1.0;
    if (BEDROCK) {
        if (world.bedrock.y > 0.0) {
            float side = float(textureSize(sampler2D(dune_heights, repeat_sampler), 0).x);
            float cell = dune.tile.w / side;
            float ground = textureLod(sampler2D(dune_heights, repeat_sampler), (at / cell + 0.5) / side, 0.0).r * cell;
            sand = smoothstep(0.0, world.bedrock.y, ground - world.bedrock.x);
        }
    }
    // The dune's tangent frame: T along world +x in the surface, B toward world +z.
    vec3 t = normalize(vec3(1.0, 0.0, 0.0) - nd * nd.x);
    vec3 b = cross(t, nd);
    // Slip faces: where the sand lies near its angle of repose it avalanches, and an
    // avalanche leaves no ripples behind (their bump and their shadows fade out).
    float slope = length(nd.xz) / max(nd.y, 1e-3);
    float rippled = 1.0 - smoothstep(dune.shadows.x, dune.shadows.y, slope);
    // The pixel's footprint on the ground in metres (derivatives need every pixel of
    // a quad: found here, before any branch).
    vec2 world_dx = dFdx(in_world.xz);
    vec2 world_dy = dFdy(in_world.xz);
    float pixel_m = max(length(abs(world_dx) + abs(world_dy)), 1e-6);

    // Ripple tile coordinates: the tile's +x (the simulation's wind) along the wind.
    vec2 c = dune.wind.xy;
    vec2 xz = in_world.xz / dune.tile.x;
    vec2 uv = vec2(c.x * xz.x + c.y * xz.y, -c.y * xz.x + c.x * xz.y);
    // LOD: the sampler's derivative-based level selection over our own chain, or the
    // paper's level per quad from its projected area (--lod-choice quad); off: level 0.
    // (Stored as 8-bit unorm, n * 0.5 + 0.5: see DuneTextures::new.)
    float quad_level = 0.0;
    // (Nested: naga reads no expression of specialization constants.)
    if (LOD_ON) {
        if (LOD_PER_QUAD) {
            int side = 3 * int(dune.detail.w);
            ivec2 q = ivec2(floor((in_world.xz + dune.tile.w) / (dune.tile.w / dune.detail.w)));
            // Beyond the 3 x 3 periods, the far rings: the coarsest level.
            bool inside = all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, ivec2(side)));
            quad_level = inside ? quads.level[q.y * side + q.x] : 3.0;
        }
    }
    // The sampler's level, worked out here once for every copy below (their offsets
    // jump between pixels, and the level must not), less 1.25: the sampler's level
    // is isotropic, it follows the longer axis of the pixel's footprint, which on
    // sand seen at a grazing angle is several times the shorter one, and blurs the
    // ripples across it. 1.25 levels finer brings the frame nearest the
    // 4x4-supersampled one. Anisotropic filtering would be the real fix; on lavapipe
    // it is too slow to use. Under temporal anti-aliasing each frame's sample filters
    // over its share of the pixel (frame.params.z, `Jitter::lod_bias`).
    vec2 texels = vec2(textureSize(sampler2D(ripple_normals, repeat_sampler), 0));
    float footprint = max(length(dFdx(uv) * texels), length(dFdy(uv) * texels));
    float level = log2(max(footprint, 1e-8)) - 1.25 + frame.params.z;
    if (LOD_PER_QUAD) {
        level = quad_level;
    }
    vec4 r;
    if (ENDLESS) {
        // The ripple tile's copies (DesertWorld::ripple_copies): each corner of the
        // lattice around the point moves the tile by its own offset; the sharpened
        // weights leave one copy alone over most of a cell. lavapipe fetches all
        // three in every pixel even so (it runs the body of every `if` under a lane
        // mask); the far rings take the heaviest copy alone.
        ivec2 corner[3];
        float weight[3];
        simplex_corners(in_warped / world.ripples.x, corner, weight);
        float total = 0.0;
        int heaviest = 0;
        for (int k = 0; k < 3; ++k) {
            weight[k] = pow(weight[k], world.ripples.y);
            total += weight[k];
            if (weight[k] > weight[heaviest]) {
                heaviest = k;
            }
        }
        if (FAR) {
            r = ripple_sample(uv + hash3(corner[heaviest] + ivec2(world.ripples.zw)).xy, level);
        } else {
            // Blended as Heitz & Neyret (2018) blend tiles: the slopes over the root
            // of the summed squared weights, so that where two uncorrelated copies
            // mix their ripples keep their contrast instead of averaging out.
            r = vec4(0.0);
            float used = 0.0;
            float squared = 0.0;
            for (int k = 0; k < 3; ++k) {
                float w = weight[k] / max(total, 1e-30);
                if (w > 0.02) {
                    vec2 offset = hash3(corner[k] + ivec2(world.ripples.zw)).xy;
                    r += w * ripple_sample(uv + offset, level);
                    used += w;
                    squared += w * w;
                }
            }
            r /= used;
            // rg hold the slopes as n * 0.5 + 0.5.
            r.rg = 0.5 + (r.rg - 0.5) * used / sqrt(squared);
        }
    } else {
        r = ripple_sample(uv, level);
    }
    vec3 ripple = unpack_normal(r.rg);
    // Footprints (Sumner et al. 1998) in their detail field: the soles trod the ripples
    // flat, the prints' and rims' slopes tilt the normal, and their own shadow for
    // this sun darkens the hollows.
    vec2 prints = vec2(0.0);   // d height / dx, dz
    float trodden = 0.0;
    float print_lit = 1.0;
    if (FOOTPRINTS) {
        vec2 duv = (in_world.xz - dune.detail_rect.xy) / dune.detail_rect.zw;
        if (all(greaterThanEqual(duv, vec2(0.0))) && all(lessThanEqual(duv, vec2(1.0)))) {
            vec4 d = texture(sampler2D(detail_map, repeat_sampler), duv, frame.params.z);
            // 128 is flat: (b - 128) / 127 of the slope range.
            prints = (d.xy * 255.0 - 128.0) / 127.0 * dune.detail.y;
            trodden = d.z;
            print_lit = d.w;
        }
    }
    ripple = normalize(vec3(ripple.xy * dune.tile.y * (1.0 - trodden) * rippled * sand, max(ripple.z, 1e-3)));
    // Back from tile to world orientation, then into the dune frame (tilted normal).
    vec2 rxy = vec2(c.x * ripple.x - c.y * ripple.y, c.y * ripple.x + c.x * ripple.y);
    vec3 n = normalize(t * rxy.x + b * rxy.y + nd * ripple.z);
    // The grainflows where the ripples fade (their slopes added to the prints').
    float tongue_tone = 0.0;
    if (GRAINFLOWS) {
        if (rippled < 1.0) {
            vec3 g = grainflows(in_world.xz, normalize(nd.xz + vec2(1e-6, 0.0)), world_dx, world_dy);
            prints += (1.0 - rippled) * sand * g.xy;
            tongue_tone = (1.0 - rippled) * sand * g.z;
        }
    }
    // The sand's grain, and on the bedrock its pebbles (their slopes join the prints').
    vec4 grain = texture(sampler2D(sand_grain, repeat_sampler), in_world.xz / dune.tile.z,
                         frame.params.z);
    float pebble_tone = 1.0;
    if (BEDROCK) {
        // Where a pixel spans more than a pebble the tile's mips still hold its
        // repeat (44 pebbles every GRAIN_TILE_M, 1.4 m), which beats with the pixels: the
        // pebbles fade into their mean before.
        float seen = (1.0 - sand) * (1.0 - smoothstep(0.15, 0.6, pixel_m / PEBBLE_M));
        prints += seen * (grain.ba * 2.0 - 1.0) * PAVEMENT_SLOPE_RANGE;
        // Metres apart, the pavement's patches (more or fewer pebbles, sand
        // streaks): value noise at two scales turned against each other, faded
        // where a pixel spans a patch.
        float patchy = 1.0 - smoothstep(0.5, 1.0, pixel_m / PATCH_M);
        float patches = 1.0 + PATCH_TONE * patchy
            * (value_noise(mat2(0.8, 0.6, -0.6, 0.8) * in_world.xz / PATCH_M)
               + 0.5 * value_noise(mat2(0.6, -0.8, 0.8, 0.6) * in_world.xz / (3.7 * PATCH_M)) - 0.75);
        pebble_tone = mix(1.0, grain.g * 2.0, seen) * patches;
    }
    // The prints' slopes in world x, z, tilted into the dune's frame like the ripples.
    n = normalize(n - t * prints.x - b * prints.y);

    vec3 l = normalize(frame.sun_dir.xyz);
    float lit = 1.0;
    if (DUNE_SHADOWS) {
        if (DUNE_SHADOWS_MARCHED) {
            float margin = march_sun_margin(vec3(at.x, in_world.y, at.y), l);
            lit *= sun_share(margin, 0.5 * fwidth(margin));
        } else {
            // The map covers one period of the field and tiles with it; its margins
            // interpolate to straight edges between texels, as soft as the sun's disc.
            lit *= sun_share(map_margin, map_soft);
        }
    }
    // The circumsolar sky is hidden by the dunes that hide the sun (the ripples'
    // shadows are narrower than it).
    float lit_dune = lit;
    if (SHADOW_MASK) {
        // The dune-shadow term alone (red), marked as terrain (blue, no green): the
        // map (its own texels, not their mips) and the per-pixel march compared pixel
        // by pixel.
        if (DUNE_SHADOWS) {
            if (DUNE_SHADOWS_MARCHED) {
            } else {
                float texel = textureLod(sampler2D(dune_field, repeat_sampler), at / dune.tile.w, 0.0).b;
                lit = sun_share((texel * 2.0 - 1.0) * dune.detail.x, 0.0);
            }
        }
        out_color = vec4(lit, 0.0, 1.0, 1.0);
        return;
    }
    if (RIPPLE_SHADOWS) {
        // The horizon map (Max 1988) toward the sun, baked per sun (the tile's
        // azimuth of the sun seen from flat ground; over a sloping dune the sun's
        // azimuth in the surface turns a little, which this leaves out), against the
        // sun's elevation over this point's dune surface, in angles. Where a pixel
        // covers many ripples (a coarser mip) the horizons it covers spread, and so
        // does the transition: the shadowed share of the pixel, not all or nothing;
        // where ripples change faster than pixels, likewise (fwidth).
        vec3 lt = vec3(dot(l, t), dot(l, b), dot(l, nd));
        float elevation = atan(lt.z, max(length(lt.xy), 1e-4));
        float horizon = r.b * (0.5 * PI);
        float soft = dune.shadows.z + r.a * (0.5 * PI) + 2.0 * fwidth(horizon);
        lit *= mix(1.0, smoothstep(horizon - soft, horizon + soft, elevation), rippled * sand);
    }

    lit *= print_lit;
    vec3 albedo = mix(world.bedrock_albedo.rgb * pebble_tone, dune.albedo.rgb * (1.0 + tongue_tone), sand)
        * (0.8 + 0.4 * grain.r);
    // Sky light: the sky's irradiance from the harmonics, scaled by the share of the
    // sky the point sees; where a dune hides the sky, its sand lights the point
    // instead: in a dune's shadow the sand toward the sun is that dune's shaded lee.
    vec3 ambient = sky_irradiance(n);
    if (SKY_OCCLUSION) {
        vec3 occluder = mix(skylight.occluder_shaded.rgb, skylight.occluder.rgb, lit);
        ambient = field.a * ambient + (1.0 - field.a) * (0.5 + 0.5 * n.y) * occluder;
    }
    ambient += skylight.circumsolar.rgb * max(dot(n, skylight.circumsolar_direction.xyz), 0.0)
        * lit_dune;
    float nl = max(dot(n, l), 0.0);
    vec3 hdr = albedo * (frame.sun_color.rgb * nl * lit + ambient);
    // Only where the sun reaches (a GPU skips it over the dune shadows, coherent over
    // many pixels; lavapipe runs it under a lane mask everywhere). (The glints'
    // footprint is found outside the branch: derivatives need every pixel of a quad.)
    if (SPARKLE && nl * lit > 0.0) {
        // sun_color is the sunlight's irradiance over pi: a BRDF f gives f pi sun_color n.l.
        vec3 v = normalize(frame.camera_pos.xyz - in_world);
        vec3 h = normalize(l + v);
        float nv = max(dot(n, v), 1e-3);
        float nh = max(dot(n, h), 0.0);
        float vh = max(dot(v, h), 0.0);
        float a2 = SAND_ROUGHNESS * SAND_ROUGHNESS;
        float dd = nh * nh * (a2 - 1.0) + 1.0;
        float k = 0.5 * SAND_ROUGHNESS;
        // GGX D times Smith-Schlick G over 4 n.l n.v, times n.l: the n.l cancels.
        float specular = a2 / (PI * dd * dd) * fresnel(vh) / ((nl * (1.0 - k) + k) * (nv * (1.0 - k) + k) * 4.0);
        // A glint mirrors the sun's irradiance into the cone of GLINT_ANGLE.
        float level = max(ceil(log2(pixel_m / GLINT_CELL_M)), 0.0);
        vec3 cell = hash3(ivec2(floor(in_world.xz / (GLINT_CELL_M * exp2(level))))
                          + ivec2(int(level) * 7919, 0));
        vec3 facet = normalize(n + GLINT_TILT * (t * (2.0 * cell.x - 1.0) + b * (2.0 * cell.y - 1.0)));
        // Quartz grains glint; the rock's varnished gravel does not.
        float mirror = sand * step(cell.z, GLINT_SHARE)
            * smoothstep(cos(GLINT_ANGLE), cos(0.5 * GLINT_ANGLE), dot(facet, h));
        const float CONE = 2.0 * PI * (1.0 - cos(GLINT_ANGLE));
        hdr += frame.sun_color.rgb * (PI * lit * (specular * nl + fresnel(vh) / CONE * mirror * nl));
    }
    // Aerial perspective (surface.vert).
    hdr = hdr * in_transmit + in_inscatter;
    out_color = vec4(tonemap(hdr, frame.params.x), 1.0);
}
