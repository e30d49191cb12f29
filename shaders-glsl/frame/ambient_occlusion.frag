#version 450
// Ambient occlusion from a single-sampled depth.
#extension GL_GOOGLE_include_directive : require
#include "ambient_occlusion.glsl"
