// Ctrl-C handling: the first SIGINT/SIGTERM asks the render to stop at the next batch boundary
// (the image so far is still written); a second one exits at once.
#pragma once

namespace pmcr {

void installInterruptHandler();
bool interruptRequested();
void requestInterrupt();  // what the handler does; also for tests
void clearInterrupt();

}  // namespace pmcr
