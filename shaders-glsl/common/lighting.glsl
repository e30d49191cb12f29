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

#endif
