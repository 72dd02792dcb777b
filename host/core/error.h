// pmcr's one error type. Its message is the single line the CLI prints for bad input:
// it names the file (when there is one) and the problem, e.g.
//   "scenes/box.gltf: accessor 3 reads past the end of buffer view 1".
#pragma once

#include <stdexcept>
#include <string>

namespace pmcr {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// Throws pmcr::Error("<file>: <message>").
[[noreturn]] void fail(const std::string& file, const std::string& message);

}  // namespace pmcr
