#include "core/paths.h"

#include <algorithm>

namespace pmcr {

bool isInsideFolder(const std::filesystem::path& path, const std::filesystem::path& folder) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path file = fs::weakly_canonical(fs::absolute(path, ec), ec);
    if (ec || file.empty()) return false;
    const fs::path dir = fs::weakly_canonical(fs::absolute(folder, ec), ec);
    if (ec || dir.empty()) return false;
    // Component by component, so that /scenes/a is not taken to hold /scenes/ab/x. A canonical
    // folder may still end in an empty component ("/scenes/"): skip it.
    auto dirEnd = dir.end();
    if (dirEnd != dir.begin() && std::prev(dirEnd)->empty()) --dirEnd;
    const auto [d, f] = std::mismatch(dir.begin(), dirEnd, file.begin(), file.end());
    return d == dirEnd && f != file.end();
}

}  // namespace pmcr
