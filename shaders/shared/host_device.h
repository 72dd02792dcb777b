// The one header shared by the C++ host and the GLSL kernels (nvpro `host_device.h` style).
// Every struct that crosses the host/device boundary, every binding number, workgroup size and
// push-constant layout is defined once, here or in the concept headers this file includes.
// Shaders use scalar block layout (GL_EXT_scalar_block_layout), so the C++ side only has to
// match plain C packing: padding fields are written out and sizes are static_asserted.
#ifndef PMCR_HOST_DEVICE_H
#define PMCR_HOST_DEVICE_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace pmcr::gpu {
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using uvec2 = glm::uvec2;
using uvec3 = glm::uvec3;
using uvec4 = glm::uvec4;
using ivec2 = glm::ivec2;
using uint = uint32_t;
using uint64_t = std::uint64_t;
#define PMCR_CHECK_SIZE(T, n) static_assert(sizeof(T) == (n), #T " must match its GLSL scalar layout")
#define PMCR_CONST static constexpr
#else
// 64-bit integers (fixed-point splat film); the device feature shaderInt64 is required.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#define PMCR_CHECK_SIZE(T, n)
#define PMCR_CONST const
#endif

#include "shared/bindings.h"
#include "shared/scene_types.h"
#include "shared/render_types.h"
#include "shared/path_types.h"
#include "shared/chain_types.h"
#include "shared/pmc_hi_types.h"
#include "shared/pmc_er_types.h"
#include "shared/mlt_types.h"
#include "shared/pssmlt_types.h"
#include "shared/bdpt_types.h"
#include "shared/photon_types.h"

#ifdef __cplusplus
}  // namespace pmcr::gpu
#endif
#endif  // PMCR_HOST_DEVICE_H
