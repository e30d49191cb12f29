#version 450
// Ring growth: hand every captured vertex to the geometry shader unchanged.

layout(location = 0) in vec4 in_pos_id;
layout(location = 1) in vec4 in_normal_sp;
layout(location = 2) in vec4 in_extra;

layout(location = 0) out vec4 out_pos_id;
layout(location = 1) out vec4 out_normal_sp;
layout(location = 2) out vec4 out_extra;

void main() {
    out_pos_id = in_pos_id;
    out_normal_sp = in_normal_sp;
    out_extra = in_extra;
    gl_Position = vec4(in_pos_id.xyz, 1.0);
}
