#include "bench/report.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>

#include "bench/plot.h"
#include "core/error.h"
#include "image/colormap.h"
#include "render/stats.h"

namespace pmcr {

namespace {

namespace fs = std::filesystem;

std::string format(const char* spec, double v) {
    char buffer[64];
    std::snprintf(buffer, sizeof(buffer), spec, v);
    return buffer;
}

std::string sci(double v) {
    return std::isfinite(v) ? format("%.3e", v) : "inf";
}
std::string general(double v) {
    return std::isfinite(v) ? format("%.4g", v) : "inf";
}
std::string fixed2(double v) {
    return std::isfinite(v) ? format("%.2f", v) : "inf";
}
// Ratios: two decimals, or two significant digits below 0.1.
std::string ratioText(double v) {
    return !std::isfinite(v) ? "inf" : v >= 0.1 ? format("%.2f", v) : format("%.2g", v);
}

nlohmann::json number(double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

std::string notImplementedText(const BenchRun& run) {
    return "not implemented yet" + (run.plannedIn.empty() ? "" : " (" + run.plannedIn + ")");
}

// File names for one run's outputs, relative to the report directory.
struct RunFiles {
    std::string png, hdr, stats, error;
    std::vector<std::pair<std::string, std::string>> diagnostics;  // (suffix, png)
    std::vector<std::string> diagnosticsHdr;
    std::vector<std::string> crops;
};

std::string slugify(const std::string& label) {
    std::string slug;
    for (char c : label)
        slug += std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' ? c : '-';
    return slug;
}

std::vector<RunFiles> planFiles(const BenchReport& report) {
    std::vector<RunFiles> files;
    std::set<std::string> used;
    for (const BenchRun& run : report.runs) {
        RunFiles f;
        if (run.implemented) {
            std::string slug = slugify(run.method.label);
            for (int k = 2; !used.insert(slug).second; ++k)
                slug = slugify(run.method.label) + "-" + std::to_string(k);
            f.png = "images/" + slug + ".png";
            f.hdr = "images/" + slug + ".exr";
            f.stats = "images/" + slug + ".json";
            f.error = "images/" + slug + "-error.png";
            for (const auto& [suffix, image] : run.diagnostics) {
                f.diagnostics.push_back(
                    {suffix, "images/" + slug + "." + slugify(suffix) + ".png"});
                f.diagnosticsHdr.push_back("images/" + slug + "." + slugify(suffix) + ".exr");
            }
            for (size_t c = 0; c < report.options.crops.size(); ++c)
                f.crops.push_back("crops/" + slug + "-crop" + std::to_string(c + 1) + ".png");
        }
        files.push_back(std::move(f));
    }
    return files;
}

std::string referenceCrop(size_t c) {
    return "crops/reference-crop" + std::to_string(c + 1) + ".png";
}

void writeText(const fs::path& path, const std::string& text) {
    writeFileAtomically(path, [&](const fs::path& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
        out.close();
        if (!out)
            throw Error(tmp.string() + ": write failed");
    });
}

// Scalar images (alpha maps, sample densities, variances) as false colour of their luminance
// from 0 to their maximum; colour images (strategy images: red/green/blue = one strategy each)
// as they are, scaled by their largest component.
Image diagnosticColors(const Image& image, float* maxValue) {
    bool grey = true;
    float largestComponent = 0.0f;
    for (size_t i = 0; i < image.pixelCount(); ++i) {
        const float* p = &image.rgb[3 * i];
        grey = grey && p[0] == p[1] && p[1] == p[2];
        for (int c = 0; c < 3; ++c)
            if (std::isfinite(p[c])) largestComponent = std::max(largestComponent, p[c]);
    }
    if (!grey) {
        *maxValue = largestComponent > 0.0f ? largestComponent : 1.0f;
        Image scaled = image;
        for (float& v : scaled.rgb) v = std::isfinite(v) ? std::max(v, 0.0f) / *maxValue : 0.0f;
        return scaled;
    }
    std::vector<float> values(image.pixelCount());
    float largest = 0.0f;
    for (size_t i = 0; i < values.size(); ++i) {
        const float v = float(
            luminance709(glm::vec3(image.rgb[3 * i], image.rgb[3 * i + 1], image.rgb[3 * i + 2])));
        values[i] = std::isfinite(v) ? v : 0.0f;
        largest = std::max(largest, values[i]);
    }
    *maxValue = largest > 0.0f ? largest : 1.0f;
    return falseColor(values, image.width, image.height, *maxValue);
}

std::string budgetText(const BenchReport& r) {
    const RenderSettings& s = r.options.base;
    std::string text;
    if (s.timeLimit > 0.0)
        text = general(s.timeLimit) + " s per method (render clock)";
    if (s.spp > 0)
        text += (text.empty() ? "" : ", at most ") + std::to_string(s.spp) + " spp per method";
    return text;
}

std::string referenceText(const BenchReport& r) {
    const nlohmann::json& info = r.referenceInfo;
    std::string text = info.value("path", "");
    if (info.value("rendered_by_bench", false))
        text += " (rendered by this bench)";
    if (info.contains("method") && !info["method"].get<std::string>().empty())
        text += ", " + info["method"].get<std::string>() + ", " + general(info.value("spp", 0.0)) +
                " spp";
    if (info.contains("seeds") && !info["seeds"].empty())
        text += ", seeds " + info["seeds"].dump();
    return text;
}

std::vector<std::string> notes(const BenchReport& r) {
    std::vector<std::string> list;
    if (r.referenceInfo.contains("notes"))
        for (const auto& n : r.referenceInfo["notes"])
            list.push_back(n.get<std::string>());
    return list;
}

const char* kDefinitions =
    "Err: mean over pixels of e^2, e the luminance difference to the reference. P-Err: mean of "
    "e^2 / tvi(Y_ref) (Fan et al., Ferwerda et al. 1996 tvi). Eff = 1 / (time x Err), "
    "P-Eff = 1 / (time x P-Err); ratios are to the first method in the table. Time is the render "
    "clock: from a method's first sample to its end, without scene upload, BVH build, kernel "
    "compilation and convergence snapshots.";

std::string svgPlot(const BenchReport& report, bool perceptual) {
    std::vector<PlotSeries> series;
    for (const BenchRun& run : report.runs) {
        if (!run.implemented)
            continue;
        PlotSeries s;
        s.label = run.method.label;
        for (const ConvergencePoint& p : run.convergence)
            s.points.push_back({p.seconds, perceptual ? p.pmse : p.mse});
        series.push_back(std::move(s));
    }
    PlotAxes axes;
    axes.title = std::string(perceptual ? "P-Err" : "Err") + " against render time, " +
                 report.scene.filename().string();
    axes.xLabel = "render time (s)";
    axes.yLabel = perceptual ? "P-Err (mean e^2 / tvi)" : "Err (luminance MSE)";
    return logLogPlotSvg(axes, series);
}

nlohmann::json metricsJson(const ErrorMetrics& e, double seconds) {
    return {{"region", toString(e.region)},
            {"mse", e.mse},
            {"mse_rgb", {e.mseRgb.r, e.mseRgb.g, e.mseRgb.b}},
            {"rmse", e.rmse},
            {"relmse", e.relmse},
            {"pmse", e.pmse},
            {"eff", number(efficiency(seconds, e.mse))},
            {"peff", number(efficiency(seconds, e.pmse))}};
}

nlohmann::json resultsJson(const BenchReport& r, const std::vector<RunFiles>& files) {
    const RenderSettings& s = r.options.base;
    nlohmann::json j;
    j["pmcr_version"] = PMCR_VERSION;
    j["scene"] = r.scene.string();
    j["device"] = r.device;
    j["width"] = r.width;
    j["height"] = r.height;
    j["time_limit_seconds"] = s.timeLimit;
    j["budget_spp"] = s.spp;
    j["seed"] = s.seed;
    j["max_depth"] = s.maxDepth;
    j["rr_depth"] = s.rrDepth;
    j["camera"] = s.camera;
    j["display_white"] = r.options.displayWhite;
    j["exposure"] = r.exposure;
    j["error_image_scale"] = r.errorScale;
    j["reference"] = r.referenceInfo;
    j["crops"] = nlohmann::json::array();
    for (const PixelRect& c : r.options.crops)
        j["crops"].push_back(toString(c));
    j["methods"] = nlohmann::json::array();
    for (size_t i = 0; i < r.runs.size(); ++i) {
        const BenchRun& run = r.runs[i];
        nlohmann::json m = {{"label", run.method.label},
                            {"method", run.method.method},
                            {"options", run.method.options},
                            {"implemented", run.implemented}};
        if (!run.implemented) {
            m["status"] = notImplementedText(run);
            j["methods"].push_back(m);
            continue;
        }
        m.update(metricsJson(run.error, run.seconds));
        m["time"] = run.seconds;
        m["wall_time"] = run.wallSeconds;
        // How busy the method kept the device (issue 38; render/stats.h).
        for (const char* key : {"device_busy", "device_idle_seconds", "gpu_milliseconds",
                                "rays_per_kernel_second", "pipeline_seconds", "prepass_seconds",
                                "queue_drains"})
            m[key] = statsNumber(run.stats, key);
        m["samples"] = run.samples;
        m["spp"] = run.spp;
        m["eff_ratio"] = number(run.effRatio);
        m["peff_ratio"] = number(run.peffRatio);
        m["crops"] = nlohmann::json::array();
        for (const ErrorMetrics& c : run.cropErrors)
            m["crops"].push_back(metricsJson(c, run.seconds));
        m["convergence"] = nlohmann::json::array();
        for (const ConvergencePoint& p : run.convergence)
            m["convergence"].push_back(
                {{"time", p.seconds}, {"spp", p.spp}, {"mse", p.mse}, {"pmse", p.pmse}});
        const RunFiles& f = files[i];
        nlohmann::json images = {{"image", f.png},
                                 {"hdr", f.hdr},
                                 {"stats", f.stats},
                                 {"error", f.error},
                                 {"crops", f.crops}};
        images["diagnostics"] = nlohmann::json::object();
        for (const auto& [suffix, png] : f.diagnostics)
            images["diagnostics"][suffix] = png;
        m["images"] = images;
        m["stats"] = run.stats;
        j["methods"].push_back(m);
    }
    return j;
}

std::string markdownRow(const std::vector<std::string>& cells, size_t columns) {
    std::string row = "|";
    for (size_t c = 0; c < columns; ++c)
        row += " " + (c < cells.size() ? cells[c] : "") + " |";
    return row + "\n";
}

std::string markdownReport(const BenchReport& r, const std::vector<RunFiles>& files) {
    std::string md = "# pmcr bench: " + r.scene.filename().string() + "\n\n";
    md += "- device: " + r.device + "\n";
    md += "- image: " + std::to_string(r.width) + "x" + std::to_string(r.height) + ", seed " +
          std::to_string(r.options.base.seed) + ", max depth " +
          std::to_string(r.options.base.maxDepth) + "\n";
    md += "- budget: " + budgetText(r) + "\n";
    md += "- reference: " + referenceText(r) + "\n";
    md += "- exposure: " + fixed2(r.exposure) +
          " EV for every image; error images show |e| from 0 to " + sci(r.errorScale) + "\n";
    for (const std::string& n : notes(r))
        md += "- note: " + n + "\n";
    const auto header = benchTableHeader();
    md += "\n" + markdownRow(header, header.size());
    md += markdownRow(std::vector<std::string>(header.size(), "---"), header.size());
    for (const auto& row : benchTableRows(r))
        md += markdownRow(row, header.size());
    md += "\n" + std::string(kDefinitions) + "\n\n## Convergence\n\n";
    md += "![Err against render time](convergence-err.svg)\n\n";
    md += "![P-Err against render time](convergence-perr.svg)\n\n## Images\n\n";
    std::vector<std::string> names = {"reference"}, images = {"![reference](reference.png)"},
                             errors = {""}, diagnostics = {""};
    for (size_t i = 0; i < r.runs.size(); ++i) {
        const BenchRun& run = r.runs[i];
        names.push_back(run.method.label);
        if (!run.implemented) {
            images.push_back(notImplementedText(run));
            errors.push_back("");
            diagnostics.push_back("");
            continue;
        }
        images.push_back("![" + run.method.label + "](" + files[i].png + ")");
        errors.push_back("![error](" + files[i].error + ")");
        std::string cell;
        for (const auto& [suffix, png] : files[i].diagnostics)
            cell += (cell.empty() ? "" : " ") + std::string("![") + suffix + "](" + png + ")";
        diagnostics.push_back(cell);
    }
    md += markdownRow(names, names.size());
    md += markdownRow(std::vector<std::string>(names.size(), "---"), names.size());
    md += markdownRow(images, names.size()) + markdownRow(errors, names.size());
    const bool anyDiagnostics = std::any_of(diagnostics.begin(), diagnostics.end(),
                                            [](const std::string& d) { return !d.empty(); });
    if (anyDiagnostics)
        md += markdownRow(diagnostics, names.size());
    md += "\n";
    md += "Rows: the images (exposure " + fixed2(r.exposure) + " EV), |e| from 0 to " +
          sci(r.errorScale) + " in false colour, the methods' diagnostic images.\n\n";
    for (size_t c = 0; c < r.options.crops.size(); ++c) {
        md += "## Crop " + std::to_string(c + 1) + " (" + toString(r.options.crops[c]) + ")\n\n";
        md += "| method | Err | P-Err | Eff | P-Eff |\n| --- | --- | --- | --- | --- |\n";
        for (const BenchRun& run : r.runs) {
            if (!run.implemented)
                continue;
            const ErrorMetrics& e = run.cropErrors[c];
            md += "| " + run.method.label + " | " + sci(e.mse) + " | " + sci(e.pmse) + " | " +
                  general(efficiency(run.seconds, e.mse)) + " | " +
                  general(efficiency(run.seconds, e.pmse)) + " |\n";
        }
        md += "\n![reference crop](" + referenceCrop(c) + ")";
        for (size_t i = 0; i < r.runs.size(); ++i)
            if (r.runs[i].implemented)
                md += " ![" + r.runs[i].method.label + "](" + files[i].crops[c] + ")";
        md += "\n\n";
    }
    return md;
}

std::string figure(const std::string& src, const std::string& caption, const char* cls) {
    return "<figure><img class=\"" + std::string(cls) + "\" src=\"" + escapeXml(src) + "\" alt=\"" +
           escapeXml(caption) + "\"><figcaption>" + escapeXml(caption) + "</figcaption></figure>\n";
}

std::string htmlReport(const BenchReport& r, const std::vector<RunFiles>& files) {
    const std::string title = "pmcr bench: " + r.scene.filename().string();
    std::string h =
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
        escapeXml(title) +
        "</title>\n<style>\n"
        "body { font-family: sans-serif; margin: 2em; }\n"
        "table { border-collapse: collapse; margin: 1em 0; }\n"
        "th, td { border: 1px solid #bbb; padding: 0.3em 0.6em; text-align: right; }\n"
        "td:first-child, th:first-child { text-align: left; }\n"
        "td.status { text-align: left; color: #a33; }\n"
        "table.images td, table.images th { text-align: center; vertical-align: top; }\n"
        "figure { display: inline-block; margin: 0.3em; vertical-align: top; }\n"
        "figcaption { font-size: 0.85em; text-align: center; }\n"
        "img.image { width: 256px; image-rendering: pixelated; }\n"
        "img.crop { width: 160px; image-rendering: pixelated; }\n"
        "</style>\n</head>\n<body>\n";
    h += "<h1>" + escapeXml(title) + "</h1>\n<ul>\n";
    h += "<li>device: " + escapeXml(r.device) + "</li>\n";
    h += "<li>image: " + std::to_string(r.width) + "x" + std::to_string(r.height) + ", seed " +
         std::to_string(r.options.base.seed) + ", max depth " +
         std::to_string(r.options.base.maxDepth) + "</li>\n";
    h += "<li>budget: " + escapeXml(budgetText(r)) + "</li>\n";
    h += "<li>reference: " + escapeXml(referenceText(r)) + "</li>\n";
    h += "<li>exposure: " + fixed2(r.exposure) +
         " EV for every image; error images show |e| in false colour from 0 to " +
         sci(r.errorScale) + "</li>\n";
    for (const std::string& n : notes(r))
        h += "<li>note: " + escapeXml(n) + "</li>\n";
    h += "</ul>\n<h2>Results</h2>\n<table class=\"results\">\n<tr>";
    const auto header = benchTableHeader();
    for (const auto& cell : header)
        h += "<th>" + escapeXml(cell) + "</th>";
    h += "</tr>\n";
    const auto rows = benchTableRows(r);
    for (const auto& row : rows) {
        h += "<tr class=\"method\">";
        if (row.size() == 2) {
            h += "<td>" + escapeXml(row[0]) + "</td><td class=\"status\" colspan=\"" +
                 std::to_string(header.size() - 1) + "\">" + escapeXml(row[1]) + "</td>";
        } else {
            for (const auto& cell : row)
                h += "<td>" + escapeXml(cell) + "</td>";
        }
        h += "</tr>\n";
    }
    h += "</table>\n<p>" + escapeXml(kDefinitions) + "</p>\n";
    h += "<h2>Convergence</h2>\n";
    h += "<img src=\"convergence-err.svg\" alt=\"Err against render time\">\n";
    h += "<img src=\"convergence-perr.svg\" alt=\"P-Err against render time\">\n";
    // Images side by side, one column per method: the image, its error, its diagnostics.
    h += "<h2>Images</h2>\n<table class=\"images\">\n<tr><th>reference</th>";
    for (const BenchRun& run : r.runs)
        h += "<th>" + escapeXml(run.method.label) + "</th>";
    h += "</tr>\n<tr><td>" + figure("reference.png", "reference", "image") + "</td>";
    for (size_t i = 0; i < r.runs.size(); ++i) {
        const BenchRun& run = r.runs[i];
        h += "<td>" +
             (run.implemented ? figure(files[i].png, "Err " + sci(run.error.mse), "image")
                              : "<p>" + escapeXml(notImplementedText(run)) + "</p>") +
             "</td>";
    }
    h += "</tr>\n<tr><td></td>";
    for (size_t i = 0; i < r.runs.size(); ++i)
        h += "<td>" +
             (r.runs[i].implemented
                  ? figure(files[i].error, "|e|, 0 to " + sci(r.errorScale), "image")
                  : "") +
             "</td>";
    h += "</tr>\n";
    const bool anyDiagnostics = std::any_of(
        files.begin(), files.end(), [](const RunFiles& f) { return !f.diagnostics.empty(); });
    if (anyDiagnostics)
        h += "<tr><td></td>";
    for (size_t i = 0; anyDiagnostics && i < r.runs.size(); ++i) {
        h += "<td>";
        for (size_t d = 0; d < files[i].diagnostics.size(); ++d) {
            float maxValue = 0.0f;
            diagnosticColors(r.runs[i].diagnostics[d].second, &maxValue);
            h += figure(files[i].diagnostics[d].second,
                        files[i].diagnostics[d].first + ", 0 to " + general(maxValue), "image");
        }
        h += "</td>";
    }
    h += std::string(anyDiagnostics ? "</tr>\n" : "") + "</table>\n";
    for (size_t c = 0; c < r.options.crops.size(); ++c) {
        h += "<h2>Crop " + std::to_string(c + 1) + " (" + toString(r.options.crops[c]) + ")</h2>\n";
        h += "<table class=\"crop\">\n<tr><th>method</th><th>Err</th><th>P-Err</th><th>Eff</th>"
             "<th>P-Eff</th></tr>\n";
        for (const BenchRun& run : r.runs) {
            if (!run.implemented)
                continue;
            const ErrorMetrics& e = run.cropErrors[c];
            h += "<tr><td>" + escapeXml(run.method.label) + "</td><td>" + sci(e.mse) + "</td><td>" +
                 sci(e.pmse) + "</td><td>" + general(efficiency(run.seconds, e.mse)) + "</td><td>" +
                 general(efficiency(run.seconds, e.pmse)) + "</td></tr>\n";
        }
        h += "</table>\n<div>\n" + figure(referenceCrop(c), "reference", "crop");
        for (size_t i = 0; i < r.runs.size(); ++i)
            if (r.runs[i].implemented)
                h += figure(files[i].crops[c], r.runs[i].method.label, "crop");
        h += "</div>\n";
    }
    h += "</body>\n</html>\n";
    return h;
}

// Writes the whole report into `dir` (which exists and is empty).
std::vector<std::string> writeAll(const BenchReport& r, const fs::path& dir) {
    std::vector<std::string> written;
    const std::vector<RunFiles> files = planFiles(r);
    fs::create_directories(dir / "images");
    if (!r.options.crops.empty())
        fs::create_directories(dir / "crops");
    auto png = [&](const std::string& name, const Image& image, float exposure) {
        writePng(dir / name, image, exposure);
        written.push_back(name);
    };
    png("reference.png", r.reference, r.exposure);
    if (r.referenceInfo.value("rendered_by_bench", false)) {
        writeHdr(dir / "reference.exr", r.reference);
        writeJsonAtomically(dir / "reference.json", r.referenceStats);
        written.push_back("reference.exr");
        written.push_back("reference.json");
    }
    for (size_t c = 0; c < r.options.crops.size(); ++c) {
        const PixelRect& k = r.options.crops[c];
        png(referenceCrop(c), crop(r.reference, k.x, k.y, k.width, k.height), r.exposure);
    }
    for (size_t i = 0; i < r.runs.size(); ++i) {
        const BenchRun& run = r.runs[i];
        if (!run.implemented)
            continue;
        const RunFiles& f = files[i];
        png(f.png, run.image, r.exposure);
        writeHdr(dir / f.hdr, run.image);
        writeJsonAtomically(dir / f.stats, run.stats);
        written.push_back(f.hdr);
        written.push_back(f.stats);
        const std::vector<float> error = luminanceErrorMap(run.image, r.reference);
        png(f.error, falseColor(error, run.image.width, run.image.height, r.errorScale), 0.0f);
        for (size_t d = 0; d < run.diagnostics.size(); ++d) {
            float maxValue = 0.0f;
            png(f.diagnostics[d].second, diagnosticColors(run.diagnostics[d].second, &maxValue),
                0.0f);
            writeHdr(dir / f.diagnosticsHdr[d], run.diagnostics[d].second);
            written.push_back(f.diagnosticsHdr[d]);
        }
        for (size_t c = 0; c < r.options.crops.size(); ++c) {
            const PixelRect& k = r.options.crops[c];
            png(f.crops[c], crop(run.image, k.x, k.y, k.width, k.height), r.exposure);
        }
    }
    const std::pair<const char*, std::string> texts[] = {
        {"convergence-err.svg", svgPlot(r, false)},
        {"convergence-perr.svg", svgPlot(r, true)},
        {"results.json", resultsJson(r, files).dump(2) + "\n"},
        {"report.md", markdownReport(r, files)},
        {"report.html", htmlReport(r, files)}};
    for (const auto& [name, text] : texts) {
        writeText(dir / name, text);
        written.push_back(name);
    }
    return written;
}

}  // namespace

std::vector<std::string> benchTableHeader() {
    return {"method", "time (s)", "samples (spp)", "Err",        "Eff",
            "P-Err",  "P-Eff",    "Eff ratio",     "P-Eff ratio"};
}

std::vector<std::vector<std::string>> benchTableRows(const BenchReport& report) {
    std::vector<std::vector<std::string>> rows;
    for (const BenchRun& run : report.runs) {
        if (!run.implemented) {
            rows.push_back({run.method.label, notImplementedText(run)});
            continue;
        }
        rows.push_back({run.method.label, fixed2(run.seconds), general(run.spp), sci(run.error.mse),
                        general(run.eff), sci(run.error.pmse), general(run.peff),
                        ratioText(run.effRatio), ratioText(run.peffRatio)});
    }
    return rows;
}

std::string benchTableText(const BenchReport& report) {
    const auto header = benchTableHeader();
    const auto rows = benchTableRows(report);
    std::vector<size_t> width(header.size());
    for (size_t c = 0; c < header.size(); ++c)
        width[c] = header[c].size();
    for (const auto& row : rows)
        for (size_t c = 0; c < row.size(); ++c)
            if (row.size() == header.size() || c == 0)
                width[c] = std::max(width[c], row[c].size());
    // The method left-aligned, numbers right-aligned; a status fills the rest of its row.
    auto line = [&](const std::vector<std::string>& cells) {
        std::string text = cells[0] + std::string(width[0] - cells[0].size(), ' ');
        for (size_t c = 1; c < cells.size(); ++c) {
            const bool status = cells.size() != header.size();
            const size_t pad = status ? 0 : width[c] - cells[c].size();
            text += " | " + std::string(pad, ' ') + cells[c];
        }
        return text + "\n";
    };
    std::string text = line(header);
    for (size_t c = 0; c < header.size(); ++c)
        text += (c > 0 ? "-+-" : "") + std::string(width[c], '-');
    text += "\n";
    for (const auto& row : rows)
        text += line(row);
    return text;
}

void checkBenchOutputDir(const fs::path& dir) {
    const std::string name = dir.string();
    if (!dir.has_filename() && !dir.has_parent_path())
        fail(name, "not a directory name");
    std::error_code ec;
    const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
    if (!fs::is_directory(parent, ec))
        fail(name, "its parent directory does not exist");
    if (!fs::exists(dir, ec))
        return;
    if (!fs::is_directory(dir, ec))
        fail(name, "exists and is not a directory");
    if (fs::is_empty(dir, ec) || fs::exists(dir / "results.json", ec))
        return;
    fail(name, "exists and is not an earlier bench report (no results.json); choose a new --out");
}

std::vector<std::string> writeBenchReport(const BenchReport& report, const fs::path& dirIn) {
    // "out/" names the directory "out".
    const fs::path dir = dirIn.has_filename() ? dirIn : dirIn.parent_path();
    checkBenchOutputDir(dir);
    const fs::path parent = dir.has_parent_path() ? dir.parent_path() : fs::path(".");
    const std::string stem = "." + dir.filename().string() + ".tmp-" + std::to_string(::getpid());
    const fs::path tmp = parent / stem, old = parent / (stem + "-old");
    std::error_code ec;
    fs::remove_all(tmp, ec);
    fs::remove_all(old, ec);
    try {
        if (!fs::create_directory(tmp, ec))
            fail(tmp.string(), "cannot create: " + ec.message());
        std::vector<std::string> written = writeAll(report, tmp);
        // Swap the new report in; an earlier one goes only once the new one is in place.
        const bool replacing = fs::exists(dir, ec);
        if (replacing)
            fs::rename(dir, old);
        try {
            fs::rename(tmp, dir);
        } catch (const fs::filesystem_error&) {
            if (replacing)
                fs::rename(old, dir, ec);
            throw;
        }
        if (replacing)
            fs::remove_all(old, ec);
        return written;
    } catch (const fs::filesystem_error& e) {
        fs::remove_all(tmp, ec);
        fail(dir.string(), std::string("cannot write the report: ") + e.code().message());
    } catch (...) {
        fs::remove_all(tmp, ec);
        throw;
    }
}

}  // namespace pmcr
