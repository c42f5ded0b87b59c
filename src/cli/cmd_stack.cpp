// SPDX-License-Identifier: MIT
// `infocus stack`: where each region of a focus stack or recorded sweep is sharpest, by its
// sharpness curve and its blur V, with a dense focus map and an all-in-focus composite
// (include/infocus/stack.h, docs/stack.md).
#include <unistd.h>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "infocus/pipeline.h"
#include "infocus/qa.h"
#include "infocus/report.h"
#include "infocus/stack.h"
#include "infocus/stack_output.h"
#include "parse.h"
#include "progress.h"

namespace infocus::cli {

namespace {

constexpr const char* kName = "stack";

struct StackArgs {
    std::string source;
    std::string grid = "8x6";
    std::string positions;
    std::string metric;
    std::string output;
    int step = 16;
    int threads = static_cast<int>(defaultJobs());
    bool json = false;
    bool quiet = false;
    bool mtf = false;
    double mtfThreshold = 0.0;  // cy/px; 0: 80 % of each region's best
};

// Checks that @p dir is, or can be made, a directory this process writes in, before minutes of
// analysis are spent.
Status prepareOutput(const std::string& dir) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        return makeError(ErrorKind::Usage,
                         "-o " + dir + " is a file; give a directory for the stack's maps");
    fs::create_directories(dir, ec);
    if (ec || access(dir.c_str(), W_OK) != 0)
        return makeError(ErrorKind::Io, "-o " + dir +
                                            ": cannot create or write in this directory; give "
                                            "one you can write in");
    return {};
}

Status writeOutputs(const std::string& dir, const StackResult& r) {
    namespace fs = std::filesystem;
    const auto put = [&](const char* name, const std::string& bytes) {
        return writeFileAtomically((fs::path(dir) / name).string(), bytes);
    };
    if (auto s = put("stack.json", stackJson(r, 2) + "\n"); !s) return s;
    std::string mapPng, colourPng, compositePng;
    if (r.map.cols > 0) {
        double low = 0, high = 0;
        const std::vector<uint16_t> v = focusMap16(r, low, high);
        auto png = encodePng(r.map.cols, r.map.rows, 1, 16, v.data());
        if (!png) return png.error();
        mapPng = std::move(*png);
        int w = 0, h = 0;
        const auto rgb = focusMapColour(r, 1024, w, h);
        if (!rgb) return rgb.error();
        auto c = encodePng(w, h, 3, 8, rgb->data());
        if (!c) return c.error();
        colourPng = std::move(*c);
        auto comp = encodePng(r.width, r.height, 1, 8, r.composite.data());
        if (!comp) return comp.error();
        compositePng = std::move(*comp);
        if (auto s = put("focus_map.png", mapPng); !s) return s;
        if (auto s = put("focus_map_colour.png", colourPng); !s) return s;
        if (auto s = put("composite.png", compositePng); !s) return s;
    }
    return put("report.html", stackReportHtml(r, colourPng, compositePng));
}

int runStackCommand(const StackArgs& args) {
    const std::string cmd = kName;
    StackOptions options;
    const auto grid = parseGrid(args.grid);
    if (!grid) return usageError(cmd, gridUsage(args.grid));
    options.cols = grid->first;
    options.rows = grid->second;
    options.metric = args.metric;
    options.mapStepPx = args.step;
    options.threads = args.threads;
    if (!args.positions.empty()) {
        auto p = readPositionsCsv(args.positions);
        if (!p) return reportError(cmd, p.error());
        options.positions = std::move(*p);
    }
    if (!args.output.empty())
        if (auto s = prepareOutput(args.output); !s) return reportError(cmd, s.error());
    // Measuring is the long part (the frames are read first, the maps are quick).
    ProgressLine progress(cmd, args.quiet);
    options.progress = [&](uint64_t done, uint64_t total) { progress.update(done, total); };
    auto r = analyzeStack(args.source, options);
    progress.clear();
    if (!r) return reportError(cmd, r.error());
    std::optional<qa::ThroughFocus> tf;
    if (args.mtf)
        // Every region with an edge: a stack's frames far from focus read few confident edges,
        // and the curve needs them to fall.
        tf = qa::throughFocus(
            *r, 0.0, args.mtfThreshold > 0 ? std::optional(args.mtfThreshold) : std::nullopt);
    if (args.json && tf) {
        auto j = nlohmann::ordered_json::parse(stackJson(*r));
        j["through_focus"] = nlohmann::ordered_json::parse(qa::throughFocusJson(*tf));
        std::cout << j.dump() << '\n';
    } else if (args.json) {
        std::cout << stackJson(*r) << '\n';
    } else {
        writeStackTable(std::cout, *r);
        if (tf) std::cout << qa::throughFocusTable(*tf);
    }
    if (!args.output.empty()) {
        if (auto s = writeOutputs(args.output, *r); !s) return reportError(cmd, s.error());
        if (!args.json)
            std::cout << "wrote stack.json, focus_map.png, focus_map_colour.png, composite.png "
                         "and report.html to "
                      << args.output << "\n";
    }
    if (!args.json)
        std::cout << "measured in " << r->analysisSeconds << " s, maps and composite in "
                  << r->mapSeconds << " s\n";
    std::cout.flush();
    return std::cout
               ? 0
               : reportError(cmd, makeError(ErrorKind::Io, "writing to standard output failed"));
}

}  // namespace

