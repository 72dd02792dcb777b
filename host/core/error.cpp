#include "core/error.h"

namespace pmcr {

void fail(const std::string& file, const std::string& message) {
    throw Error(file.empty() ? message : file + ": " + message);
}

}  // namespace pmcr
