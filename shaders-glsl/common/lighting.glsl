// Direct sun plus hemispherical sky/ground ambient: enough to read a shape's relief
// without shadows. All colours are linear.
#ifndef SEDIMENT_LIGHTING_GLSL
#define SEDIMENT_LIGHTING_GLSL

vec3 hemisphere_ambient(vec3 n, vec3 sky, vec3 ground) {
    return mix(ground, sky, 0.5 + 0.5 * n.y);
}

// Lambert diffuse plus a normalised Blinn-Phong lobe.
vec3 sun_light(vec3 n, vec3 v, vec3 l, vec3 albedo, vec3 sun, float shininess, float specular) {
    float ndl = max(dot(n, l), 0.0);
    vec3 h = normalize(l + v);
    float spec = specular * (shininess + 8.0) / 25.1327 * pow(max(dot(n, h), 0.0), shininess);
    return sun * ndl * (albedo + vec3(spec));
}

// `light.w == 0`: a directional light toward `light.xyz`; `light.w == 1`: a point light
// at `light.xyz` with inverse-square falloff (`color` is its radiance at distance 1).
void light_at(vec4 light, vec3 color, vec3 world, out vec3 l, out vec3 radiance) {
    if (light.w > 0.5) {
        vec3 d = light.xyz - world;
        float d2 = max(dot(d, d), 0.01);
        l = d * inversesqrt(d2);
        radiance = color / d2;
    } else {
        l = normalize(light.xyz);
        radiance = color;
    }
}

#endif
