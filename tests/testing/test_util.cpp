#include "test_util.h"

#include <unistd.h>

namespace pmcr::test {

std::filesystem::path sourcePath(const std::string& relative) {
    return std::filesystem::path(PMCR_SOURCE_DIR) / relative;
}

std::filesystem::path tempDir(const std::string& name) {
    auto dir = std::filesystem::temp_directory_path() /
               ("pmcr-test-" + std::to_string(getpid()) + "-" + name);
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

}  // namespace pmcr::test
