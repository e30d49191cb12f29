#version 450
// Cave walls and speleothems (Cui et al.'s directional light, plus the head lamp a
// cave needs, its soft shadows, and fog), or flat-coloured wireframe lines. The vertex
// stage is `lit_mesh.vert`, whose Frame block is the first part of this one.
#extension GL_GOOGLE_include_directive : require
#include "lighting.glsl"
#include "tonemap.glsl"
#include "shadow.glsl"

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

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;

layout(location = 0) out vec4 out_color;

void main() {
    vec3 to_eye = frame.camera_pos.xyz - in_world;
    float dist = length(to_eye);
    vec3 v = to_eye / max(dist, 1e-4);
    vec3 albedo = object.albedo.rgb;
    vec3 hdr = albedo;
    if (object.material.z < 0.5) {
        vec3 n = normalize(in_normal);
        float shininess = object.material.x;
        float specular = object.material.y;
        hdr = albedo * hemisphere_ambient(n, frame.sky_color.rgb, frame.ground_color.rgb)
            + sun_light(n, v, normalize(frame.sun_dir.xyz), albedo, frame.sun_color.rgb,
                        shininess, specular);
        // The head lamp, just beside the eye: its shadows show as thin dark rims.
        vec3 to_lamp = frame.lamp_at.xyz - in_world;
        float d2 = max(dot(to_lamp, to_lamp), 1.0);
        vec3 l = normalize(to_lamp);
        float visible = dot(n, l) > 0.0 ? shadow_visibility(in_world, n) : 0.0;
        hdr += sun_light(n, v, l, albedo, frame.lamp.rgb * (visible / d2), shininess,
                         specular);
    }
    float fog = 1.0 - exp(-frame.fog.w * dist);
    hdr = mix(hdr, frame.fog.rgb, fog);
    out_color = vec4(tonemap(hdr, frame.params.x), 1.0);
}
