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
    double seconds = 0.25;
};

int runBench(const BenchArgs& args) {
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
    sub->add_option("--seconds", args->seconds, "Time budget per measured case")
        ->check(CLI::Range(0.01, 10.0))
        ->capture_default_str();
    return {sub, [args] { return runBench(*args); }};
}

}  // namespace infocus::cli
