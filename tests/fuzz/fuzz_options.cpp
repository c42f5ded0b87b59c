// SPDX-License-Identifier: MIT
// The parsers of source strings and options: any text as a source string (its playback and
// sim: options, and one frame of a small simulated camera), and as the value of every
// structured command-line option (grid, ROI, transfer, lengths, focus, f-number, pixel format).
#include <string>
#include <string_view>

#include "infocus/luma.h"
#include "infocus/sim.h"
#include "infocus/source.h"
#include "replay/playback.h"
#include "src/cli/lens_options.h"
#include "src/cli/parse.h"
#include "tests/fuzz/fuzz.h"

namespace infocus::fuzz {

std::vector<std::vector<uint8_t>> seeds() {
    std::vector<std::vector<uint8_t>> out;
    for (const std::string_view s :
         {"sim:size=32x24,scene=steps,distances=0.5:1:2,noise=0.01,seed=7",
          "sim:size=16x16,scene=tilted,tilt=40,axis=y,format=YUYV,focus=0.8",
          "sim:size=16x16,scene=edges,angle=5,lens=rpi-cam3,fps=1e-6",
          "rec/,loop=1,start=2.5s,pace=original", "/dev/video0,format=MJPG,size=640x480", "16x9",
          "10,20,30,40", "srgb", "50mm", "1.2m", "inf", "f/2.8", "YUYV"})
        out.emplace_back(s.begin(), s.end());
    return out;
}

}  // namespace infocus::fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace infocus;
    const std::string text(reinterpret_cast<const char*>(data), size);
    (void)cli::parseGrid(text);
    (void)cli::gridUsage(text);
    (void)cli::parseRoi(text);
    AnalysisOptions options;
    (void)cli::parseTransfer(text, options);
    (void)cli::parseLength(text, "--option");
    (void)cli::parseFocus(text, "--focus");
    (void)cli::parseFNumber(text, "--f-number");
    (void)parsePixelFormat(text);

    auto spec = parseSourceSpec(text);
    if (!spec) return 0;
    (void)replay::parsePlaybackOptions(*spec);
    if (spec->kind != "sim") return 0;
    auto config = parseSimOptions(spec->options);
    // Renders only small frames, at once (a paced camera at 1e-6 fps would wait for days).
    if (!config || int64_t{config->size.width} * config->size.height > 64 * 64) return 0;
    spec->options["pace"] = "fast";
    auto source = openSource(*spec);
    if (!source || !(*source)->start()) return 0;
    if (auto frame = (*source)->next()) (void)toLuma8(*frame);
    (*source)->stop();
    return 0;
}
