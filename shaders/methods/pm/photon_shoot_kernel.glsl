// The body of photon_shoot.comp and photon_shoot_all_lights.comp: one photon path per
// invocation. The path leaves a light (photon_emission.glsl), scatters by BSDF sampling with the
// adjoint BSDF, and stores a photon at every hit whose BSDF has a non-delta lobe, the first hit
// included (the final gather reads the whole incident light at its hit points from the map,
// Jensen 2001 sec. 9.2; the gather point's own direct light is estimated by light sampling and
// skips PHOTON_DIRECT photons). A photon after one or more delta scatterings and no other is a
// caustic photon (L S+ D). Russian roulette from rrDepth on the path's throughput.
//
// Path `path` stores its photons in slots path * slotsPerPath + 0, 1, ..., in order, and clears
// the flags of the slot after its last: the host reads them in path order, so the map is the
// same bit for bit for a seed (host/methods/pm/photon_map.cpp).
#include "shared/host_device.h"

layout(local_size_x = WORKGROUP_SIZE) in;
layout(push_constant, scalar) uniform PushBlock { PhotonShootPush push; };

#include "common/film.glsl"
#include "common/octahedral.glsl"
#include "common/shading.glsl"
#include "methods/pm/photon_emission.glsl"

layout(set = WORK_SET, binding = PM_BINDING_SLOTS, scalar) writeonly buffer SlotBuffer {
    Photon slots[];
};

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint rays = 0u;
    uint full = 0u;
    if (i < push.pathCount) {
        uint path = push.pathOffset + i;
        uint base = path * push.slotsPerPath;
        Rng rng = rngCreate(hash3(push.seed, push.pass, path));
        PhotonRay ray = emitPhoton(rng);
        vec3 beta = ray.power * push.pathScale;
        vec3 throughput = vec3(1.0);  // beta / (the emitted flux): what roulette looks at
        bool specularChain = true;    // every scattering so far was through a delta lobe
        uint stored = 0u;
        bool alive = maxComponent(beta) > 0.0 && isFinite(beta);
        for (uint hitIndex = 1u; alive && hitIndex <= push.maxDepth; ++hitIndex) {
            Hit hit;
            rays += 1u;
            if (!traceClosest(ray.origin, ray.dir, FLOAT_MAX, hit)) break;
            SurfacePoint s = surfaceAt(hit.triangle, vec2(hit.b1, hit.b2));
            beta *= segmentTransmittance(s, ray.dir, hit.t);
            vec3 wo = -ray.dir;
            ShadingPoint sh = makeShadingPoint(s, wo);
            sh.bsdf.adjoint = true;  // the clear coat's adjoint term (bsdf.glsl clearcoatNormal)
            if (bsdfHasNonDelta(sh.bsdf)) {
                if (stored == push.slotsPerPath) {
                    full = 1u;
                    break;
                }
                uint flags = PHOTON_STORED | (hitIndex == 1u ? PHOTON_DIRECT : 0u) |
                             (hitIndex > 1u && specularChain ? PHOTON_CAUSTIC : 0u) |
                             (hitIndex << PHOTON_HIT_SHIFT);
                slots[base + stored] = Photon(s.position, packSnorm2x16(octEncode(wo)), beta, flags);
                stored += 1u;
            }
            if (hitIndex == push.maxDepth) break;
            BsdfSample bs;
            vec3 wi;
            float uLobe = rngNext(rng);
            vec2 uDir = rngNext2(rng);
            float uRoulette = rngNext(rng);
            if (!shadingSample(sh, uLobe, uDir, bs, wi)) break;
            // The adjoint BSDF (Veach 1997 sec. 5.3.2, pbrt-v4 TransportMode::Importance): no
            // 1 / eta^2 on transmission (bsdf.glsl divides by it for radiance), and the shading
            // normal's correction |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|) (Veach 1997 eq. 5.19); the
            // clear coat's adjoint term is in bs.f.
            vec3 factor = bs.f * abs(bs.wi.z) / bs.pdf;
            factor *= sqr(bs.eta);
            float denom = abs(dot(wo, sh.ng)) * abs(bs.wi.z);
            factor *= denom > 0.0 ? abs(sh.woLocal.z) * abs(dot(wi, sh.ng)) / denom : 0.0;
            beta *= factor;
            throughput *= factor;
            specularChain = specularChain && bs.delta;
            if (hitIndex >= push.rrDepth) {
                float q = max(0.0, 1.0 - maxComponent(throughput));
                if (uRoulette < q) break;
                beta /= 1.0 - q;
                throughput /= 1.0 - q;
            }
            alive = maxComponent(beta) > 0.0 && isFinite(beta);
            ray.origin = spawnOrigin(sh, wi);
            ray.dir = wi;
        }
        if (stored < push.slotsPerPath) slots[base + stored].flags = 0u;
    }
    counterAdd(COUNTER_RAYS, rays);
    counterAdd(COUNTER_PM_SLOTS_FULL, full);
}
