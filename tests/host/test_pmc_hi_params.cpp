// PMC-HI's mixture slots for a scene (host/methods/pmc_hi/pmc_hi.h pmcHiParamsFor): one light
// component per light up to --max-light-components, else one shared by all; the environment
// takes one of the PMC_HI_MAX_LIGHTS light slots, so that the push constants keep their size;
// --initial-alpha must weigh exactly the components there are.
#include <gtest/gtest.h>

#include "core/error.h"
#include "methods/pmc_hi/pmc_hi.h"

namespace pmcr {
namespace {

PmcHiOptions options(uint32_t maxLights) {
    PmcHiOptions o;
    o.maxLightComponents = maxLights;
    return o;
}

TEST(PmcHiParams, LightComponentsSharedAndTheEnvironmentSlot) {
    struct Case {
        uint32_t maxLights, lights;
        bool environment;
        uint32_t lightComponents;
        bool shared;
    };
    const Case cases[] = {
        {4, 2, false, 2, false},
        {4, 4, false, 4, false},
        {4, 5, false, 1, true},
        {4, 4, true, 4, false},  // under the option's limit, the environment takes no light's place
        {8, 8, false, 8, false},
        {8, 7, true, 7, false},
        {8, 8, true, 1, true},   // 8 lights and the environment: 9 > PMC_HI_MAX_LIGHTS slots
        {8, 0, true, 0, false},  // a scene lit by its environment (and punctual lights) alone
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(testing::Message() << c.lights << " lights, max " << c.maxLights
                                        << (c.environment ? ", environment" : ""));
        const gpu::PmcHiParams p = pmcHiParamsFor(options(c.maxLights), c.lights, c.environment);
        EXPECT_EQ(p.lightComponents, c.lightComponents);
        EXPECT_EQ(p.sharedLight != 0u, c.shared);
        EXPECT_EQ((p.flags & gpu::PMC_HI_FLAG_ENVIRONMENT) != 0u, c.environment);
        const uint32_t slots = gpu::PMC_HI_LIGHT + c.lightComponents + (c.environment ? 1u : 0u);
        EXPECT_EQ(pmcHiComponents(p), slots);
        EXPECT_LE(slots, gpu::PMC_HI_MAX_COMPONENTS);
    }
}

TEST(PmcHiParams, InitialAlphaWeighsEveryComponent) {
    PmcHiOptions o = options(8);
    o.initialAlpha = {0.5, 0.1, 0.2, 0.3};  // BSDF, two lights, the environment
    const gpu::PmcHiParams p = pmcHiParamsFor(o, 2, true);
    EXPECT_NE(p.flags & gpu::PMC_HI_FLAG_INITIAL_ALPHA, 0u);
    EXPECT_FLOAT_EQ(p.initialAlpha[gpu::PMC_HI_BSDF], 0.5f);
    EXPECT_FLOAT_EQ(p.initialAlpha[gpu::PMC_HI_LIGHT + 1], 0.2f);
    EXPECT_FLOAT_EQ(p.initialAlpha[gpu::PMC_HI_LIGHT + 2], 0.3f);  // the environment's slot
    EXPECT_THROW(pmcHiParamsFor(o, 2, false), Error);                // one weight too many
    EXPECT_THROW(pmcHiParamsFor(o, 3, true), Error);                 // one too few
}

}  // namespace
}  // namespace pmcr
