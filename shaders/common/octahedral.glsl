// Unit vectors as two floats: the octahedral map (Cigolle, Donow, Evangelakos, Mara, McGuire,
// Meyer 2014, "A Survey of Efficient Representations for Independent Unit Vectors", sec. 3.3):
// the unit sphere projected onto the octahedron |x| + |y| + |z| = 1, whose lower half is folded
// over the upper one into the square [-1, 1]^2. Stored as floats the round trip is exact to a
// few ulps, which is how path records keep a direction towards the environment.
#ifndef PMCR_OCTAHEDRAL_GLSL
#define PMCR_OCTAHEDRAL_GLSL

// -1 for negative components, else +1 (sign() would give 0 at 0).
vec2 signNotZero(vec2 v) { return vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0); }

vec2 octEncode(vec3 d) {
    vec2 p = d.xy / (abs(d.x) + abs(d.y) + abs(d.z));
    return d.z <= 0.0 ? (1.0 - abs(p.yx)) * signNotZero(p) : p;
}

vec3 octDecode(vec2 e) {
    vec3 d = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (d.z < 0.0) d.xy = (1.0 - abs(d.yx)) * signNotZero(d.xy);
    return normalize(d);
}

#endif
