// SPDX-License-Identifier: MIT
// Loads the benchmark module on first use, in the executable (never in the module itself).
#include "bench/bench_module.h"
#include "src/core/module_loader.h"

namespace infocus::bench {

Result<const BenchModule*> loadBench(const std::string& purpose) {
    return loadModuleTable<BenchModule>(kBenchModule, kBenchEntry, kBenchAbi, purpose, "bench");
}

}  // namespace infocus::bench
