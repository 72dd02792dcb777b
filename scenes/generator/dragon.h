// The Stanford dragon as pmcr's scenes use it, stored once in scenes/meshes/ and shared by every
// scene that shows it.
#pragma once

#include "gltf_writer.h"
#include "scenes.h"

namespace pmcr::scenegen {

// Where the dragon's triangles are stored, relative to scenes/: float positions, then u32
// indices (no normals: flat shaded), referenced by the dragon scenes as an external buffer.
inline constexpr const char* kDragonUri = "meshes/stanford-dragon.bin";

inline constexpr const char* kDragonCredit =
    "Stanford dragon (dragon_vrip_res2, 202,520 triangles): Stanford University Computer "
    "Graphics Laboratory, Stanford 3D Scanning Repository, used under its terms (credit, research "
    "use, no commercial use; see scenes/licenses/); scaled and translated only.";

// The dragon read from <assets>/meshes/stanford_dragon_res2.glb and placed uniformly scaled by 10
// (about 2.05 long along x, 1.44 tall, 0.92 deep, head towards -x), standing on y = 0 and
// centred on the y axis. The source's vertex normals are dropped: some 1,900 of its triangles
// are wound against them, and at this triangle density flat shading looks the same. The Stanford
// terms allow scaling, rotating and moving the model, not changing its shape.
ObjectDesc dragonObject(const SceneContext& context, int material);

}  // namespace pmcr::scenegen
