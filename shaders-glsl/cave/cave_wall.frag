#version 450
// Cave walls and speleothems (Cui et al.'s directional light, plus the head lamp a
// cave needs, its soft shadows, and fog), the Short-profile speleothems as wet calcite,
// or flat-coloured wireframe lines. The vertex stage is `lit_mesh.vert`, whose Frame
// block is the first part of this one.
#extension GL_GOOGLE_include_directive : require
#include "lighting.glsl"
#include "tonemap.glsl"
#include "shadow.glsl"
#include "rock.glsl"
#include "wet_film.glsl"

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_proj;
    vec4 camera_pos;   // xyz: the camera
    vec4 sun_dir;      // xyz: toward the directional light
    vec4 sun_color;
    vec4 sky_color;    // ambient from above
    vec4 ground_color; // ambient from below
    vec4 params;       // x exposure
    vec4 lamp;         // rgb: lamp radiance at 1 m (inverse-square falloff)
    vec4 fog;          // rgb: fog colour, w: density per metre
    vec4 lamp_at;      // xyz: the lamp, beside the camera
} frame;

layout(push_constant) uniform Object {
    mat4 model;
    vec4 albedo;   // rgb linear albedo (the line colour when unlit)
    vec4 material; // x shininess, y specular weight, z > 0.5: unlit (wireframe)
} object;

// The pipeline of wet calcite (`Surface::WetCalcite`): its code compiled away from the
// walls' pipeline, where llvmpipe would run it under a lane mask for every pixel.
layout(constant_id = 0) const bool WET = false;
// The walls' pipeline (`Surface::Limestone`): limestone (`rock.glsl`) over a grey of
// ROCK_GREY times their albedo.
layout(constant_id = 1) const bool ROCK = false;
const float ROCK_GREY = 0.5;

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;

layout(location = 0) out vec4 out_color;

// Wet calcite (`WET`), for the Short-profile speleothems, which carry no
// texture coordinates: a relief of solid noise in world space (the cave's speleothems
// stand upright), under the water film of the grown ones (`wet_film.glsl`). Knobs of
// crystal a few centimetres across, smaller ones over them and a fine grain; low rims
// of flowstone round the speleothem about RIM_SPACING apart in some bands of its
// height, their level wandering so that they neither stay level nor repeat. Each
// octave fades to its mean before its period spans three pixels (`octave_weight`),
// and the colour drifts between cream and tan in patches.
const float RIM_SPACING = 0.035;
// The film: its GGX roughness (water over a rough crystal surface, rougher than the
// grown speleothems' still film), the share of the relief its surface keeps, and the
// head lamp's radius (a hand lamp's reflector), metres.
const float CALCITE_FILM_ALPHA = 0.05;
const float CALCITE_FILM_RELIEF = 0.35;
const float LAMP_RADIUS = 0.03;

void calcite(vec3 p, float footprint, inout vec3 n, inout vec3 albedo) {
    const float TAU = 6.2831853;
    vec3 wander_scale = vec3(5.0, 2.0, 5.0);
    vec4 wander = value_noise(p * wander_scale + 31.0);
    float phase = TAU * p.y / RIM_SPACING + 5.0 * wander.x;
    vec4 band = value_noise(p * vec3(1.2, 3.5, 1.2) + 11.0);
    float rim_height = 0.0004 * smoothstep(0.45, 0.8, band.x);
    vec3 rim_gradient = rim_height * cos(phase)
                      * (vec3(0.0, TAU / RIM_SPACING, 0.0) + 5.0 * wander.yzw * wander_scale);
    vec4 knobs = value_noise(p * 16.0 + 7.0);
    vec4 small = value_noise(p * 45.0 + 19.0);
    vec4 grain = value_noise(p * 140.0 + 3.0);
    float r = octave_weight(1.0 / RIM_SPACING, footprint);
    vec3 slope = r * rim_gradient + octave_weight(16.0, footprint) * 0.3 * knobs.yzw
               + octave_weight(45.0, footprint) * 0.12 * small.yzw
               + octave_weight(140.0, footprint) * 0.035 * grain.yzw;
    n = normalize(n - (slope - dot(slope, n) * n));
    vec4 patches = value_noise(p * vec3(1.7, 0.6, 1.7) + 53.0);
    albedo *= mix(vec3(1.03, 1.02, 1.0), vec3(0.92, 0.87, 0.79), smoothstep(0.35, 0.9, patches.x));
}

void main() {
    vec3 to_eye = frame.camera_pos.xyz - in_world;
    float dist = length(to_eye);
    vec3 v = to_eye / max(dist, 1e-4);
    vec3 albedo = object.albedo.rgb;
    vec3 hdr = albedo;
    if (object.material.z < 0.5) {
        vec3 n = normalize(in_normal);
        vec3 geometric = n;
        // A temporal frame's sample stands for its share of the pixel.
        float footprint = length(fwidth(in_world)) * exp2(frame.params.z);
        if (WET) {
            calcite(in_world, footprint, n, albedo);
            albedo = wet_albedo(albedo);
        }
        if (ROCK) {
            limestone(in_world, footprint, albedo * ROCK_GREY, n, albedo);
        }
        float shininess = object.material.x;
        float specular = object.material.y;
        hdr = albedo * hemisphere_ambient(n, frame.sky_color.rgb, frame.ground_color.rgb)
            + sun_light(n, v, normalize(frame.sun_dir.xyz), albedo, frame.sun_color.rgb,
                        shininess, specular);
        // The head lamp, just beside the eye: its shadows show as thin dark rims.
        vec3 to_lamp = frame.lamp_at.xyz - in_world;
        float d2 = max(dot(to_lamp, to_lamp), 1.0);
        vec3 l = normalize(to_lamp);
        float visible = dot(geometric, l) > 0.0 ? shadow_visibility(in_world, geometric) : 0.0;
        vec3 lamp = frame.lamp.rgb * (visible / d2);
        hdr += sun_light(n, v, l, albedo, lamp, shininess, specular);
        if (WET) {
            // The film follows part of the relief; it reflects the lamp, the directional
            // light (a point of no size far along its direction) and the light from
            // above, and what it reflects the calcite below does not receive.
            vec3 nc = normalize(mix(geometric, n, CALCITE_FILM_RELIEF));
            float facing = dot(nc, v);
            if (facing < 0.2) {
                nc = normalize(nc + v * (0.2 - facing));
            }
            vec3 r = reflect(-v, nc);
            vec3 glint = lamp * film_highlight(nc, v, r, in_world, frame.lamp_at.xyz,
                                               LAMP_RADIUS, CALCITE_FILM_ALPHA)
                       + frame.sun_color.rgb * film_highlight(nc, v, r, in_world,
                             in_world + normalize(frame.sun_dir.xyz) * 1000.0, 0.0,
                             CALCITE_FILM_ALPHA);
            float fresnel = water_fresnel(dot(nc, v));
            vec3 above = hemisphere_ambient(r, frame.sky_color.rgb, frame.ground_color.rgb);
            hdr = hdr * (1.0 - water_fresnel(dot(geometric, v))) + fresnel * above + glint;
        }
    }
    float fog = 1.0 - exp(-frame.fog.w * dist);
    hdr = mix(hdr, frame.fog.rgb, fog);
    out_color = vec4(tonemap(hdr, frame.params.x), 1.0);
}
