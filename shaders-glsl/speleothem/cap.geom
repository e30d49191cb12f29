#version 450
// Caps for open growth fronts, drawn beside the paper's mesh (which the transform
// feedback keeps as it is): a front-band triangle with two vertices on the tip ring
// (ID -1) and one on the ring behind it (ID 0) gives the cap triangle between the two
// tips and the ring's centre, found from the chord: p1 = c + r n1 and p2 = c + r n2, so
// r = |p1 - p2| / |n1 - n2|. Fronts that closed to a point or joined a column have no
// tip ring left, so get no cap. The CPU twin is `model::speleothem::caps`.

layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

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

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec3 out_tangent;
layout(location = 3) out vec3 out_uv;
layout(location = 4) out vec3 out_color;
// The axis (w 0: a cap, which no light crosses in `surface.glsl`'s sense).
layout(location = 5) out vec4 out_axis;

void corner(int k, vec3 world, vec3 normal) {
    out_world = world;
    out_normal = normal;
    out_tangent = in_tangent[k];
    out_uv = in_uv[k];
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
    corner(a, in_world[a], g);
    corner(b, in_world[b], g);
    corner(a, c, g);
    EndPrimitive();
}
