// SPDX-License-Identifier: MIT
// `infocus sweep`: moves a motorised lens through its range, measures every position, and
// leaves the lens where the frame is sharpest (include/infocus/sweep.h).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "commands.h"
#include "infocus/analysis_output.h"
#include "infocus/sweep.h"
#include "infocus/sweep_output.h"
#include "lens_options.h"
#include "parse.h"

namespace infocus::cli {

namespace {

constexpr const char* kName = "sweep";

struct SweepArgs {
    std::string source;
    std::string from, to;
    int steps = 15;
    int refine = 9;
    std::optional<int> settle;
    std::string grid = "8x6";
    std::string metric;
    std::string output;
    bool noBlur = false;
    bool noMove = false;
    bool json = false;
};

// A position given on the command line, in the control's unit. A dioptre control takes a
// distance or dioptres with their unit ("1.2m", "0.8dpt", "inf"), as --focus does; a control in
// the driver's own steps takes a plain number.
Result<double> parsePosition(const std::string& text, const std::string& option,
                             const FocusRange& range, const std::string& source) {
    if (range.unit == "dioptre") {
        auto m = parseFocus(text, option);
        if (!m) return m.error();
        return std::isinf(*m) ? 0.0 : 1.0 / *m;
    }
    double v = 0;
    if (!readsWhole(text, v) || !std::isfinite(v)) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%g to %g", range.min, range.max);
        return makeError(ErrorKind::Usage, option + " " + text + ": the lens control of " + source +
                                               " counts in its driver's own steps (unit " +
                                               range.unit + ", range " + buf +
                                               "), not in distances; give a number in that range");
    }
    return v;
}

int runSweepCommand(const SweepArgs& args) {
    const std::string cmd = kName;
    SweepOptions options;
    const auto grid = parseGrid(args.grid);
    if (!grid) return usageError(cmd, gridUsage(args.grid));
    options.analysis.cols = grid->first;
    options.analysis.rows = grid->second;
    options.analysis.metric = args.metric;
    options.analysis.measureBlur = !args.noBlur;
    options.steps = args.steps;
    options.refineSteps = args.refine;
    options.settleFrames = args.settle;
    options.moveToBest = !args.noMove;
    // Options are checked before the source opens: a mistyped operator must not move a lens.
    if (auto a = Analyzer::create(options.analysis); !a) return reportError(cmd, a.error());

    namespace fs = std::filesystem;
    std::ofstream jsonl;
    fs::path dir;
    if (!args.output.empty()) {
        dir = args.output;
        std::error_code ec;
        if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
            return usageError(
                cmd, "-o " + args.output + " is a file; give a directory for the sweep's files");
        for (const char* f : {"sweep.jsonl", "summary.json"})
            if (fs::exists(dir / f, ec))
                return usageError(cmd, "-o " + args.output + " already holds a sweep (" + f +
                                           "); give a new or empty directory");
    }

    auto source = openSource(args.source);
    if (!source) return reportError(cmd, source.error());
    FrameSource& src = **source;
    FocusControl* control = src.focusControl();
    if (!control) return reportError(cmd, noFocusControlError(args.source));
    const FocusRange range = control->range();
    for (auto [text, slot] : {std::pair{&args.from, &options.from}, {&args.to, &options.to}}) {
        if (text->empty()) continue;
        auto v =
            parsePosition(*text, slot == &options.from ? "--from" : "--to", range, args.source);
        if (!v) return reportError(cmd, v.error());
        *slot = *v;
    }
    const int settle = args.settle.value_or(control->settleFrames());
    // Said with the first position measured, once the sweep's options have been accepted.
    const auto printHeader = [&] {
        writeSweepHeader(std::cout, args.source, range, options.from.value_or(range.min),
                         options.to.value_or(range.max), args.steps, args.refine, settle);
    };
    // Created once the source is open and the range accepted: a failed start leaves no empty
    // sweep.jsonl behind, which would make the next run refuse the directory as a sweep's.
    if (!dir.empty()) {
        std::error_code ec;
        fs::create_directories(dir, ec);
        jsonl.open(dir / "sweep.jsonl", std::ios::out | std::ios::trunc);
        if (ec || !jsonl)
            return reportError(
                cmd, makeError(ErrorKind::Io, "cannot write in '" + args.output +
                                                  "'; check that it can be created and written"));
    }
    if (auto s = src.start(); !s) return reportError(cmd, s.error());
    size_t written = 0;
    auto result = runSweep(src, options, [&](const SweepStep& s) -> Status {
        if (jsonl.is_open()) {
            jsonl << toJsonLine(s.analysis) << '\n';
            jsonl.flush();  // a position measured is a position kept
            if (!jsonl)
                return makeError(ErrorKind::Io, "writing " + (dir / "sweep.jsonl").string() +
                                                    " failed after " + std::to_string(written) +
                                                    " position(s); free disk space or write "
                                                    "elsewhere (-o DIR)");
        }
        if (args.json) {
            ++written;
            return {};
        }
        if (written++ == 0) printHeader();
        writeSweepStep(std::cout, s);
        std::cout.flush();
        return {};
    });
    src.stop();
    if (!result) {
        if (written)
            std::cerr << "infocus sweep: " << written << " position(s) measured before the error"
                      << (jsonl.is_open() ? " are in " + (dir / "sweep.jsonl").string() : "")
                      << "\n";
        return reportError(cmd, result.error());
    }
    if (jsonl.is_open()) {
        std::ofstream f(dir / "summary.json", std::ios::out | std::ios::trunc);
        f << sweepSummaryJson(args.source, *result, settle, 2) << '\n';
        f.flush();
        if (!f)
            return reportError(
                cmd, makeError(ErrorKind::Io, "writing " + (dir / "summary.json").string() +
                                                  " failed; the measurements are in sweep.jsonl"));
    }
    if (args.json) {
        std::cout << sweepSummaryJson(args.source, *result, settle) << '\n';
        std::cout.flush();
        return std::cout ? 0
                         : reportError(
                               cmd, makeError(ErrorKind::Io, "writing to standard output failed"));
    }
    if (!result->best) {
        std::fprintf(stderr,
                     "infocus sweep: no position scored above zero: nothing in the frame "
                     "to focus on (a blank scene, a capped lens, or the lens does not "
                     "move); the lens was left where it was\n");
        return kExitFailure;
    }
    const FocusPeak& best = *result->best;
    writeSweepSummary(std::cout, *result, options.moveToBest);
    std::cout.flush();
    if (best.atEnd)
        std::fprintf(stderr,
                     "infocus sweep: the sharpest position is the sweep's %s one: the best focus "
                     "may lie beyond it; sweep a wider range (--from, --to)\n",
                     best.index == 0 ? "first" : "last");
    if (best.prominence < 0.1)
        std::fprintf(stderr,
                     "infocus sweep: the frame's sharpness changes by only %.0f %% over the sweep: "
                     "the scene may lack texture, or the lens may not move; check the best focus "
                     "by eye\n",
                     100.0 * best.prominence);
    return std::cout
               ? 0
               : reportError(cmd, makeError(ErrorKind::Io, "writing to standard output failed"));
}

}  // namespace

