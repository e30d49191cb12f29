// Tone mapping shared by every scene: exposure, then one of three operators: Narkowicz's
// fit of the ACES filmic curve, Reinhard's L / (1 + L) on luminance, Ashikhmin's (2002)
// global operator, which Tortelli & Walter cite. The colour target is sRGB, so the
// hardware applies the transfer curve.
//
// The operator is a specialization constant (ids 16..18, `ToneMap::constants`), fixed
// per pipeline: read from a uniform, llvmpipe would run all three operators in every
// pixel (a CPU rasteriser runs both sides of a branch).
#ifndef SEDIMENT_TONEMAP_GLSL
#define SEDIMENT_TONEMAP_GLSL

// Every false: ACES. At most one is true. (Three switches, not one number: naga reads
// no expression of specialization constants, such as a comparison.)
layout(constant_id = 16) const bool TONE_MAP_REINHARD = false;
layout(constant_id = 17) const bool TONE_MAP_ASHIKHMIN = false;
layout(constant_id = 18) const bool TONE_MAP_LINEAR = false;

vec3 tonemap_aces(vec3 hdr, float exposure) {
    vec3 x = hdr * exposure;
    const float a = 2.51;
    const float b = 0.03;
    const float c = 2.43;
    const float d = 0.59;
    const float e = 0.14;
    return clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0, 1.0);
}

float luminance(vec3 c) {
    return dot(c, vec3(0.2126, 0.7152, 0.0722));
}

// Scales a colour to luminance `l` keeping its chromaticity; where a channel would
// pass white the colour is scaled down until it fits, keeping hue and saturation and
// giving up luminance (clipping the channel would shift the hue; mixing toward white
// leaves Table 1's iron and copper at about two thirds of their saturation where the
// lamp lights them).
vec3 with_luminance(vec3 c, float l) {
    float lc = max(luminance(c), 1e-6);
    vec3 s = c * (l / lc);
    float top = max(max(s.r, s.g), s.b);
    if (top > 1.0) {
        s /= top;
    }
    return clamp(s, 0.0, 1.0);
}

vec3 tonemap_reinhard(vec3 hdr, float exposure) {
    float l = luminance(hdr) * exposure;
    return with_luminance(hdr, l / (1.0 + l));
}

// Ashikhmin (2002), eq. 4: the perceptual capacity C(L) of the visual system up to
// world luminance L (cd/m^2), from the threshold-versus-intensity curve.
float ashikhmin_capacity(float l) {
    if (l < 0.0034) {
        return l / 0.0014;
    } else if (l < 1.0) {
        return 2.4483 + log(l / 0.0034) / 0.4027;
    } else if (l < 7.2444) {
        return 16.5630 + (l - 1.0) / 0.4027;
    }
    return 32.0693 + log(l / 7.2444) / 0.0556;
}

// Ashikhmin's global tone function, eq. 5: display luminance
// Ld = (C(Lw) - C(Lwmin)) / (C(Lwmax) - C(Lwmin)) of the display's maximum. The world
// range is fixed rather than measured from the frame (sediment draws in one pass, with
// no reduction over the image): one unit of scene radiance is 100 cd/m^2, the white
// point Lwmax is 1.2 units / exposure, and Lwmin 2.5 decades below it — about the range
// a lamp-lit cave spans, so the dark rock stays dark. Ashikhmin's local
// (detail-preserving) part is not used.
vec3 tonemap_ashikhmin(vec3 hdr, float exposure) {
    const float LWMAX = 120.0;
    const float LWMIN = LWMAX / 316.0;
    float lw = luminance(hdr) * exposure * 100.0;
    float c0 = ashikhmin_capacity(LWMIN);
    float ld = (ashikhmin_capacity(clamp(lw, LWMIN, 1e6)) - c0)
             / (ashikhmin_capacity(LWMAX) - c0);
    return with_luminance(hdr, clamp(ld, 0.0, 1.0));
}

// The pipeline's operator (above) after `exposure`; `TONE_MAP_LINEAR`: radiance times
// exposure, for a floating-point target (the environment map's faces).
vec3 tonemap(vec3 hdr, float exposure) {
    if (TONE_MAP_LINEAR) {
        return hdr * exposure;
    }
    if (TONE_MAP_ASHIKHMIN) {
        return tonemap_ashikhmin(hdr, exposure);
    }
    if (TONE_MAP_REINHARD) {
        return tonemap_reinhard(hdr, exposure);
    }
    return tonemap_aces(hdr, exposure);
}

#endif
