#version 450
// Temporal anti-aliasing when nothing moved: every history kept, no depth read.
#extension GL_GOOGLE_include_directive : require
#define SETTLED
#include "temporal.glsl"
