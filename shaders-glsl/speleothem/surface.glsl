// Wet calcite (Tortelli & Walter 4.2): the lamp's soft shadows (`shadow.glsl`), normal
// mapping for ruggedness (a mip chain, its strength `--bump`, Toksvig's factor where
// the filtered normals spread), the lamp, a film of water over the calcite (a clear
// coat reflecting the chamber, lamp included, from the cube map sediment rendered of
// it, through Schlick's Fresnel for water; `--environment` its strength), tone mapping
// (Ashikhmin 2002 by default), and light through the calcite (`--subsurface`): the
// lamp seen through thin tips, straws and edges. The body of `surface.frag` (shaded once per pixel) and
// `surface_per_sample.frag` (once per sample: the bump detail and the highlights it
// makes alias inside the silhouette, where multisampling alone does not reach).
#include "lighting.glsl"
#include "tonemap.glsl"
#include "shadow.glsl"
#include "wet_film.glsl"

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_proj;
    vec4 camera_pos;
    vec4 sun_dir;
    vec4 sun_color;
    vec4 sky_color;
    vec4 ground_color;
    vec4 params;
} frame;

layout(set = 0, binding = 2) uniform texture2D normal_map;
layout(set = 0, binding = 3) uniform sampler normal_sampler;
layout(set = 0, binding = 4) uniform textureCube environment;
layout(set = 0, binding = 5) uniform sampler environment_sampler;

layout(push_constant) uniform Surface {
    vec4 params;
    vec4 look;
    vec4 light;
} surface;

// `sample`-interpolated inputs make the stage run once per sample.
#ifdef PER_SAMPLE
#define SHADED sample in
#else
#define SHADED in
#endif
layout(location = 0) SHADED vec3 in_world;
layout(location = 1) SHADED vec3 in_normal;
layout(location = 2) SHADED vec3 in_tangent;
layout(location = 3) SHADED vec3 in_uv;
layout(location = 4) SHADED vec3 in_color;
// xyz a point on the speleothem's axis (its tip ring's centre); w 1 on its wall, 0 on
// a cap.
layout(location = 5) SHADED vec4 in_axis;

layout(location = 0) out vec4 out_color;

const float SHININESS = 48.0;
// The water film (`wet_film.glsl`): its GGX roughness (still water over the rings, not
// a mirror: the drip's ripples), and the share of the normal map's relief its surface
// keeps (water fills the finer hollows).
const float FILM_ALPHA = 0.015;
const float FILM_RELIEF = 0.15;

// Calcite's mean free path for light, in scene units (metres): how far light crosses
// the crystals before it is scattered or absorbed. A few centimetres of speleothem
// calcite let a lamp through (the glow of a backlit soda straw); a pillar does not.
const float CALCITE_FREE_PATH = 0.015;

// The lamp's light that crosses the speleothem to come out at `world` (`--subsurface`),
// per unit of its radiance there, before the albedo: thickness-based transmission.
// Lamp light falls on the far side of the ring (cosine `entering` = -n.l there and
// here alike, the chord being symmetric) and crosses it along l: for a ring of radius
// r, with radial normal n and l_perp the part of l across the vertical axis, the chord
// is 2 r (-n.l) / |l_perp|^2 long, and exp(-chord / CALCITE_FREE_PATH) of the light
// gets through and leaves diffusely. The ring's radius is the distance from the tip's
// axis along n: exact while the speleothem grows straight down or up (wind slants
// the rings' centres, and the radius is then off by the slant). `chord` is returned
// for the far side's shadow test.
float transmitted(vec3 world, vec3 n, vec3 l, vec4 axis, out float chord) {
    chord = 0.0;
    vec2 nr = n.xz;
    float nr_len = length(nr);
    float lp2 = dot(l.xz, l.xz);
    if (axis.w < 0.5 || nr_len < 1e-3 || lp2 < 1e-4) {
        return 0.0;
    }
    nr /= nr_len;
    float entering = -dot(nr, l.xz);
    if (entering <= 0.0) {
        return 0.0;
    }
    float radius = max(dot(world.xz - axis.xz, nr), 0.0);
    chord = 2.0 * radius * entering / lp2;
    return entering * exp(-chord / CALCITE_FREE_PATH);
}

