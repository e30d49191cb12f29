#version 450
// Ring growth: hand every captured vertex to the geometry shader unchanged. Position
// and ID ride in gl_Position (the geometry shader reads them there as gl_in[k], and the
// pass discards rasterisation, so nothing clips or divides them): lavapipe copies each
// vertex-shader output a geometry-shader input matches, per vertex, so one output fewer
// is one copy fewer.

layout(location = 0) in vec4 in_pos_id;
layout(location = 1) in vec4 in_normal_sp;
layout(location = 2) in vec4 in_extra;

layout(location = 1) out vec4 out_normal_sp;
layout(location = 2) out vec4 out_extra;

void main() {
    gl_Position = in_pos_id;
    out_normal_sp = in_normal_sp;
    out_extra = in_extra;
}
