// A film of water over calcite (Tortelli & Walter 4.2, beyond the paper): water's
// Fresnel reflectance, the film's highlight of a spherical lamp, and the darker, deeper
// colour of the calcite under it. Shared by the grown speleothems
// (`speleothem/surface.glsl`) and the cave's Short-profile ones (`cave/cave_wall.frag`).
#ifndef SEDIMENT_WET_FILM_GLSL
#define SEDIMENT_WET_FILM_GLSL

// Water's reflectance at normal incidence: (1.33 - 1)^2 / (1.33 + 1)^2.
const float WATER_F0 = 0.02;

// Schlick's Fresnel for water at incidence cosine `c` (clamped: a unit vectors' dot
// product can pass 1 by a rounding, and pow of a negative base is undefined).
float water_fresnel(float c) {
    return WATER_F0 + (1.0 - WATER_F0) * pow(clamp(1.0 - c, 0.0, 1.0), 5.0);
}

// The film's highlight of the lamp, a sphere of radius `radius` at `lamp`, per unit of
// the radiance it sends to `world`: GGX (Walter et al. 2007) with the height-correlated
// Smith visibility (Heitz 2014) and Schlick's Fresnel for water, toward the point of
// the sphere nearest the mirror direction `r`, the lobe widened by the sphere's
// angular size and renormalised so the sphere gives what a point lamp would (Karis
// 2013). Times n.l, and pi: a lamp's `radiance` lights a white diffuser to 1 here.
float film_highlight(vec3 n, vec3 v, vec3 r, vec3 world, vec3 lamp, float radius, float alpha) {
    vec3 to = lamp - world;
    vec3 across = dot(to, r) * r - to;
    vec3 l = normalize(to + across * clamp(radius / max(length(across), 1e-6), 0.0, 1.0));
    float nl = dot(n, l);
    if (nl <= 0.0) {
        return 0.0;
    }
    float wide = clamp(alpha + radius / (2.0 * length(to)), 0.0, 1.0);
    float norm = (alpha / wide) * (alpha / wide);
    float a2 = wide * wide;
    float nv = max(dot(n, v), 1e-4);
    vec3 h = normalize(l + v);
    float nh = max(dot(n, h), 0.0);
    float k = nh * nh * (a2 - 1.0) + 1.0;
    float d = a2 / (3.14159265 * k * k);
    float vis = 0.5 / (nl * sqrt(nv * nv * (1.0 - a2) + a2) + nv * sqrt(nl * nl * (1.0 - a2) + a2));
    float f = water_fresnel(dot(v, h));
    return 3.14159265 * norm * d * vis * f * nl;
}

// Lekner & Dorf (1988): the albedo of a rough surface of albedo `a` under water. The
// water's surface reflects WATER_DIFFUSE_R of diffuse light from outside; from inside
// it lets out (1 - WATER_DIFFUSE_R) / n^2 and reflects the rest, p, back down to the
// calcite, so the light goes back and forth: (1 - R) a (1 - p) / (1 - p a).
const float WATER_DIFFUSE_R = 0.066;
const float WATER_N = 1.33;
vec3 wet_albedo(vec3 a) {
    float out_share = (1.0 - WATER_DIFFUSE_R) / (WATER_N * WATER_N);
    float p = 1.0 - out_share;
    return (1.0 - WATER_DIFFUSE_R) * a * out_share / (1.0 - p * a);
}

#endif
