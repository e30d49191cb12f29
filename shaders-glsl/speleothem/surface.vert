#version 450
// Shading the grown speleothems: reads the captured ring vertices directly.

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_proj;
    vec4 camera_pos;
    vec4 sun_dir;
    vec4 sun_color;
    vec4 sky_color;
    vec4 ground_color;
    vec4 params;
} frame;

// Per speleothem, 2 vec4: (mineral colour rgb, rings grown so far), (growth sign,
// mineral mix intensity, thickening accumulated so far, 0).
layout(set = 0, binding = 1, std430) readonly buffer Speleothems {
    vec4 info[];
} speleothems;

layout(push_constant) uniform Surface {
    // x segments per ring, y texture repeats per unit of length, z normal-map strength,
    // w 1 for vertices frozen by the append-only growth, else 0
    vec4 params;
} surface;

layout(location = 0) in vec4 in_pos_id;
layout(location = 1) in vec4 in_normal_sp;
layout(location = 2) in vec4 in_extra;

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec3 out_tangent;
layout(location = 3) out vec2 out_uv;
layout(location = 4) out vec3 out_color;

const vec3 CALCITE = vec3(0.8, 0.8, 0.8);

void main() {
    uint sp = uint(in_normal_sp.w + 0.5);
    vec4 mineral = speleothems.info[2u * sp];
    vec4 misc = speleothems.info[2u * sp + 1u];
    vec3 g = vec3(0.0, misc.x, 0.0);
    vec3 n_radial = in_normal_sp.xyz;
    // Surface normal of a band whose radius changes by `slope` per unit of height:
    // tilt the radial normal against the growth direction (at a cone apex N = 0 and the
    // slope is -1, giving the growth direction itself).
    out_normal = normalize(n_radial - g * in_extra.z + vec3(0.0, 1e-6, 0.0));
    out_tangent = length(n_radial) > 0.5 ? normalize(cross(g, n_radial)) : vec3(1.0, 0.0, 0.0);
    out_uv = vec2(in_extra.x / surface.params.x, in_extra.y * surface.params.y);
    // Tortelli & Walter: fv_c = mc * (arID / rc), linear from base to tip; the user's
    // intensity mixes it into white calcite.
    float t = mineral.w > 0.0 ? clamp(in_extra.w / mineral.w, 0.0, 1.0) : 1.0;
    out_color = mix(CALCITE, mineral.rgb * t, misc.y);
    // The append-only growth writes a vertex once, less the thickening accumulated when
    // it left the front; add the current total (model::speleothem::unfreeze).
    vec3 p = in_pos_id.xyz + n_radial * (misc.z * surface.params.w);
    out_world = p;
    gl_Position = frame.view_proj * vec4(p, 1.0);
}
