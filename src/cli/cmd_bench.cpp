// SPDX-License-Identifier: MIT
// `infocus bench`: measured speed of this machine, infocus beside a baseline from the same run.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>
#include <memory>

#include "bench/bench.h"
#include "commands.h"

namespace infocus::cli {

namespace {

struct BenchArgs {
    bool json = false;
    bool accuracy = false;
    double seconds = 0.25;
};

// The blur engine's accuracy table: true vs measured width on synthetic edges.
int runAccuracyTable(bool json) {
    const auto& angles = bench::accuracyAngles();
    if (!json) {
        std::printf(
            "blur accuracy: synthetic edges, pixel-integrated, 8-bit, contrast 150 grey levels\n");
        std::printf("%-8s %6s %6s", "model", "true", "noise%");
        for (double a : angles)
            std::printf(" %6.1f°", a);
        std::printf(" %7s  %s\n", "worst%", "target");
    }
    int misses = 0;
    bench::runAccuracy([&](const bench::AccuracyRow& row) {
        if (row.inTarget && !row.pass) ++misses;
        if (json) {
            nlohmann::ordered_json j;
            j["what"] = "blur_accuracy";
            j["model"] = row.model == "disc d" ? "disc_diameter" : "gaussian_sigma";
            j["true_px"] = row.truePx;
            j["noise_pct"] = row.noisePct;
            nlohmann::ordered_json m = nlohmann::ordered_json::array();
            for (size_t i = 0; i < angles.size(); ++i)
                m.push_back(
                    {{"angle_deg", angles[i]},
                     {"measured_px", row.measuredPx[i] ? nlohmann::ordered_json(*row.measuredPx[i])
                                                       : nlohmann::ordered_json()}});
            j["measured"] = m;
            j["worst_error_pct"] = row.worstErrorPct;
            j["tolerance_pct"] = row.tolerancePct;
            j["in_target"] = row.inTarget;
            j["pass"] = row.pass;
            std::cout << j.dump() << std::endl;
            return;
        }
        std::printf("%-8s %6.2f %6.1f", row.model.c_str(), row.truePx, row.noisePct);
        for (const auto& m : row.measuredPx) {
            if (m)
                std::printf(" %7.3f", *m);
            else
                std::printf(" %7s", "none");
        }
        std::printf(" %7.2f  ", row.worstErrorPct);
        if (row.inTarget)
            std::printf("±%.0f%% %s\n", row.tolerancePct, row.pass ? "ok" : "MISS");
        else
            std::printf("(outside target range)\n");
        std::fflush(stdout);
    });
    if (!json) std::printf("%d row(s) inside the target ranges missed their tolerance\n", misses);
    return 0;
}

int runBench(const BenchArgs& args) {
    if (args.accuracy) return runAccuracyTable(args.json);
    bench::BenchOptions options;
    options.secondsPerCase = args.seconds;
    if (!args.json)
        std::printf("%-14s %11s %12s %12s %9s  %s\n", "what", "size", "infocus ms", "baseline ms",
                    "speedup", "baseline");
    bench::runAll(options, [&](const bench::BenchRow& row) {
        if (args.json) {
            nlohmann::ordered_json j;
            j["what"] = row.what;
            j["width"] = row.width;
            j["height"] = row.height;
            j["ms"] = row.ms;
            if (row.baselineMs) {
                j["baseline_ms"] = *row.baselineMs;
                j["speedup"] = *row.baselineMs / row.ms;
                j["baseline"] = row.baseline;
            }
            if (!row.focusOperator.empty()) j["operator"] = row.focusOperator;
            if (row.frameBlurPx) j["frame_blur_width_px"] = *row.frameBlurPx;
            if (!row.note.empty()) j["note"] = row.note;
            std::cout << j.dump() << std::endl;
            return;
        }
        char size[32];
        std::snprintf(size, sizeof size, "%dx%d", row.width, row.height);
        if (row.baselineMs)
            std::printf("%-14s %11s %12.3f %12.3f %8.1fx  %s", row.what.c_str(), size, row.ms,
                        *row.baselineMs, *row.baselineMs / row.ms, row.baseline.c_str());
        else
            std::printf("%-14s %11s %12.3f %12s %9s  -", row.what.c_str(), size, row.ms, "-", "-");
        if (!row.note.empty()) std::printf(" (%s)", row.note.c_str());
        std::printf("\n");
        std::fflush(stdout);
    });
    return 0;
}

}  // namespace

Command addBenchCommand(CLI::App& app) {
    auto args = std::make_shared<BenchArgs>();
    CLI::App* sub = app.add_subcommand(
        "bench", "Measure this machine's speed: infocus beside a baseline timed in the same run");
    sub->add_flag("--json", args->json, "One JSON object per line instead of a table");
    sub->add_flag("--accuracy", args->accuracy,
                  "Print the blur engine's accuracy on synthetic edges of known blur instead");
    sub->add_option("--seconds", args->seconds, "Time budget per measured case")
        ->check(secondsIn(0.0, 10.0, "0.5"))
        ->capture_default_str();
    return {sub, [args] { return runBench(*args); }};
}

}  // namespace infocus::cli
