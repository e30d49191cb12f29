#version 450
// Temporal anti-aliasing under a still camera: the history at the same pixel.
#extension GL_GOOGLE_include_directive : require
#define STILL
#include "temporal.glsl"
