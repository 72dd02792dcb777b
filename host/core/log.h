// Minimal logging to stderr. Warnings are for input pmcr accepts but does not fully support
// (an ignored glTF extension, a punctual light); errors go through pmcr::Error instead.
//
// Bad input is one line on stderr (README): `pmcr render` holds its messages while it loads and
// checks the scene, so that an error found then is all the user sees; the held messages are
// printed, in order, once the render goes ahead (`--verbose` prints them as they come).
#pragma once

#include <string>

namespace pmcr::log {

void setQuiet(bool quiet);
bool quiet();
void info(const std::string& message);     // suppressed by --quiet
void warning(const std::string& message);  // always printed, prefixed "warning: "

// From hold() on, info and warning lines are kept instead of printed (info still suppressed by
// --quiet). release() prints what was kept and prints again as messages come; discard() drops
// what was kept (the command failed: its error line is the only one) and stops holding.
void hold();
void release();
void discard();

}  // namespace pmcr::log
