// `pmcr bench`'s outputs (bench/report.h, bench/plot.h) for a synthetic bench: the table, the
// files the HTML and Markdown reports reference, results.json, the SVG plot, the method list.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "bench/plot.h"
#include "bench/report.h"
#include "core/error.h"
#include "test_util.h"

namespace pmcr {
namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

Image ramp(int width, int height, float scale) {
    Image image(width, height);
    for (size_t i = 0; i < image.rgb.size(); ++i)
        image.rgb[i] = scale * float(i % 7 + 1) / 7.0f;
    return image;
}

BenchRun implementedRun(const std::string& label, const Image& reference, float scale,
                        double seconds) {
    BenchRun run;
    run.method = {label, label, {}};
    run.image = ramp(reference.width, reference.height, scale);
    run.seconds = seconds;
    run.wallSeconds = seconds + 0.5;
    run.samples = 64;
    run.spp = 4.0;
    run.error = measureError(run.image, reference);
    run.eff = efficiency(seconds, run.error.mse);
    run.peff = efficiency(seconds, run.error.pmse);
    run.convergence = {{seconds / 4, 1.0, 4 * run.error.mse, 4 * run.error.pmse},
                       {seconds, 4.0, run.error.mse, run.error.pmse}};
    run.stats = {{"method", label}};
    return run;
}

// A bench of pt, direct (with a diagnostic image) and a method not implemented yet.
BenchReport syntheticReport() {
    BenchReport r;
    r.options.base.timeLimit = 1.0;
    r.options.base.seed = 7;
    r.options.crops = {{1, 1, 2, 2}};
    r.scene = "scenes/box.glb";
    r.device = "test device";
    r.width = 6;
    r.height = 4;
    r.reference = ramp(6, 4, 1.0f);
    r.referenceInfo = {{"path", "ref.exr"},
                       {"rendered_by_bench", false},
                       {"notes", {"a note about the reference"}}};
    BenchRun pt = implementedRun("pt", r.reference, 1.25f, 1.0);
    BenchRun direct = implementedRun("direct:light-samples=4", r.reference, 0.5f, 2.0);
    direct.diagnostics.push_back({"samples", ramp(6, 4, 3.0f)});
    for (BenchRun* run : {&pt, &direct}) {
        MetricOptions crop;
        crop.cropped = true;
        crop.crop = r.options.crops[0];
        run->cropErrors.push_back(measureError(run->image, r.reference, crop));
        run->effRatio = run->eff / pt.eff;
        run->peffRatio = run->peff / pt.peff;
    }
    BenchRun planned;
    planned.method = {"pmc-pt", "pmc-pt", {}};
    planned.implemented = false;
    planned.plannedIn = "issue 9";
    r.runs = {pt, direct, planned};
    r.exposure = 0.5f;
    r.errorScale = 0.25f;
    return r;
}

std::vector<std::string> cells(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, '|')) {
        cell.erase(0, cell.find_first_not_of(' '));
        cell.erase(cell.find_last_not_of(' ') + 1);
        out.push_back(cell);
    }
    return out;
}

TEST(BenchReport, TableHasThePapersColumnsAndOneRowPerMethod) {
    const BenchReport r = syntheticReport();
    std::stringstream text(benchTableText(r));
    std::vector<std::string> lines;
    for (std::string line; std::getline(text, line);)
        lines.push_back(line);
    ASSERT_EQ(lines.size(), 5u);  // header, rule, three methods
    EXPECT_EQ(cells(lines[0]),
              (std::vector<std::string>{"method", "time (s)", "samples (spp)", "Err", "Eff",
                                        "P-Err", "P-Eff", "Eff ratio", "P-Eff ratio"}));
    const auto pt = cells(lines[2]);
    ASSERT_EQ(pt.size(), 9u);
    EXPECT_EQ(pt[0], "pt");
    EXPECT_EQ(pt[1], "1.00");
    EXPECT_EQ(pt[7], "1.00");
    const auto direct = cells(lines[3]);
    EXPECT_EQ(direct[0], "direct:light-samples=4");
    // Eff ratio = Eff(direct) / Eff(pt), as printed.
    char expected[32];
    std::snprintf(expected, sizeof(expected), "%.2f", r.runs[1].eff / r.runs[0].eff);
    EXPECT_EQ(direct[7], expected);
    EXPECT_EQ(cells(lines[4]),
              (std::vector<std::string>{"pmc-pt", "not implemented yet (issue 9)"}));
}

