// Solid value noise for procedural materials (the rock of the growth chamber, the
// cave's calcite), and the weight that fades an octave before it aliases.
#ifndef SEDIMENT_NOISE_GLSL
#define SEDIMENT_NOISE_GLSL

// Value noise on the unit lattice with its gradient (Quilez's analytic derivative of
// the smoothstep-weighted corners): one lookup gives colour and relief.
float lattice_hash(vec3 p) {
    p = fract(p * 0.3183099 + 0.1) * 17.0;
    return fract(p.x * p.y * p.z * (p.x + p.y + p.z));
}

vec4 value_noise(vec3 x) {
    vec3 i = floor(x);
    vec3 w = fract(x);
    vec3 u = w * w * (3.0 - 2.0 * w);
    vec3 du = 6.0 * w * (1.0 - w);
    float a = lattice_hash(i);
    float b = lattice_hash(i + vec3(1, 0, 0));
    float c = lattice_hash(i + vec3(0, 1, 0));
    float d = lattice_hash(i + vec3(1, 1, 0));
    float e = lattice_hash(i + vec3(0, 0, 1));
    float f = lattice_hash(i + vec3(1, 0, 1));
    float g = lattice_hash(i + vec3(0, 1, 1));
    float h = lattice_hash(i + vec3(1, 1, 1));
    float k1 = b - a, k2 = c - a, k3 = e - a, k4 = a - b - c + d;
    float k5 = a - c - e + g, k6 = a - b - e + f, k7 = -a + b + c - d + e - f - g + h;
    float value = a + k1 * u.x + k2 * u.y + k3 * u.z + k4 * u.x * u.y + k5 * u.y * u.z
                + k6 * u.z * u.x + k7 * u.x * u.y * u.z;
    vec3 grad = du * vec3(k1 + k4 * u.y + k6 * u.z + k7 * u.y * u.z,
                          k2 + k5 * u.z + k4 * u.x + k7 * u.z * u.x,
                          k3 + k6 * u.x + k5 * u.y + k7 * u.x * u.y);
    return vec4(value, grad);
}

// An octave of `frequency` (per unit) fades out to its mean where its period spans
// fewer than about three pixels (`footprint`: the pixel's size on the surface): below
// that it would only alias.
float octave_weight(float frequency, float footprint) {
    return 1.0 - smoothstep(0.3, 0.6, frequency * footprint);
}

#endif
