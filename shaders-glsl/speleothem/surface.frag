#version 450
// Speleothem surfaces shaded once per pixel (the viewer's default).
#extension GL_GOOGLE_include_directive : require
#include "surface.glsl"
