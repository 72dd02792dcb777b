// The film of energy-redistribution methods (ERPT, PMC-ER): 64-bit fixed-point deposits
// (shared/chain_types.h SplatPixel), order-independent and so deterministic. Each seed pass is
// added into a host accumulator and the device film cleared, so an interrupted render keeps the
// completed passes only (a partial pass would be a biased, darker estimate).
#pragma once

#include <vector>

#include "image/image.h"
#include "shared/host_device.h"
#include "vk/buffer.h"

namespace pmcr {

class SplatFilm {
public:
    SplatFilm(vk::Context& context, int width, int height);

    const vk::Buffer& pixels() const { return m_pixels; }
    // Adds the device film into the host accumulator and clears it: one pass is complete.
    // The device film's deposits join the completed passes: `count` passes run together.
    void completePass(uint32_t count = 1);
    // Adds `count` completed passes' deposits made on another device film (3 per pixel, read
    // back by the caller: PMC-ER's lanes each have their own) into the accumulator.
    void addPasses(const std::vector<uint64_t>& deposits, uint32_t count);
    int completedPasses() const { return m_passes; }
    // Per-pass average: sum over passes / passes, in pixel-value units (e_d per deposit).
    Image resolve(float depositEnergy) const;
    // Every deposit so far (completed passes and the device film's), times `scale` per unit
    // deposited: for splats that are not counted in passes (bdpt's light tracing).
    Image resolveTotal(double scale);

private:
    int m_width;
    int m_height;
    vk::Buffer m_pixels;
    std::vector<uint64_t> m_accumulated;  // 3 per pixel
    int m_passes = 0;
};

}  // namespace pmcr