void main() {
    vec3 n = normalize(gl_FrontFacing ? in_normal : -in_normal);
    vec3 geometric = n;
    vec3 t = normalize(in_tangent - n * dot(in_tangent, n));
    vec3 b = cross(n, t);
    // The seam-free u (Tarini): the copy whose screen-space change is smaller.
    vec2 uv_a = in_uv.xz;
    vec2 uv_b = in_uv.yz;
    bool a = fwidth(uv_a.x) <= fwidth(uv_b.x);
    vec2 uv = a ? uv_a : uv_b;
    vec2 dx = a ? dFdx(uv_a) : dFdx(uv_b);
    vec2 dy = a ? dFdy(uv_a) : dFdy(uv_b);
#ifdef PER_SAMPLE
    // Each of the n samples stands for 1/n of the pixel: the normal map is filtered
    // over that much, so the n shadings the resolve averages see the bump detail the
    // pixel holds (measured in tests/gpu/anti_aliasing.rs).
    float footprint = surface.look.w;
#else
    // Once per pixel: over the pixel, or under temporal anti-aliasing over this
    // frame's sample's share of it (`Jitter::lod_bias`).
    float footprint = exp2(frame.params.z);
#endif
    vec3 tn = textureGrad(sampler2D(normal_map, normal_sampler), uv, dx * footprint,
                          dy * footprint).xyz * 2.0 - 1.0;
    // A filtered normal is shorter where the normals it averages spread. Lambert's
    // and the ambient terms are linear in the normal, so they take the filtered one
    // as it is (the mean of the shading over the pixel, not the shading of a mean
    // direction, which would be too bright); the highlight takes its direction, with
    // Toksvig's (2005) lower shininess for the spread.
    float len = clamp(length(tn), 1e-3, 1.0);
    float spread = (1.0 - len) / len;
    float bump = surface.params.z;
    vec3 nf = t * (tn.x * bump) + b * (tn.y * bump) + n * tn.z;
    nf /= max(length(nf) / len, 1.0);
    n = normalize(nf);
    float shininess = SHININESS / (1.0 + SHININESS * spread * bump * bump);

    vec3 v = normalize(frame.camera_pos.xyz - in_world);
    vec3 l;
    // Unshadowed: the light through the calcite enters on the far side, whose shadow
    // is its own.
    vec3 unshadowed;
    light_at(frame.sun_dir, frame.sun_color.rgb, in_world, l, unshadowed);
    float visible = shadow_visibility(in_world, geometric);
    vec3 radiance = unshadowed * visible;
    float film = surface.look.x;
    float wet = clamp(film, 0.0, 1.0);
    // Under the film the calcite is darker and its colour deeper: light it scatters back
    // is partly reflected down again at the water's surface (Lekner & Dorf 1988).
    vec3 albedo = mix(in_color, wet_albedo(in_color), wet);
    vec3 ambient = mix(frame.ground_color.rgb, frame.sky_color.rgb, 0.5 + 0.5 * nf.y);
    vec3 h = normalize(l + v);
    float spec = 0.35 * (shininess + 8.0) / 25.1327 * pow(max(dot(n, h), 0.0), shininess)
               * max(dot(n, l), 0.0);
    // Under water the calcite's own sheen fades: its reflectance against water,
    // ((1.66 - 1.33) / (1.66 + 1.33))^2 = 0.012, is a fifth of that against air.
    spec *= 1.0 - 0.8 * wet;
    vec3 hdr = albedo * ambient + radiance * (albedo * max(dot(nf, l), 0.0) + vec3(spec));
    if (surface.light.x > 0.5) {
        float chord;
        float through = transmitted(in_world, geometric, l, in_axis, chord);
        if (through > 1e-3) {
            // The far side, where the light enters, in the lamp's shadow or not (its
            // centre's: the light through is soft anyway).
            hdr += albedo * unshadowed * through
                 * shadow_visibility_hard(in_world + l * chord, l);
        }
    }
    // The film: its surface follows the rings with part of the bumps' relief; where
    // the filtered bumps spread it is rougher (as Toksvig's factor for the calcite).
    vec3 nc = normalize(t * (tn.x * bump * FILM_RELIEF) + b * (tn.y * bump * FILM_RELIEF)
                        + geometric * tn.z);
    // A bump may turn the film's normal from the camera, which it cannot see there:
    // bent back to face it (else Fresnel's grazing reflectance, near 1, would blacken
    // the calcite below in specks).
    float facing = dot(nc, v);
    if (facing < 0.2) {
        nc = normalize(nc + v * (0.2 - facing));
    }
    float alpha = sqrt(FILM_ALPHA * FILM_ALPHA + spread * bump * FILM_RELIEF);
    vec3 r = reflect(-v, nc);
    float fresnel = water_fresnel(dot(nc, v));
    // The mip whose texels subtend the lobe's width, alpha radians: a face of 2^y
    // texels spans pi / 2.
    float lod = clamp(surface.look.y + 1.0 + log2(alpha / 3.14159265), 0.0, surface.look.y);
    vec3 env = textureLod(samplerCube(environment, environment_sampler), r, lod).rgb;
    // The cube holds the chamber without the lamp: the lamp's highlight is drawn from
    // where it is, not from where the cube's centre sees it.
    vec3 glint = radiance * film_highlight(nc, v, r, in_world, frame.sun_dir.xyz,
                                           shadow.params.w, alpha);
    // What the film reflects the calcite below does not receive: on average over the
    // film's bumps, the share its mean surface reflects (each bump's own would
    // speckle the calcite where bumps turn to grazing).
    float mean_fresnel = water_fresnel(dot(geometric, v));
    hdr = hdr * (1.0 - wet * mean_fresnel) + film * (fresnel * env + glint);
    out_color = vec4(tonemap(hdr, frame.params.x), 1.0);
}
