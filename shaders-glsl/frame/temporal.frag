#version 450
// Temporal anti-aliasing where the camera moved: the history reprojected.
#extension GL_GOOGLE_include_directive : require
#include "temporal.glsl"
