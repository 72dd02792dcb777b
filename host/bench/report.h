// What `pmcr bench` writes: DIR/report.html and DIR/report.md (a table per scene like the
// papers', images side by side at one exposure, error images at one scale, crops, diagnostics,
// convergence plots), DIR/results.json (every figure, for scripts), and the images and SVG plots
// they show. The table printed to stdout has the same rows.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "bench/bench.h"

namespace pmcr {

// The results table's header and rows as text cells: method | time (s) | samples (spp) | Err |
// Eff | P-Err | P-Eff | Eff ratio | P-Eff ratio. A method not implemented yet has two cells:
// its label and "not implemented yet (issue N)".
std::vector<std::string> benchTableHeader();
std::vector<std::vector<std::string>> benchTableRows(const BenchReport& report);
// The table as aligned plain text, one line per row (for stdout).
std::string benchTableText(const BenchReport& report);

// Fails early (pmcr::Error) unless `dir` can be written: its parent directory exists, and it
// does not exist, is empty, or is an earlier bench report (holds results.json), which is replaced.
void checkBenchOutputDir(const std::filesystem::path& dir);

// Writes every file into a temporary directory beside `dir`, then renames it to `dir`: there is
// never a half-written report. Returns the files written, relative to `dir`.
std::vector<std::string> writeBenchReport(const BenchReport& report,
                                          const std::filesystem::path& dir);

}  // namespace pmcr
