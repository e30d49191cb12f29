// Tone mapping shared by every scene: exposure, then Narkowicz's fit of the ACES
// filmic curve. The colour target is sRGB, so the hardware applies the transfer curve.
#ifndef SEDIMENT_TONEMAP_GLSL
#define SEDIMENT_TONEMAP_GLSL

vec3 tonemap_aces(vec3 hdr, float exposure) {
    vec3 x = hdr * exposure;
    const float a = 2.51;
    const float b = 0.03;
    const float c = 2.43;
    const float d = 0.59;
    const float e = 0.14;
    return clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0, 1.0);
}

#endif
