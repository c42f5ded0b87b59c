// SPDX-License-Identifier: MIT
/// @file bench_module.h
/// The benchmark module (infocus-bench.so): the rows of `infocus bench` with their OpenCV
/// baselines and synthetic frames. OpenCV's core and imgproc cost every command their start-up,
/// so only `infocus bench` loads them, with this module. Internal to infocus.
#pragma once

#include <string>
#include <vector>

#include "bench/bench.h"
#include "infocus/error.h"

namespace infocus::bench {

/// The module's entry points (bench.h says what each does). Built with the executable that
/// loads it: kBenchAbi guards against a module left from another version.
struct BenchModule {
    int abi;
    void (*runAll)(const BenchOptions& options, const RowSink& sink);
    void (*benchBlurImages)(const BenchOptions& options, const std::string& input,
                            const std::vector<Image<uint8_t>>& images, const RowSink& sink);
    const std::vector<double>& (*accuracyAngles)();
    void (*runAccuracy)(const AccuracySink& sink);
    void (*runSquareAccuracy)(const SquareSink& sink);
    const std::vector<double>& (*mtfAccuracyAngles)();
    void (*runMtfAccuracy)(const MtfSink& sink);
};

/// Version of struct BenchModule; raised whenever it or a type it passes changes.
inline constexpr int kBenchAbi = 4;

/// File name of the module and the name of its entry point.
inline constexpr const char* kBenchModule = "infocus-bench.so";
inline constexpr const char* kBenchEntry = "infocus_bench";

/// The module's entry points, loaded on the first call. On failure, an error that says that
/// @p purpose ("measuring this machine's speed") needs the module, where it was looked for and
/// what to do.
Result<const BenchModule*> loadBench(const std::string& purpose);

}  // namespace infocus::bench

extern "C" {
/// The module's one exported symbol: its entry points.
const infocus::bench::BenchModule* infocus_bench();
}