Command addSweepCommand(CLI::App& app) {
    auto args = std::make_shared<SweepArgs>();
    CLI::App* sub = app.add_subcommand(
        "sweep", "Focus sweep: move the lens through its range and leave it at best focus");
    sub->add_option("SOURCE", args->source, "A camera with a focus motor, or sim:")->required();
    sub->add_option("--from", args->from,
                    "First position: a distance or dioptres for a dioptre lens (1.2m, 0.8dpt, "
                    "inf), a number in the driver's steps otherwise (default: the range's start)");
    sub->add_option("--to", args->to, "Last position, as --from (default: the range's end)");
    sub->add_option("--steps", args->steps, "Positions of the first pass, evenly spaced")
        ->check(CLI::Range(2, 1000))
        ->capture_default_str();
    sub->add_option("--refine", args->refine,
                    "Positions of a second pass between the neighbours of the sharpest (0: none)")
        ->check(CLI::Range(0, 1000))
        ->capture_default_str();
    sub->add_option("--settle", args->settle,
                    "Frames discarded after each move (default: the camera's own)")
        ->check(CLI::Range(0, 1000));
    sub->add_option("--grid", args->grid, "Regions as columns x rows")->capture_default_str();
    sub->add_option("--metric", args->metric,
                    "Focus operator: lapv, lapm, teng (default), tenv, brenner, glvn, dctr");
    sub->add_option("-o,--output", args->output,
                    "Directory for sweep.jsonl (each frame measured, as analyze writes it) and "
                    "summary.json");
    sub->add_flag("--no-blur", args->noBlur, "Sharpness only: skip the blur-width measurement");
    sub->add_flag("--no-move", args->noMove, "Leave the lens at the last position measured");
    sub->add_flag("--json", args->json, "Print the summary as one JSON object instead of a table");
    sub->footer(
        "The best focus is the peak of the whole frame's sharpness over the lens positions, "
        "interpolated by a Gaussian through the sharpest position and its neighbours; each "
        "region's peak is reported too (a tilted sensor or scene peaks at different positions "
        "across the frame).");
    return {sub, [args] { return runSweepCommand(*args); }};
}

}  // namespace infocus::cli
