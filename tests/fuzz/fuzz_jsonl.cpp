// SPDX-License-Identifier: MIT
// The analyze JSONL reader, as `depth` and `report` read it back: every line parsed, and what
// parses written again and mapped to depth.
#include <string>
#include <string_view>

#include "infocus/analysis.h"
#include "infocus/depth_map.h"
#include "infocus/output.h"
#include "infocus/source.h"
#include "tests/fuzz/fuzz.h"

namespace infocus::fuzz {

std::vector<std::vector<uint8_t>> seeds() {
    std::vector<std::vector<uint8_t>> out;
    // Real lines: a simulated frame analysed on a small grid, with and without ROIs.
    auto source = openSource("sim:size=96x64,pace=fast,noise=0.01");
    if (!source || !(*source)->start()) return out;
    auto frame = (*source)->next();
    if (!frame) return out;
    frame->lens = LensPosition{2.0, "dioptre", 2.0};
    for (int grid : {1, 3}) {
        AnalysisOptions options;
        options.cols = grid;
        options.rows = grid;
        auto analyzer = Analyzer::create(options);
        if (!analyzer) continue;
        auto a = (*analyzer)->analyze(*frame, 0);
        if (!a) continue;
        const std::string line = toJsonLine(*a) + "\n" + toJsonLine(*a);
        out.emplace_back(line.begin(), line.end());
    }
    const std::string small = R"({"frame": 0, "width": 4, "height": 2, "regions": []})";
    out.emplace_back(small.begin(), small.end());
    return out;
}

}  // namespace infocus::fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace infocus;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    size_t at = 0;
    while (at <= text.size()) {
        size_t end = text.find('\n', at);
        if (end == std::string_view::npos) end = text.size();
        auto a = parseJsonLine(text.substr(at, end - at));
        if (a) {
            (void)parseJsonLine(toJsonLine(*a));
            (void)depthMap(*a, std::nullopt);
        }
        at = end + 1;
    }
    return 0;
}
