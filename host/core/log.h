// Minimal logging to stderr. Warnings are for input pmcr accepts but does not fully support
// (an ignored glTF extension, a punctual light); errors go through pmcr::Error instead.
#pragma once

#include <string>

namespace pmcr::log {

void setQuiet(bool quiet);
bool quiet();
void info(const std::string& message);     // suppressed by --quiet
void warning(const std::string& message);  // always printed, prefixed "warning: "

}  // namespace pmcr::log
