// Nishita et al.'s (1993) single scattering through a spherical atmosphere, the GPU
// half of src/model/atmosphere.rs (same formulas, same samples, same order): the
// sky-view table's compute shader integrates it, the sky and the terrain look it up.
// Metres; radiance in units of the sun's irradiance above the air.
#ifndef SEDIMENT_ATMOSPHERE_GLSL
#define SEDIMENT_ATMOSPHERE_GLSL

const float PI = 3.14159265358979323846;
const uint VIEW_SAMPLES = 32u;
const uint SUN_SAMPLES = 12u;
const uint MS_SIZE = 32u;

// The ozone layer's tent (model::atmosphere::OZONE_PEAK_M, OZONE_HALF_WIDTH_M).
const float OZONE_PEAK_M = 25000.0;
const float OZONE_HALF_WIDTH_M = 15000.0;

struct Air {
    vec4 rayleigh;  // rgb scattering per metre at the ground, w scale height
    vec4 mie;       // x scattering, y extinction per metre at the ground, z scale height, w g
    vec4 ground;    // rgb albedo, w ground radius
    vec4 sun;       // rgb irradiance above the air, w top radius
    vec4 ozone;     // rgb absorption per metre at the layer's peak, w unused
};

vec3 air_extinction(Air a, float h) {
    float ozone = max(1.0 - abs(h - OZONE_PEAK_M) / OZONE_HALF_WIDTH_M, 0.0);
    return a.rayleigh.rgb * exp(-h / a.rayleigh.w) + vec3(a.mie.y * exp(-h / a.mie.z))
        + a.ozone.rgb * ozone;
}

float rayleigh_phase(float mu) {
    return 3.0 / (16.0 * PI) * (1.0 + mu * mu);
}

// Cornette & Shanks.
float mie_phase(float mu, float g) {
    float g2 = g * g;
    return 3.0 / (8.0 * PI) * (1.0 - g2) * (1.0 + mu * mu)
        / ((2.0 + g2) * pow(max(1.0 + g2 - 2.0 * g * mu, 1e-6), 1.5));
}

vec3 air_total_scattering(Air a, float h) {
    return a.rayleigh.rgb * exp(-h / a.rayleigh.w) + vec3(a.mie.x * exp(-h / a.mie.z));
}

vec3 air_scattering(Air a, float h, float mu) {
    return a.rayleigh.rgb * (exp(-h / a.rayleigh.w) * rayleigh_phase(mu))
        + vec3(a.mie.x * exp(-h / a.mie.z) * mie_phase(mu, a.mie.w));
}

float radius_at(float r, float mu, float t) {
    return sqrt(t * t + 2.0 * r * mu * t + r * r);
}

// (top - r)(top + r) + (r mu)^2: the metres survive f32 at planet scale.
float distance_to_top(Air a, float r, float mu) {
    float top = a.sun.w;
    float disc = (top - r) * (top + r) + (r * mu) * (r * mu);
    return max(-r * mu + sqrt(max(disc, 0.0)), 0.0);
}

// Negative when the ray misses the ground.
float distance_to_ground(Air a, float r, float mu) {
    float g = a.ground.w;
    float disc = (r * mu) * (r * mu) - (r - g) * (r + g);
    if (mu < 0.0 && disc >= 0.0) {
        return max(-r * mu - sqrt(disc), 0.0);
    }
    return -1.0;
}

// Sample i of n along a ray of length far: distance (x) and length (y), crowded toward
// the start (t = far s^2).
vec2 ray_sample(uint i, uint n, float far) {
    float s = (float(i) + 0.5) / float(n);
    return vec2(far * s * s, far * 2.0 * s / float(n));
}

vec3 transmittance_to_space(Air a, float r, float mu) {
    if (distance_to_ground(a, r, mu) >= 0.0) {
        return vec3(0.0);
    }
    float far = distance_to_top(a, r, mu);
    vec3 depth = vec3(0.0);
    for (uint i = 0u; i < SUN_SAMPLES; ++i) {
        vec2 s = ray_sample(i, SUN_SAMPLES, far);
        depth += air_extinction(a, radius_at(r, mu, s.x) - a.ground.w) * s.y;
    }
    return exp(-depth);
}

// The sky-view table's elevation of row coordinate v (Hillaire 2020: denser at the
// horizon) and its inverse.
float elevation_of_v(float v) {
    float s = 2.0 * v - 1.0;
    return sign(s) * s * s * (0.5 * PI);
}

// Table coordinates of a view direction (y up) with the sun at azimuth `sun_azimuth`
// (radians from +x toward +z): u the azimuth from the sun's over pi, v the elevation.
vec2 sky_view_uv(vec3 view, float sun_azimuth) {
    float e = asin(clamp(view.y, -1.0, 1.0));
    float s = sqrt(abs(e) / (0.5 * PI)) * sign(e);
    float az = atan(view.z, view.x) - sun_azimuth;
    // The azimuth from the sun's wrapped into -pi..pi (a round, not atan(sin, cos):
    // the same angle for two transcendentals fewer in every sky pixel).
    float rel = abs(az - 2.0 * PI * round(az / (2.0 * PI)));
    return vec2(rel / PI, 0.5 + 0.5 * s);
}

#endif
