// Seconds since the process started (the first call, made first thing in main): the stats'
// wall_seconds, what a user waits for from the command to the image written.
#pragma once

namespace pmcr {

double processSeconds();

}  // namespace pmcr
