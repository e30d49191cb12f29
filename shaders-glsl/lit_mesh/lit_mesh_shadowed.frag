#version 450
// Lit meshes in the shadow of a lamp (`render::shadow_map`).
#extension GL_GOOGLE_include_directive : require
#define SHADOWED
#include "lit_mesh.glsl"
