#version 450
// Lit meshes without shadows.
#extension GL_GOOGLE_include_directive : require
#include "lit_mesh.glsl"
