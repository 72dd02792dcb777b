#include "render_test.h"

#include <map>
#include <memory>

#include "gpu_test.h"
#include "scene/gltf_loader.h"
#include "test_util.h"

namespace pmcr::test {

const Scene& testScene(const std::string& relativePath) {
    static std::map<std::string, std::unique_ptr<Scene>> cache;
    auto& slot = cache[relativePath];
    if (!slot) slot = std::make_unique<Scene>(loadScene(sourcePath(relativePath)));
    return *slot;
}

RenderResult renderForTest(const Scene& scene, RenderSettings settings) {
    settings.quiet = true;
    resolveImageSize(scene, settings);
    return renderScene(gpuContext(), scene, settings);
}

glm::dvec3 imageMean(const Image& image) {
    glm::dvec3 sum(0.0);
    for (size_t i = 0; i < image.pixelCount(); ++i)
        sum += glm::dvec3(image.rgb[3 * i], image.rgb[3 * i + 1], image.rgb[3 * i + 2]);
    return sum / double(image.pixelCount());
}

}  // namespace pmcr::test
