#version 450
// Caps for open growth fronts, drawn beside the paper's mesh (which the transform
// feedback keeps as it is): a front-band triangle with two vertices on the tip ring
// (ID -1) and one on the ring behind it (ID 0) gives the sector between the two tips
// and the ring's centre, raised into a dome: Franke's stationary profile
// (`model::speleothem::DOME_PROFILE`, whose numbers these are) scaled in height by the
// speleothem's dome factor (`GrowthPlan::dome`; 0: flat). Each point on a spoke from a
// tip vertex depends on that vertex alone, so neighbouring sectors meet exactly; the
// rim takes the flank's normal, so the join shows no crease. Fronts that closed to a
// point or joined a column have no tip ring left, so get no cap. The CPU twin is
// `model::speleothem::caps`.

layout(triangles) in;
layout(triangle_strip, max_vertices = 11) out;

const int DOME_ROWS = 5;
// Rows from the rim inward: radius share, height in tip-ring radii, slope dy/dx.
const float DOME_U[DOME_ROWS] = float[](1.0, 0.9, 0.75, 0.55, 0.3);
const float DOME_H[DOME_ROWS] = float[](0.0, 0.4093, 0.703, 0.9209, 1.0652);
const float DOME_SLOPE[DOME_ROWS] = float[](6.7516, 2.7138, 1.449, 0.8101, 0.3777);

layout(set = 0, binding = 0) uniform Frame {
    mat4 view_proj;
    vec4 camera_pos;
    vec4 sun_dir;
    vec4 sun_color;
    vec4 sky_color;
    vec4 ground_color;
    vec4 params;
} frame;

layout(location = 0) in vec3 in_world[];
layout(location = 1) in vec3 in_normal[];
layout(location = 2) in vec3 in_tangent[];
layout(location = 3) in vec3 in_uv[];
layout(location = 4) in vec3 in_color[];
layout(location = 5) in vec4 in_tip_centre[];
layout(location = 6) in float in_id[];
layout(location = 7) in vec3 in_growth[];
layout(location = 8) in vec2 in_dome[];

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec3 out_tangent;
layout(location = 3) out vec3 out_uv;
layout(location = 4) out vec3 out_color;
// The axis (w 0: a cap, which no light crosses in `surface.glsl`'s sense).
layout(location = 5) out vec4 out_axis;

// The caps' texture: the normal map laid flat in world x and z, this many repeats a
// scene unit (the flanks' density round a ring 5 cm in radius). The flanks' u runs
// round the ring and their tangent along it: copied to a cap's corners, every sector
// got its own stretch and turn of the bumps, a star across a flat top.
const float CAP_REPEATS = 3.2;

void corner(int k, vec3 world, vec3 normal) {
    out_world = world;
    out_normal = normal;
    out_tangent = normalize(vec3(1.0, 0.0, 0.0) - normal * normal.x + vec3(0.0, 0.0, 1e-6));
    float u = world.x * CAP_REPEATS;
    out_uv = vec3(u, u + 0.5, world.z * CAP_REPEATS);
    out_color = in_color[k];
    out_axis = vec4(in_tip_centre[k].xyz, 0.0);
    gl_Position = frame.view_proj * vec4(world, 1.0);
    EmitVertex();
}

void main() {
    int tips[2] = int[2](0, 0);
    int count = 0;
    bool behind = false;
    for (int k = 0; k < 3; ++k) {
        if (abs(in_id[k] + 1.0) < 0.25) {
            if (count < 2) {
                tips[count] = k;
            }
            count += 1;
        } else if (abs(in_id[k]) < 0.25) {
            behind = true;
        }
    }
    if (count != 2 || !behind) {
        return;
    }
    int a = tips[0];
    int b = tips[1];
    if (length(in_world[a] - in_world[b]) < 1e-6) {
        return;
    }
    vec3 c = in_tip_centre[a].xyz;
    vec3 g = in_growth[a];
    // Counter-clockwise seen from outside, along the growth direction.
    if (dot(cross(in_world[b] - in_world[a], c - in_world[a]), g) < 0.0) {
        int t = a;
        a = b;
        b = t;
    }
    float k = in_dome[a].x;
    if (k <= 0.0) {
        corner(a, in_world[a], g);
        corner(b, in_world[b], g);
        corner(a, c, g);
        EndPrimitive();
        return;
    }
    // A strip from the rim inward, alternating the two spokes, closed at the apex.
    for (int row = 0; row < DOME_ROWS; ++row) {
        for (int side = 0; side < 2; ++side) {
            int v = side == 0 ? a : b;
            vec3 p = in_world[v];
            float r = length(p - c);
            vec3 radial = (p - c) / max(r, 1e-12);
            vec3 point = row == 0 ? p : c + (p - c) * DOME_U[row] + g * (k * DOME_H[row] * r);
            vec3 normal = row == 0 ? in_normal[v] : normalize(g + radial * (k * DOME_SLOPE[row]));
            corner(v, point, normal);
        }
    }
    // One apex for every sector of the front (`model::speleothem::dome_apex`).
    corner(a, c + g * in_dome[a].y, g);
    EndPrimitive();
}
