// PMC-ER's pool of image positions (Lai, Fan, Chenney and Dyer 2007, sec. 4.5 "Regeneration":
// "a pool of stratified pixel positions ... we keep asking the pool to give us the next unused
// stratified pixel position"), stratified per pixel: a pool of `rounds` rounds hands every pixel
// exactly `rounds` positions, one per round.
//
// Within a round the pixels come in bit-reversed Morton order (the Z-order curve of the smallest
// power-of-two grid that holds the image, its index bits reversed; pixels outside the image are
// skipped) under a random toroidal shift of the image per round: any run of consecutive positions
// is spread evenly over the image, as the paper's regeneration wants. Within a pixel, the
// position is the path tracer's: sample `firstSample + round` of the pixel's own sampler
// sequence (shaders/common/sampler.glsl, PT_SOURCE_LIST), so that all the positions a pixel gets
// over a render are one stratified sequence, as path tracing's samples are (an independent
// jitter per pass left the coverage of the light's edge pixels 30 times noisier than `pt`'s).
//
// Why per pixel: a path-traced position then contributes to its own pixel exactly as a
// `rounds`-spp path tracer's sample does, so the seed paths PMC-ER deposits at their own pixel
// (its --redistribute indirect, as ERPT's) carry no noise from the count of positions a pixel
// got. PMC-PT's image-wide R2 pool (methods/pmc_pt/pixel_population.h PositionPool) puts 2 to 6 of
// every 4 P positions in a pixel, which made that count noise dominate on the light's pixels.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/random.h"

namespace pmcr {

struct PoolSample {
    uint32_t pixel;        // linear pixel index
    uint32_t sampleIndex;  // in the pixel's sampler sequence
};

class StratifiedPixelPool {
public:
    // Samples firstSample .. firstSample + rounds - 1 of every pixel. With `lanes` > 1, the
    // share of lane `lane`: the positions l, l + lanes, l + 2 lanes, ... of the whole sequence
    // (the lanes' pools, made from equal generators, share the shifts and split the positions;
    // any run of a lane's consecutive positions is still spread over the image).
    StratifiedPixelPool(int width, int height, uint32_t rounds, uint32_t firstSample, Pcg32& rng,
                        uint32_t lane = 0, uint32_t lanes = 1);

    // This lane's positions.
    uint64_t size() const {
        const uint64_t all = uint64_t(m_rounds) * uint64_t(m_width) * uint64_t(m_height);
        return all / m_lanes + (m_lane < all % m_lanes ? 1 : 0);
    }
    uint64_t remaining() const { return size() - m_used; }
    // The next min(count, remaining()) samples.
    std::vector<PoolSample> next(uint32_t count);

private:
    // Advances m_code (and the round) to the next code of the current round inside the image,
    // and decodes it into m_point.
    bool advance();

    int m_width;
    int m_height;
    uint32_t m_rounds;
    uint32_t m_firstSample;
    Pcg32 m_rng;
    int m_bitsX = 0, m_bitsY = 0;  // the power-of-two grid: 2^bitsX by 2^bitsY
    uint32_t m_round = 0;
    uint64_t m_code = 0;           // next Morton index of the round, before bit reversal
    glm::ivec2 m_shift{0};         // the round's toroidal shift
    glm::ivec2 m_point{0};         // m_code's pixel before the shift (advance())
    uint64_t m_used = 0;
    uint32_t m_lane = 0;
    uint32_t m_lanes = 1;
    uint64_t m_seen = 0;           // positions of every lane passed so far
};

}  // namespace pmcr
