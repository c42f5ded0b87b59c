// SPDX-License-Identifier: MIT
// The benchmark module's exported entry point.
#include "bench/bench_module.h"

extern "C" __attribute__((visibility("default"))) const infocus::bench::BenchModule*
infocus_bench() {
    static const infocus::bench::BenchModule kBench{
        infocus::bench::kBenchAbi,          &infocus::bench::runAll,
        &infocus::bench::benchBlurImages,   &infocus::bench::accuracyAngles,
        &infocus::bench::runAccuracy,       &infocus::bench::runSquareAccuracy,
        &infocus::bench::mtfAccuracyAngles, &infocus::bench::runMtfAccuracy,
    };
    return &kBench;
}