Command addStackCommand(CLI::App& app) {
    auto args = std::make_shared<StackArgs>();
    CLI::App* sub = app.add_subcommand(
        "stack",
        "Focus stack: where each region is sharpest across the frames, and at what distance");
    sub->add_option("SOURCE", args->source,
                    "Frames of a stack: a directory or glob of images (name order), a video, or "
                    "a recording (its lens positions are used)")
        ->required();
    sub->add_option("--grid", args->grid, "Regions as columns x rows")->capture_default_str();
    sub->add_option("--positions", args->positions,
                    "CSV of frame,position,unit: the position of each frame (unit dpt, m, or an "
                    "axis's own such as a stage's mm)");
    sub->add_option("--metric", args->metric,
                    "Focus operator: lapv, lapm, teng (default), tenv, brenner, glvn, dctr");
    sub->add_option("--step", args->step, "Step of the dense focus map, pixels")
        ->check(CLI::Range(2, 1024))
        ->capture_default_str();
    sub->add_option("--jobs,--threads", args->threads, "Frames measured at once")
        ->check(CLI::Range(1, 64))
        ->default_str("the machine's cores");
    sub->add_flag("--quiet", args->quiet,
                  "No progress line on stderr (it is shown only when stderr is a terminal)");
    sub->add_option("-o,--output", args->output,
                    "Directory for stack.json, focus_map.png (16-bit), focus_map_colour.png, "
                    "composite.png and report.html");
    sub->add_flag("--json", args->json, "Print the analysis as one JSON object instead of tables");
    sub->add_flag("--mtf", args->mtf,
                  "Also MTF50 through focus per region: best focus, depth of focus, tilt and "
                  "field curvature (docs/qa.md)");
    sub->add_option("--mtf-threshold", args->mtfThreshold,
                    "MTF50 (cy/px) that bounds the depth of focus with --mtf (default: 80 % of "
                    "each region's best)")
        ->check(CLI::Range(0.0, 1.0));
    sub->footer(
        "Each region's peak is a Gaussian through its sharpest frame and the two beside it; its "
        "blur widths are fitted by a V whose vertex is where the blur vanishes; the two agree "
        "when within one frame. Regions without texture, too dark or clipped are marked, not "
        "guessed. See docs/stack.md.");
    return {sub, [args] { return runStackCommand(*args); }};
}

}  // namespace infocus::cli
