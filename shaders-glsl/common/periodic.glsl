// Indices on a periodic field, shared by the passes that walk one (dune_shadow.comp,
// horizon.comp).
#ifndef SEDIMENT_PERIODIC_GLSL
#define SEDIMENT_PERIODIC_GLSL

// `i` mod `n` as the CPU twins' rem_euclid, without an integer division: x86 has no
// vector one, so llvmpipe divides lane by lane. The float quotient's floor is exact
// for |i| < 2^23: the added half keeps it at least 0.5 / n from a whole number, far
// more than its rounding. (Scalar, not ivec2: naga 30 misreads integer vector modulo.)
int wrap_periodic(int i, int n) {
    return i - n * int(floor((float(i) + 0.5) / float(n)));
}

#endif
