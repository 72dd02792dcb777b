// `pmcr bench` on a tiny scene, in-process on the test device: the report, its table rows and
// files (erpt's diagnostic images included), the figures in results.json; and the convergence
// snapshots it plots.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "bench/bench.h"
#include "bench/report.h"
#include "gpu_test.h"
#include "render/methods.h"
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

// A snapshot's time comes off the render clock, so the batches in flight must not run on for
// free meanwhile: the device's kernel time stays within the clock (one queue runs one kernel
// at a time). pm, which keeps two gather batches in flight, had 1.45 s of kernels a second of
// clock in `pmcr bench` on lavapipe, and 4 spp where `pmcr render` reached 2.4.
TEST_F(Bench, SnapshotsTakeNoDeviceTimeOffTheClock) {
    const Scene& scene = testScene("scenes/cornell-glass.glb");
    for (const char* method : {"pm", "pmc-ip"}) {
        RenderSettings s;
        s.method = method;
        s.width = 64;
        s.height = 64;
        s.timeLimit = 1.0;
        for (int k = 1; k <= 12; ++k) s.snapshotSeconds.push_back(1.0 * k / 13.0);
        const RenderResult r = renderForTest(scene, s);
        ASSERT_FALSE(r.snapshots.empty()) << method;
        const double kernelSeconds = r.stats["gpu_milliseconds"].get<double>() * 1e-3;
        EXPECT_LE(kernelSeconds, r.samplingSeconds * 1.02 + 0.005)
            << method << ": " << r.snapshots.size() << " snapshots";
    }
}

// The first method in the registry that is not implemented yet ("" once all are).
std::string unimplementedMethod() {
    for (const MethodInfo& m : methods())
        if (!m.create)
            return m.name;
    return "";
}

TEST_F(Bench, ReportForATinyScene) {
    const Scene& scene = testScene("scenes/cornell-classic.glb");
    const std::string planned = unimplementedMethod();
    std::vector<std::string> labels = {"pt", "direct", "erpt"};
    if (!planned.empty())
        labels.push_back(planned);
    std::string list;
    for (const auto& l : labels)
        list += (list.empty() ? "" : ",") + l;
    BenchOptions o;
    o.methods = parseBenchMethods("--methods", list);
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

    // The HTML table: one row per method, a method not implemented yet reported as such.
    const std::string html = readText(dir / "report.html");
    const std::regex row("<tr class=\"method\"><td>([^<]*)</td>");
    std::vector<std::string> rows;
    for (auto it = std::sregex_iterator(html.begin(), html.end(), row);
         it != std::sregex_iterator(); ++it)
        rows.push_back((*it)[1]);
    EXPECT_EQ(rows, labels);
    const std::string status =
        planned.empty() ? "" : "not implemented yet (" + findMethod(planned)->plannedIn + ")";
    if (!planned.empty()) {
        EXPECT_NE(html.find("<td>" + planned + "</td><td class=\"status\" colspan=\"8\">" + status),
                  std::string::npos);
        EXPECT_NE(readText(dir / "report.md").find("| " + planned + " | " + status + " |"),
                  std::string::npos);
    }
    // Every file it shows exists, the methods' diagnostic images (erpt's) among them.
    const std::regex link("(?:src|href)=\"([^\"]+)\"");
    std::set<std::string> links;
    for (auto it = std::sregex_iterator(html.begin(), html.end(), link);
         it != std::sregex_iterator(); ++it) {
        links.insert((*it)[1]);
        EXPECT_TRUE(fs::is_regular_file(dir / (*it)[1].str())) << (*it)[1];
    }
    for (const char* f : {"reference.png", "images/pt.png", "images/pt-error.png",
                          "images/direct.png", "images/erpt.png", "images/erpt.chains.png",
                          "images/erpt.proposals.png", "crops/reference-crop1.png",
                          "crops/erpt-crop1.png", "convergence-err.svg", "convergence-perr.svg"})
        EXPECT_EQ(links.count(f), 1u) << f;
    for (const char* f : {"report.md", "results.json", "reference.exr", "reference.json",
                          "images/pt.exr", "images/direct.json", "images/erpt.chains.exr"})
        EXPECT_TRUE(fs::is_regular_file(dir / f)) << f;

    // The figures: Eff = 1 / (T Err), ratios to pt. --time is a limit the render ends within
    // (a pass that would end past it is not started), so T is any positive time.
    const nlohmann::json results = nlohmann::json::parse(readText(dir / "results.json"));
    ASSERT_EQ(results["methods"].size(), labels.size());
    const auto& pt = results["methods"][0];
    for (size_t i = 0; i < 3; ++i) {
        const auto& m = results["methods"][i];
        const double t = m["time"].get<double>(), mse = m["mse"].get<double>();
        const double pmse = m["pmse"].get<double>();
        EXPECT_GT(t, 0.0) << m["label"];
        EXPECT_GT(mse, 0.0);
        EXPECT_NEAR(m["eff"].get<double>(), 1.0 / (t * mse), 1e-9 / (t * mse));
        EXPECT_NEAR(m["peff"].get<double>(), 1.0 / (t * pmse), 1e-9 / (t * pmse));
        EXPECT_NEAR(m["eff_ratio"].get<double>(), m["eff"].get<double>() / pt["eff"].get<double>(),
                    1e-12 * m["eff_ratio"].get<double>());
        EXPECT_EQ(m["crops"].size(), 1u);
    }
    EXPECT_DOUBLE_EQ(pt["eff_ratio"].get<double>(), 1.0);
    EXPECT_GT(pt["spp"].get<double>(), 0.0);
    if (!planned.empty())
        EXPECT_EQ(results["methods"][3]["status"], status);
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
    if (!planned.empty())
        EXPECT_NE(table.find("| " + status), std::string::npos) << table;
}

}  // namespace
}  // namespace pmcr::test
