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

// Per speleothem, 3 vec4: (mineral colour rgb, rings grown so far), (growth sign,
// mineral mix intensity, thickening accumulated so far, the height of the dome capping
// its open front), (tip ring centre, the dome's height factor).
layout(set = 0, binding = 1, std430) readonly buffer Speleothems {
    vec4 info[];
} speleothems;

layout(push_constant) uniform Surface {
    // x segments per ring, y texture repeats per unit of length, z normal-map strength,
    // w 1 for vertices frozen by the append-only growth, else 0
    vec4 params;
    // x environment reflection strength, y the environment cube's last mip level, z the
    // rings of the whole growth when colouring by age (0: by mineral), w the share of
    // a pixel's side one sample shades (1 / sqrt(samples per pixel))
    vec4 look;
    // x 1 with light through the calcite (`surface.glsl`), else 0
    vec4 light;
} surface;

layout(location = 0) in vec4 in_pos_id;
layout(location = 1) in vec4 in_normal_sp;
layout(location = 2) in vec4 in_extra;

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec3 out_tangent;
layout(location = 3) out vec3 out_uv;
layout(location = 4) out vec3 out_color;
// The tip ring's centre (a point on the axis; w 1: on the wall), and for the cap pass
// (`cap.geom`) the ring ID and the growth direction.
layout(location = 5) out vec4 out_tip_centre;
layout(location = 6) out float out_id;
layout(location = 7) out vec3 out_growth;
// The cap pass's dome: its height factor (`GrowthPlan::dome`) and its apex's height
// above the tip ring's centre (`model::speleothem::dome_apex`).
layout(location = 8) out vec2 out_dome;

const vec3 CALCITE = vec3(0.8, 0.8, 0.8);


void main() {
    uint sp = uint(in_normal_sp.w + 0.5);
    vec4 mineral = speleothems.info[3u * sp];
    vec4 misc = speleothems.info[3u * sp + 1u];
    vec3 g = vec3(0.0, misc.x, 0.0);
    vec3 n_radial = in_normal_sp.xyz;
    // Surface normal of a band whose radius changes by `slope` per unit of height:
    // tilt the radial normal against the growth direction (at a cone apex N = 0 and the
    // slope is -1, giving the growth direction itself).
    out_normal = normalize(n_radial - g * in_extra.z + vec3(0.0, 1e-6, 0.0));
    out_tangent = length(n_radial) > 0.5 ? normalize(cross(g, n_radial)) : vec3(1.0, 0.0, 0.0);
    // Around the ring u runs 0..1 and wraps; a second copy shifted by half a turn is
    // continuous where the first jumps (Tarini 2012): the fragment shader uses
    // whichever varies less, so no seam shows where the segment index wraps.
    float u = in_extra.x / surface.params.x;
    out_uv = vec3(u, fract(u + 0.5), in_extra.y * surface.params.y);
    // Tortelli & Walter: fv_c = mc * (arID / rc), "a linear variation from base to
    // tip". Read literally every base is black, which no figure of theirs shows; read
    // as the mineral's share of the colour over white calcite, rising linearly from
    // base to tip (from 35 % at the base), scaled by the user's intensity.
    float t = mineral.w > 0.0 ? clamp(in_extra.w / mineral.w, 0.0, 1.0) : 1.0;
    out_color = mix(CALCITE, mineral.rgb, misc.y * (0.35 + 0.65 * t));
    if (surface.look.z > 0.0) {
        // By age: each ring by its date (ring number over the whole growth's), a ramp
        // from dark umber (oldest) through ochre to pale cream (newest), times the
        // mineral's colour (white calcite: the ramp itself).
        // A foot (ring -1, `model::speleothem::feet`) is coated still: the newest.
        float age = in_extra.w < 0.0 ? 1.0 : clamp(in_extra.w / surface.look.z, 0.0, 1.0);
        vec3 ramp = age < 0.5
            ? mix(vec3(0.18, 0.08, 0.03), vec3(0.72, 0.42, 0.14), age * 2.0)
            : mix(vec3(0.72, 0.42, 0.14), vec3(0.98, 0.95, 0.85), age * 2.0 - 1.0);
        out_color *= ramp / CALCITE;
    }
    // The append-only growth writes a vertex once, less the thickening accumulated when
    // it left the front; add the current total (model::speleothem::unfreeze).
    vec3 p = in_pos_id.xyz + n_radial * (misc.z * surface.params.w);
    out_world = p;
    vec4 tip = speleothems.info[3u * sp + 2u];
    out_tip_centre = vec4(tip.xyz, 1.0);
    out_dome = vec2(tip.w, misc.w);
    out_id = in_pos_id.w;
    out_growth = g;
    gl_Position = frame.view_proj * vec4(p, 1.0);
    // A joint (ID 2, model::speleothem::feet::joints) waits for its front's last ring,
    // its ring number: until the two have met it lies beyond the far plane.
    if (in_pos_id.w > 1.5 && in_extra.w > mineral.w + 0.5) {
        gl_Position = vec4(0.0, 0.0, 2.0, 1.0);
    }
}
