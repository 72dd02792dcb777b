// Helpers shared by the test suites.
#pragma once

#include <filesystem>
#include <string>

namespace pmcr::test {

// Absolute path of a file in the source tree, e.g. sourcePath("scenes/furnace.gltf").
std::filesystem::path sourcePath(const std::string& relative);

// A fresh, empty temporary directory for one test (removed by the OS, not by the test).
std::filesystem::path tempDir(const std::string& name);

}  // namespace pmcr::test
