// Small maths shared by every kernel.
#ifndef PMCR_MATH_GLSL
#define PMCR_MATH_GLSL

const float PI = 3.14159265358979323846;
const float TWO_PI = 6.28318530717958647692;
const float INV_PI = 0.31830988618379067154;
const float INV_TWO_PI = 0.15915494309189533577;
const float INV_FOUR_PI = 0.07957747154594766788;
const float FLOAT_MAX = 3.402823466e38;
// Largest float below 1: samples stay in [0, 1).
const float ONE_MINUS_EPSILON = 0.99999994;

float sqr(float x) { return x * x; }
float safeSqrt(float x) { return sqrt(max(x, 0.0)); }
float maxComponent(vec3 v) { return max(v.x, max(v.y, v.z)); }

// Rec. 709 / sRGB luminance, as host/scene/scene.cpp's luminance().
float luminance(vec3 rgb) { return dot(rgb, vec3(0.2126, 0.7152, 0.0722)); }

bool isFinite(float x) { return !isnan(x) && !isinf(x); }
bool isFinite(vec3 v) { return isFinite(v.x) && isFinite(v.y) && isFinite(v.z); }

// Orthonormal basis around unit n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
void orthonormalBasis(vec3 n, out vec3 t, out vec3 b) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

// A shading frame: local z = normal.
struct Frame {
    vec3 t;
    vec3 b;
    vec3 n;
};

Frame frameFromNormal(vec3 n) {
    Frame f;
    f.n = n;
    orthonormalBasis(n, f.t, f.b);
    return f;
}
vec3 toLocal(Frame f, vec3 v) { return vec3(dot(v, f.t), dot(v, f.b), dot(v, f.n)); }
vec3 toWorld(Frame f, vec3 v) { return v.x * f.t + v.y * f.b + v.z * f.n; }

// Offsets a ray origin off the surface along the geometric normal so that the new ray does not
// re-hit the surface it leaves: a few ulps in integer space far from the origin, a small
// absolute step near it (Wachter and Binder 2019, "A Fast and Robust Method for Avoiding
// Self-Intersection", Ray Tracing Gems ch. 6). `n` must point to the side the ray leaves to.
vec3 offsetRayOrigin(vec3 p, vec3 n) {
    const float originScale = 1.0 / 32.0;
    const float floatScale = 1.0 / 65536.0;
    const float intScale = 256.0;
    ivec3 ofi = ivec3(intScale * n);
    vec3 pi = vec3(intBitsToFloat(floatBitsToInt(p.x) + (p.x < 0.0 ? -ofi.x : ofi.x)),
                   intBitsToFloat(floatBitsToInt(p.y) + (p.y < 0.0 ? -ofi.y : ofi.y)),
                   intBitsToFloat(floatBitsToInt(p.z) + (p.z < 0.0 ? -ofi.z : ofi.z)));
    return vec3(abs(p.x) < originScale ? p.x + floatScale * n.x : pi.x,
                abs(p.y) < originScale ? p.y + floatScale * n.y : pi.y,
                abs(p.z) < originScale ? p.z + floatScale * n.z : pi.z);
}

#endif