TEST(BenchReport, WritesEveryFileItReferences) {
    const fs::path dir = test::tempDir("bench-report") / "out";
    const BenchReport r = syntheticReport();
    const std::vector<std::string> written = writeBenchReport(r, dir);
    for (const std::string& f : written)
        EXPECT_TRUE(fs::is_regular_file(dir / f)) << f;
    for (const char* f : {"report.html", "report.md", "results.json", "convergence-err.svg",
                          "convergence-perr.svg", "reference.png", "images/pt.png",
                          "images/pt-error.png", "images/direct-light-samples-4.samples.png",
                          "crops/reference-crop1.png", "crops/pt-crop1.png"})
        EXPECT_TRUE(fs::is_regular_file(dir / f)) << f;

    // Every image the HTML and the Markdown show exists.
    const std::string html = readText(dir / "report.html");
    const std::string md = readText(dir / "report.md");
    std::set<std::string> referenced;
    const std::regex htmlLink("(?:src|href)=\"([^\"]+)\""), mdLink("\\]\\(([^)]+)\\)");
    for (auto it = std::sregex_iterator(html.begin(), html.end(), htmlLink);
         it != std::sregex_iterator(); ++it)
        referenced.insert((*it)[1]);
    const size_t fromHtml = referenced.size();
    for (auto it = std::sregex_iterator(md.begin(), md.end(), mdLink); it != std::sregex_iterator();
         ++it)
        referenced.insert((*it)[1]);
    EXPECT_GE(fromHtml, 10u);
    for (const std::string& f : referenced)
        EXPECT_TRUE(fs::is_regular_file(dir / f)) << f;
    EXPECT_NE(html.find("images/direct-light-samples-4.samples.png"), std::string::npos);

    // One table row per method; the unimplemented one says so.
    const std::regex row("<tr class=\"method\"><td>([^<]*)</td>");
    std::vector<std::string> rows;
    for (auto it = std::sregex_iterator(html.begin(), html.end(), row);
         it != std::sregex_iterator(); ++it)
        rows.push_back((*it)[1]);
    EXPECT_EQ(rows, (std::vector<std::string>{"pt", "direct:light-samples=4", "pmc-pt"}));
    EXPECT_NE(html.find("not implemented yet (issue 9)"), std::string::npos);
    EXPECT_NE(html.find("a note about the reference"), std::string::npos);
    EXPECT_NE(md.find("| pmc-pt | not implemented yet (issue 9) |"), std::string::npos);

    const nlohmann::json results = nlohmann::json::parse(readText(dir / "results.json"));
    ASSERT_EQ(results["methods"].size(), 3u);
    const auto& pt = results["methods"][0];
    for (const char* key : {"mse", "rmse", "relmse", "pmse", "time", "eff", "peff", "eff_ratio",
                            "peff_ratio", "spp", "samples", "convergence", "crops", "images"})
        EXPECT_TRUE(pt.contains(key)) << key;
    EXPECT_DOUBLE_EQ(pt["mse"].get<double>(), r.runs[0].error.mse);
    EXPECT_FALSE(results["methods"][2]["implemented"].get<bool>());
    EXPECT_DOUBLE_EQ(results["exposure"].get<double>(), 0.5);
    EXPECT_EQ(results["reference"]["path"], "ref.exr");
}

TEST(BenchReport, OutputDirectoryIsWrittenWholeAndReplacedOnlyIfItIsAReport) {
    const fs::path root = test::tempDir("bench-dirs");
    const BenchReport r = syntheticReport();
    // An earlier report is replaced; nothing of it or of the temporaries stays.
    writeBenchReport(r, root / "a");
    std::ofstream(root / "a" / "stale.txt") << "old";
    writeBenchReport(r, root / "a");
    EXPECT_FALSE(fs::exists(root / "a" / "stale.txt"));
    EXPECT_TRUE(fs::exists(root / "a" / "report.html"));
    for (const auto& e : fs::directory_iterator(root))
        EXPECT_EQ(e.path().filename(), "a");
    // A directory holding something else is refused before anything is written.
    fs::create_directories(root / "mine");
    std::ofstream(root / "mine" / "thesis.tex") << "precious";
    EXPECT_THROW(checkBenchOutputDir(root / "mine"), Error);
    EXPECT_THROW(writeBenchReport(r, root / "mine"), Error);
    EXPECT_TRUE(fs::exists(root / "mine" / "thesis.tex"));
    EXPECT_THROW(checkBenchOutputDir(root / "no" / "such"), Error);
}

TEST(BenchReport, MethodLists) {
    const auto list = parseBenchMethods("--methods", "pt,direct:light-samples=4,erpt");
    ASSERT_EQ(list.size(), 3u);
    EXPECT_EQ(list[1].method, "direct");
    EXPECT_EQ(list[1].options.at("light-samples"), "4");
    EXPECT_EQ(list[2].method, "erpt");
    for (const char* bad :
         {"pt,,direct", "nope", "direct:light-samples", "direct:bogus=1", "pt,pt"})
        EXPECT_THROW(parseBenchMethods("--methods", bad), Error) << bad;
}

TEST(Plot, LogLogSvgHasOneLinePerSeriesAndALegend) {
    PlotAxes axes{"Err against time", "time (s)", "Err"};
    const std::string svg = logLogPlotSvg(
        axes, {{"pt", {{0.1, 1e-2}, {1.0, 1e-3}, {10.0, 1e-4}}},
               {"a<b", {{0.2, 2e-2}, {2.0, 0.0}, {4.0, 5e-3}}},  // the zero is skipped
               {"empty", {}}});
    EXPECT_EQ(svg.rfind("<svg", 0), 0u);
    EXPECT_NE(svg.find("</svg>"), std::string::npos);
    size_t polylines = 0;
    for (size_t at = svg.find("<polyline"); at != std::string::npos;
         at = svg.find("<polyline", at + 1))
        ++polylines;
    EXPECT_EQ(polylines, 2u);
    EXPECT_NE(svg.find("a&lt;b"), std::string::npos);
    EXPECT_NE(svg.find("empty (no data)"), std::string::npos);
    EXPECT_NE(svg.find(">time (s)<"), std::string::npos);
    EXPECT_NE(svg.find(">0.001<"), std::string::npos);  // a decade label on the Err axis
    EXPECT_EQ(svg.find("nan"), std::string::npos);
    EXPECT_EQ(svg.find("inf"), std::string::npos);
    // The first series falls from top left to bottom right.
    const std::regex points("points=\"([0-9.]+),([0-9.]+) [0-9., ]* ([0-9.]+),([0-9.]+)\"");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(svg, m, points));
    EXPECT_LT(std::stod(m[1]), std::stod(m[3]));
    EXPECT_LT(std::stod(m[2]), std::stod(m[4]));
}

}  // namespace
}  // namespace pmcr
