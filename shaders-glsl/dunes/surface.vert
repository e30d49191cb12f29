#version 450
// Dune quads: world position and the dune's own normal; the fragment shader bump maps
// the ripples onto them. The aerial perspective — single scattering of sunlight in the
// air between the eye and the sand, from the sky's own atmosphere
// (src/model/atmosphere.rs) taken as it is at the ground: over a field's few hundred
// metres of a 1.2 km aerosol and 8 km air scale height, the closed form of a
// homogeneous medium, L T + S / sigma_t (1 - T), of the sun and of the sky's and sand's
// light — is computed here per vertex: it changes little across a 4 m quad, and per
// pixel lavapipe would pay for it in every fragment.
#extension GL_GOOGLE_include_directive : require
#include "atmosphere.glsl"
#include "world.glsl"

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_proj;
    vec4 camera_pos;
    vec4 sun_dir;
    vec4 sun_color;
    vec4 sky_color;
    vec4 ground_color;
    vec4 params;
} frame;

// surface.frag's block (the vertex stage reads the air).
layout(push_constant) uniform Dune {
    vec4 tile;
    vec4 wind;
    vec4 shadows;
    vec4 albedo;
    vec4 air_extinction;  // rgb per metre at the ground, w aerosol g
    vec4 air_scattering;  // rgb Rayleigh per metre, w aerosol
    vec4 detail_rect;     // footprints' detail field: world x, z of its corner, its size
    vec4 detail;          // y slope range of the encoding, w dune grid side
} dune;

layout(location = 0) in vec3 in_position;

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_transmit;
layout(location = 2) out vec3 out_inscatter;
// The dune copies' warp at this vertex (world.glsl): smooth over hundreds of metres,
// interpolated across a quad.
layout(location = 3) out vec2 out_warped;

void main() {
    out_world = in_position;
    out_warped = in_position.xz + warp_at(in_position.xz);
    vec3 to_eye = in_position - frame.camera_pos.xyz;
    float dist = length(to_eye);
    float nu = dot(to_eye / max(dist, 1e-6), normalize(frame.sun_dir.xyz));
    vec3 ext = dune.air_extinction.rgb;
    vec3 scatter = dune.air_scattering.rgb * rayleigh_phase(nu)
        + vec3(dune.air_scattering.w * mie_phase(nu, dune.air_extinction.w));
    out_transmit = exp(-ext * dist);
    vec3 haze = (1.0 - out_transmit) / max(ext, vec3(1e-9));
    // The sun's light scattered toward the eye (sun_color is the sunlight over pi:
    // back to irradiance), and the sky's and the sand's light scattered all round (their
    // mean radiance, scattered isotropically: the air's own glow, which in thick haze is
    // most of what is seen; the sky-view table has it through multiple scattering).
    vec3 total = dune.air_scattering.rgb + vec3(dune.air_scattering.w);
    vec3 ambient = 0.5 * (frame.sky_color.rgb + frame.ground_color.rgb);
    out_inscatter = (PI * frame.sun_color.rgb * scatter + total * ambient) * haze;
    gl_Position = frame.view_proj * vec4(in_position, 1.0);
}
