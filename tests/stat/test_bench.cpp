// `pmcr bench` on a tiny scene, in-process on the test device: the report, its table rows and
// files, the figures in results.json; and the convergence snapshots it plots.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

#include "bench/bench.h"
#include "bench/report.h"
#include "gpu_test.h"
#include "render_test.h"
#include "test_util.h"

namespace pmcr::test {
namespace {

namespace fs = std::filesystem;

class Bench : public GpuTest {};

std::string readText(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// A snapshot is the image so far: bit for bit the render that stops at its sample count.
TEST_F(Bench, SnapshotsAreTheImageSoFar) {
    const Scene& scene = testScene("scenes/cornell-classic.glb");
    RenderSettings s;
    s.method = "pt";
    s.width = 8;  // 64 pixels: every dispatch is a whole pass, so batches end between passes
    s.height = 8;
    s.spp = 24;
    s.snapshotSpp = {1.0, 2.0, 9.0};
    const RenderResult r = renderForTest(scene, s);
    ASSERT_GE(r.snapshots.size(), 1u);
    double previousSpp = 0.0, previousSeconds = -1.0;
    for (const Snapshot& snap : r.snapshots) {
        EXPECT_GT(snap.samplesPerPixel, previousSpp);
        EXPECT_GE(snap.seconds, previousSeconds);
        EXPECT_LT(snap.samplesPerPixel, 24.0);
        previousSpp = snap.samplesPerPixel;
        previousSeconds = snap.seconds;
        ASSERT_EQ(snap.samplesPerPixel, std::floor(snap.samplesPerPixel));
        RenderSettings partial = s;
        partial.spp = uint32_t(snap.samplesPerPixel);
        partial.snapshotSpp.clear();
        EXPECT_EQ(snap.image.rgb, renderForTest(scene, partial).output.image.rgb)
            << "snapshot at " << snap.samplesPerPixel << " spp";
    }
    EXPECT_GE(r.snapshots.back().samplesPerPixel, 9.0);  // the last scheduled point was taken
    EXPECT_LE(r.samplingSeconds, r.seconds);
}

TEST_F(Bench, ReportForATinyScene) {
    const Scene& scene = testScene("scenes/cornell-classic.glb");
    BenchOptions o;
    o.methods = parseBenchMethods("--methods", "pt,direct,erpt");
    o.base.timeLimit = 0.5;
    o.base.width = 32;
    o.base.height = 32;
    o.base.quiet = true;
    o.referenceSpp = 64;
    o.crops = {{8, 8, 8, 8}};
    BenchReport report = prepareBench(scene, o);
    runBench(gpuContext(), scene, report);
    ASSERT_FALSE(report.interrupted);
    const fs::path dir = tempDir("bench") / "report";
    writeBenchReport(report, dir);

    // The HTML table: one row per method, erpt reported as not implemented.
    const std::string html = readText(dir / "report.html");
    const std::regex row("<tr class=\"method\"><td>([^<]*)</td>");
    std::vector<std::string> rows;
    for (auto it = std::sregex_iterator(html.begin(), html.end(), row);
         it != std::sregex_iterator(); ++it)
        rows.push_back((*it)[1]);
    EXPECT_EQ(rows, (std::vector<std::string>{"pt", "direct", "erpt"}));
    EXPECT_NE(
        html.find("<td>erpt</td><td class=\"status\" colspan=\"8\">not implemented yet (issue 7)"),
        std::string::npos);
    // Every file it shows exists.
    const std::regex link("(?:src|href)=\"([^\"]+)\"");
    int links = 0;
    for (auto it = std::sregex_iterator(html.begin(), html.end(), link);
         it != std::sregex_iterator(); ++it, ++links)
        EXPECT_TRUE(fs::is_regular_file(dir / (*it)[1].str())) << (*it)[1];
    EXPECT_EQ(links, 10);  // reference and its crop, 2 x (image, error, crop), 2 plots
    for (const char* f : {"report.md", "results.json", "convergence-err.svg", "reference.exr",
                          "reference.json", "images/pt.exr", "images/direct.json"})
        EXPECT_TRUE(fs::is_regular_file(dir / f)) << f;
    EXPECT_NE(readText(dir / "report.md").find("| erpt | not implemented yet (issue 7) |"),
              std::string::npos);

    // The figures: Eff = 1 / (T Err), ratios to pt, the same time budget for both methods.
    const nlohmann::json results = nlohmann::json::parse(readText(dir / "results.json"));
    ASSERT_EQ(results["methods"].size(), 3u);
    const auto& pt = results["methods"][0];
    const auto& direct = results["methods"][1];
    for (const auto* m : {&pt, &direct}) {
        const double t = (*m)["time"].get<double>(), mse = (*m)["mse"].get<double>();
        EXPECT_GE(t, 0.5) << (*m)["label"];
        EXPECT_LT(t, 5.0) << (*m)["label"];
        EXPECT_GT(mse, 0.0);
        EXPECT_NEAR((*m)["eff"].get<double>(), 1.0 / (t * mse), 1e-9 / (t * mse));
        EXPECT_NEAR((*m)["peff"].get<double>(), 1.0 / (t * (*m)["pmse"].get<double>()),
                    1e-9 / (t * (*m)["pmse"].get<double>()));
        EXPECT_GT((*m)["spp"].get<double>(), 0.0);
        EXPECT_EQ((*m)["crops"].size(), 1u);
    }
    EXPECT_DOUBLE_EQ(pt["eff_ratio"].get<double>(), 1.0);
    EXPECT_NEAR(direct["eff_ratio"].get<double>(),
                direct["eff"].get<double>() / pt["eff"].get<double>(), 1e-12);
    EXPECT_EQ(results["methods"][2]["status"], "not implemented yet (issue 7)");
    // The reference is the bench's own, with a seed the methods do not use.
    EXPECT_TRUE(results["reference"]["rendered_by_bench"].get<bool>());
    EXPECT_NE(results["reference"]["seeds"][0], results["seed"]);

    // Convergence: points in time order, the last one the final image; pt's error falls from
    // its first snapshot (a few spp) to the end.
    const auto& points = pt["convergence"];
    ASSERT_GE(points.size(), 3u);
    for (size_t i = 1; i < points.size(); ++i)
        EXPECT_GT(points[i]["time"].get<double>(), points[i - 1]["time"].get<double>());
    EXPECT_DOUBLE_EQ(points.back()["mse"].get<double>(), pt["mse"].get<double>());
    EXPECT_GT(points.front()["mse"].get<double>(), points.back()["mse"].get<double>());
    EXPECT_NE(readText(dir / "convergence-err.svg").find("<polyline"), std::string::npos);

    // The table printed to stdout.
    const std::string table = benchTableText(report);
    EXPECT_NE(table.find("method | time (s) | samples (spp) |"), std::string::npos) << table;
    EXPECT_NE(table.find("erpt   | not implemented yet (issue 7)"), std::string::npos) << table;
}

}  // namespace
}  // namespace pmcr::test
