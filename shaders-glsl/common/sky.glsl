// A simple analytic daylight sky: a zenith-to-horizon gradient that warms and darkens
// as the sun sinks, and a glow around the sun. Linear colours.
#ifndef SEDIMENT_SKY_GLSL
#define SEDIMENT_SKY_GLSL

// The sky's colour at the horizon (also the haze far surfaces fade into).
vec3 horizon_haze(vec3 sun) {
    return mix(vec3(0.85, 0.55, 0.35), vec3(0.62, 0.72, 0.85), smoothstep(0.0, 0.5, max(sun.y, 0.0)));
}

vec3 sky_radiance(vec3 dir, vec3 sun) {
    float elevation = max(sun.y, 0.0);
    vec3 zenith = mix(vec3(0.10, 0.16, 0.35), vec3(0.16, 0.32, 0.75), smoothstep(0.0, 0.6, elevation));
    vec3 horizon = horizon_haze(sun);
    float up = clamp(dir.y, 0.0, 1.0);
    vec3 sky = mix(horizon, zenith, pow(up, 0.45));
    float glow = max(dot(dir, sun), 0.0);
    sky += vec3(1.0, 0.8, 0.55) * (0.35 * pow(glow, 8.0) + 4.0 * pow(glow, 900.0));
    // Below the horizon: the haze far surfaces fade into.
    if (dir.y < 0.0) {
        sky = horizon;
    }
    return sky;
}

#endif
