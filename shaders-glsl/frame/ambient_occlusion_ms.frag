#version 450
// Ambient occlusion from sample 0 of a multisampled depth.
#extension GL_GOOGLE_include_directive : require
#define MULTISAMPLED
#include "ambient_occlusion.glsl"
