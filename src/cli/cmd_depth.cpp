// SPDX-License-Identifier: MIT
// `infocus depth`: per-region depth from blur width and the in-focus plane, from `analyze` output
// (JSONL) or straight from a source.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "infocus/analysis.h"
#include "infocus/analysis_output.h"
#include "infocus/depth_map.h"
#include "infocus/depth_output.h"
#include "infocus/pipeline.h"
#include "infocus/plane_fit.h"
#include "lens_options.h"
#include "parse.h"

namespace infocus::cli {

namespace {

constexpr const char* kName = "depth";

struct DepthArgs {
    std::string input;
    LensOptions lens;
    DepthMapOptions depth;
    std::string grid = "16x9";
    uint64_t frames = 1;
    std::string transfer = "linear";
    bool json = false;
};

// What frame @p a needs beyond its measurements: a complete lens with a focus distance.
Result<DepthCamera> lensFor(const LensValues& v, const FrameAnalysis& a) {
    const auto usage = [](const std::string& m) { return makeError(ErrorKind::Usage, m); };
    if (!v.focalLength)
        return usage("give the focal length, e.g. --focal 4.74mm (or --lens rpi-cam3)");
    if (!v.fNumber) return usage("give the aperture, e.g. --fnumber 1.8 (or --lens PRESET)");
    if (!v.pixelPitch)
        return usage(
            "give the pixel pitch of the analysed image, e.g. --pixel-pitch 1.4um (for a "
            "downscaled image, the sensor pitch times the scale factor)");
    DepthCamera camera;
    camera.lens = {*v.focalLength, *v.fNumber};
    camera.pixelPitch = *v.pixelPitch;
    if (v.focusDistance) {
        camera.focusDistance = *v.focusDistance;
        camera.focusSource = "--focus";
    } else if (const auto focus = focusFromLensPosition(a)) {
        camera.focusDistance = *focus;
        camera.focusSource = "lens position of the frame";
    } else {
        return usage("give the focus distance, e.g. --focus 0.5m or --focus 2dpt (frame " +
                     std::to_string(a.frame) + " carries no lens position in dioptres)");
    }
    if (!(camera.focusDistance > camera.lens.focalLength))
        return usage("the focus distance " + formatDistance(camera.focusDistance) +
                     " is at or inside the focal length; focus farther, e.g. --focus 1m");
    return camera;
}

Status processFrame(const FrameAnalysis& a, const DepthArgs& args, const LensValues& values) {
    auto camera = lensFor(values, a);
    if (!camera) return camera.error();
    camera->blurFloorPx = args.depth.blurFloorPx;
    const DepthMap map =
        depthMap(a,
                 optics::CameraGeometry{camera->lens, camera->focusDistance, camera->pixelPitch,
                                        0.5 * a.width, 0.5 * a.height},
                 args.depth);
    if (args.json)
        std::cout << depthJsonLine(a, map, *camera) << std::endl;
    else
        writeDepthTable(std::cout, a, map, *camera);
    return {};
}

bool isJsonlFile(const std::string& input) {
    std::error_code ec;
    return input.size() > 6 && input.ends_with(".jsonl") &&
           std::filesystem::is_regular_file(input, ec);
}

int runDepth(const DepthArgs& args) {
    auto values = args.lens.resolve();
    if (!values) return reportError(kName, values.error());
    if (const std::string u = depthMapOptionsUsage(args.depth); !u.empty())
        return usageError(kName, u);
    uint64_t frames = 0, damaged = 0;
    bool warnedSharpened = false;
    const auto sink = [&](const FrameAnalysis& a) -> Status {
        ++frames;
        warnIfSharpened(kName, a, warnedSharpened);
        return processFrame(a, args, *values);
    };
    if (args.input == "-" || isJsonlFile(args.input)) {
        std::ifstream file;
        if (args.input != "-") file.open(args.input);
        std::istream& in = args.input == "-" ? std::cin : file;
        std::string line;
        uint64_t lineNo = 0;
        while (std::getline(in, line)) {
            ++lineNo;
            if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
            auto a = parseJsonLine(line);
            if (!a) {
                auto e = a.error();
                e.message = args.input + " line " + std::to_string(lineNo) + ": " + e.message;
                return reportError(kName, e);
            }
            if (const Status st = sink(*a); !st) return reportError(kName, st.error());
        }
    } else {
        AnalysisOptions options;
        const auto grid = parseGrid(args.grid);
        if (!grid) return usageError(kName, gridUsage(args.grid));
        options.cols = grid->first;
        options.rows = grid->second;
        if (!parseTransfer(args.transfer, options))
            return usageError(kName, transferUsage(args.transfer));
        const auto onStart = [&](const SourceInfo& info, const AnalysisOptions& used) {
            noteTransfer(kName, info, used);
        };
        // Damaged frames were skipped without a word: said as analyze says them, and exit 1.
        const auto onDamaged = [&](const Error& e) {
            ++damaged;
            std::cerr << "infocus depth: skipped a damaged frame: " << e.message << "\n";
        };
        if (const Status st =
                analyzeSource(args.input, options, args.frames, sink, onDamaged, onStart);
            !st)
            return reportError(kName, st.error());
    }
    if (frames == 0)
        return reportError(
            kName, makeError(ErrorKind::Corrupt, "'" + args.input +
                                                     "' held no frame; give 'infocus analyze' "
                                                     "output or a source that delivers frames"));
    if (damaged) {
        std::cerr << "infocus depth: " << damaged << " damaged frame(s) skipped\n";
        return kExitFailure;
    }
    return 0;
}

}  // namespace

Command addDepthCommand(CLI::App& app) {
    auto args = std::make_shared<DepthArgs>();
    CLI::App* sub = app.add_subcommand(
        "depth", "Per-region depth from blur width, the in-focus line and the tilt of the scene");
    sub->add_option("INPUT", args->input, "analyze JSONL file, - (stdin), or a SOURCE")->required();
    args->lens.add(sub, LensOptionSet{.coc = false, .pitch = true});
    addDepthMapOptions(sub, args->depth);
    sub->add_option("--grid", args->grid, "Regions as columns x rows (SOURCE input)")
        ->capture_default_str();
    sub->add_option("--frames", args->frames, "Frames to analyse (SOURCE input; 0: all)")
        ->check(frameCount())
        ->capture_default_str();
    sub->add_option(
           "--transfer", args->transfer,
           "How grey levels encode light (SOURCE input): linear, srgb, rec709 or auto (the "
           "source's own)")
        ->capture_default_str();
    sub->add_flag("--json", args->json, "One JSON object per frame (JSONL)");
    sub->footer(
        "Each region's blur width b gives two depths, 1/z = 1/u +- b/(A z_s), in front of and\n"
        "behind the in-focus distance u. A robust fit of |p0 + p1 x + p2 y| to the blur map gives\n"
        "the in-focus line and the tilt of the scene; one focus setting cannot say which side of\n"
        "that line is nearer, so both readings are shown.\n\n"
        "Examples:\n"
        "  infocus analyze sim:scene=tilted,focus=0.5m -o tilt.jsonl\n"
        "  infocus depth tilt.jsonl --lens rpi-cam3 --pixel-pitch 5.04um --focus 0.5m\n"
        "    (sim: renders the 4608-pixel-wide sensor at 1280 wide: 1.4um x 3.6 per pixel)\n"
        "  infocus depth sim:scene=tilted --focal 25mm --fnumber 1.4 --pixel-pitch 3.45um "
        "--focus 2dpt --json");
    return {sub, [args] { return runDepth(*args); }};
}

}  // namespace infocus::cli
