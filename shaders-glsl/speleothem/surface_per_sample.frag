#version 450
// Speleothem surfaces shaded once per sample (pictures written to files).
#extension GL_GOOGLE_include_directive : require
#define PER_SAMPLE
#include "surface.glsl"
