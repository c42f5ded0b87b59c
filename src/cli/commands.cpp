// SPDX-License-Identifier: MIT
#include "commands.h"

#include <cmath>
#include <cstdint>
#include <iomanip>
#include <iostream>

#include "parse.h"

namespace infocus::cli {

std::vector<Command> registerCommands(CLI::App& app) {
    // Order here is the order of `infocus --help`.
    return {
        addLiveCommand(app),   addDevicesCommand(app), addAnalyzeCommand(app), addDofCommand(app),
        addDepthCommand(app),  addRecordCommand(app),  addSweepCommand(app),   addStackCommand(app),
        addReportCommand(app), addCheckCommand(app),   addBenchCommand(app),
    };
}

void addDepthMapOptions(CLI::App* app, DepthMapOptions& options) {
    app->add_option("--blur-floor", options.blurFloorPx,
                    "Blur width (px) a perfectly focused region still measures; removed in "
                    "quadrature")
        ->capture_default_str();
    app->add_option("--min-confidence", options.minConfidence,
                    "Ignore regions whose blur confidence is below this")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
}

std::string depthMapOptionsUsage(const DepthMapOptions& options) {
    if (!(options.blurFloorPx >= 0.0) || !std::isfinite(options.blurFloorPx))
        return "--blur-floor must be a finite 0 or more pixels, e.g. --blur-floor 1.5";
    // (CLI::Range lets a NaN through: no comparison with it fails.)
    if (std::isnan(options.minConfidence))
        return "--min-confidence must be a number from 0 to 1, e.g. 0.1";
    return {};
}

int reportError(const std::string& command, const Error& error) {
    std::cerr << "infocus " << command << ": " << error.message << "\n";
    return error.kind == ErrorKind::Usage ? kExitUsage : kExitFailure;
}

void warnIfSharpened(const std::string& command, const FrameAnalysis& a, bool& warned) {
    if (warned || !a.sharpeningHalo || *a.sharpeningHalo < kSharpenedHaloFraction) return;
    warned = true;
    int regions = 0;
    for (const RegionResult& r : a.regions)
        regions += r.haloFraction ? 1 : 0;
    std::cerr << "infocus " << command << ": frame " << a.frame
              << ": the sharp edges carry halos on both sides (median " << std::fixed
              << std::setprecision(1) << 100.0 * *a.sharpeningHalo << " % of their contrast, "
              << regions
              << " regions): the frames look sharpened, and sharpening makes blur widths read "
                 "narrow (a 1 px blur by up to a third); turn the camera's sharpening off "
                 "('infocus devices' lists the control) or analyse frames that are not "
                 "sharpened\n"
              << std::defaultfloat;
}

void noteTransfer(const std::string& command, const SourceInfo& source,
                  const AnalysisOptions& options) {
    if (!options.transferFromSource) return;
    const auto& [curve, told] = source.transfer;
    const std::string origin = told.empty() ? "the source names no transfer function" : told;
    if (curve == TransferFunction::Linear)
        std::cerr << "infocus " << command << ": the frames hold linear light, measured as they "
                  << "are (--transfer auto: " << origin << ")\n";
    else if (curve)
        std::cerr << "infocus " << command << ": blur measured in linear light, the frames decoded "
                  << "from " << (*curve == TransferFunction::Srgb ? "sRGB" : "BT.709")
                  << " (--transfer auto: " << origin << ")\n";
    else
        std::cerr << "infocus " << command << ": --transfer auto: " << origin
                  << "; grey levels measured as they are (linear): give --transfer srgb or rec709 "
                     "if you know the camera's curve\n";
}

int usageError(const std::string& command, const std::string& message) {
    std::cerr << "infocus " << command << ": " << message << "\n"
              << "Run 'infocus " << command << " --help' for the options.\n";
    return kExitUsage;
}

CLI::Validator frameCount(uint64_t least) {
    return CLI::Validator(
        [least](const std::string& text) {
            uint64_t n = 0;
            if (!readsWhole(text, n) || n < least)
                return "'" + text + "' is not a frame count; give a whole number ≥ " +
                       std::to_string(least) + ", e.g. 100";
            return std::string();
        },
        "N");
}

CLI::Validator secondsIn(double lo, double hi, const std::string& example) {
    return CLI::Validator(
        [lo, hi, example](const std::string& text) {
            double s = 0.0;
            // Written so that a NaN fails too (no comparison with it holds).
            if (!readsWhole(text, s) || !(s > lo && s <= hi))
                return "'" + text + "' is not a duration here; give seconds above " +
                       CLI::detail::to_string(lo) +
                       (std::isfinite(hi) ? " and at most " + CLI::detail::to_string(hi) : "") +
                       ", e.g. " + example;
            return std::string();
        },
        "S");
}

}  // namespace infocus::cli
