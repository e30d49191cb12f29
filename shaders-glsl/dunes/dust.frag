#version 450
// Sand dust: a spherical blob whose grain density falls off from the centre; the
// light it absorbs is proportional to the density (alpha blended over the scene). Its
// colour is the sunlit and skylit dust's radiance, tone mapped as the terrain is.
#extension GL_GOOGLE_include_directive : require
#include "tonemap.glsl"

layout(push_constant) uniform Dust {
    mat4 view_proj;
    vec4 right;
    vec4 up;
    vec4 color;  // rgb radiance, a peak opacity
    vec4 tone;   // x exposure, y operator
} dust;

layout(location = 0) in vec2 in_disc;
layout(location = 0) out vec4 out_color;

void main() {
    float r2 = dot(in_disc, in_disc);
    if (r2 > 1.0) {
        discard;
    }
    // Density through a Gaussian blob, integrated along the view ray.
    float density = exp(-4.0 * r2);
    out_color = vec4(tonemap(dust.color.rgb, vec4(dust.tone.xy, 0.0, 0.0)), dust.color.a * density);
}
