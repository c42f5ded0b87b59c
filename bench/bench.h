// SPDX-License-Identifier: MIT
/// @file bench.h
/// `infocus bench`: this machine's speed for each kernel, beside a baseline timed in the same run.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace infocus::bench {

/// One measured case: infocus's time per frame and, where one applies, the baseline's.
struct BenchRow {
    std::string what;  ///< "sharpness", "blur", "mjpeg_luma", ...
    int width = 0;
    int height = 0;
    double ms = 0.0;                   ///< infocus, median milliseconds per frame
    std::optional<double> baselineMs;  ///< the baseline, median milliseconds per frame
    std::string baseline;              ///< what the baseline is, e.g. "cv::Laplacian+meanStdDev"
    std::string note;                  ///< threads used, target, ...
};

/// Options shared by all benchmarks.
struct BenchOptions {
    double secondsPerCase = 0.25;  ///< time budget for each timed loop
};

/// Receives each row as soon as it is measured.
using RowSink = std::function<void(const BenchRow&)>;

/// Runs every registered benchmark, in order, handing each row to @p sink.
void runAll(const BenchOptions& options, const RowSink& sink);

/// Median time in milliseconds of one call of @p fn, after a warm-up call, over at least 5 calls
/// or @p budgetS seconds, whichever is longer.
double medianMs(const std::function<void()>& fn, double budgetS);

// Registered benchmarks (bench/bench.cpp lists them).
/// MJPEG luma-only decode (infocus) vs full-colour RGB decode of the same 1080p JPEG.
void benchMjpeg(const BenchOptions& options, const RowSink& sink);

}  // namespace infocus::bench
