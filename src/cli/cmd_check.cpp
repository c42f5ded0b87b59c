// SPDX-License-Identifier: MIT
// `infocus check`: a pass/fail gate for a production line or a CI system. Measures the frames
// (or, with --positions, a stack's MTF50 through focus), judges them against a spec and exits 0
// on a pass, 3 on a failure (include/infocus/qa.h, docs/qa.md).
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "infocus/luma.h"
#include "infocus/pipeline.h"
#include "infocus/qa.h"
#include "infocus/report.h"
#include "infocus/stack.h"
#include "lens_options.h"

namespace infocus::cli {

namespace {

constexpr const char* kName = "check";
// Exit status of a frame or stack that fails its spec.
constexpr int kExitSpecFailed = 3;

struct CheckArgs {
    std::string source, spec, junit, positions, report;
    LensOptions lens;
    uint64_t frames = 0;
    bool json = false;
};

int runCheck(const CheckArgs& args) {
    auto spec = qa::readSpec(args.spec);
    if (!spec) return reportError(kName, spec.error());
    auto values = args.lens.resolve();
    if (!values) return reportError(kName, values.error());
    // A limit in lens units needs the lens data to convert: said before anything is measured.
    if (const auto key = spec->needsPixelPitch(); key && !values->pixelPitch)
        return usageError(kName, "the spec's " + *key +
                                     " needs the pixel pitch; give --pixel-pitch, e.g. 1.4um "
                                     "(or --lens PRESET)");
    if (spec->needsFNumber() && args.positions.empty() && !values->fNumber)
        return usageError(kName,
                          "the spec's tilt limit needs the f-number to turn blur into defocus; "
                          "give --fnumber, e.g. 1.8 (or --lens PRESET)");
    if (spec->maxTiltDeg && !args.positions.empty() && !values->pixelPitch)
        return usageError(kName,
                          "the spec's max_tilt_deg over a stack needs the pixel pitch to know "
                          "the sensor's size; give --pixel-pitch, e.g. 1.4um");
    const qa::LensData lens{values->pixelPitch, values->fNumber, values->focalLength};
    std::vector<qa::Verdict> verdicts;
    std::optional<qa::ThroughFocus> through;
    Image<uint8_t> first;  // the first frame, for the report's zone map
    if (!args.positions.empty()) {
        StackOptions options;
        options.cols = spec->cols, options.rows = spec->rows;
        options.maps = false;
        auto p = readPositionsCsv(args.positions);
        if (!p) return reportError(kName, p.error());
        options.positions = std::move(*p);
        auto r = analyzeStack(args.source, options);
        if (!r) return reportError(kName, r.error());
        const qa::ThroughFocus tf =
            qa::throughFocus(*r, spec->minConfidence, spec->dofThresholdCyPx);
        verdicts.push_back(qa::judgeStack(*r, tf, *spec, lens));
        if (!args.json) std::cout << qa::throughFocusTable(tf);
        through = tf;
    } else {
        AnalysisOptions options;
        options.cols = spec->cols, options.rows = spec->rows;
        bool endless = false;
        const auto onStart = [&](const SourceInfo& info, const AnalysisOptions&) {
            endless = !info.frameCount.has_value();
        };
        uint64_t damaged = 0;
        const auto onDamaged = [&](const Error& e) {
            ++damaged;
            std::cerr << "infocus check: skipped a damaged frame: " << e.message << "\n";
        };
        const Status st = analyzeSourceFrames(
            args.source, options, args.frames,
            [&](const FrameAnalysis& a, const Frame& frame) -> Status {
                verdicts.push_back(qa::judgeFrame(a, *spec, lens));
                if (!args.report.empty() && first.width() == 0)
                    if (auto luma = toLuma8(frame)) {
                        first = Image<uint8_t>(luma->width, luma->height);
                        for (int y = 0; y < luma->height; ++y)
                            std::copy_n(luma->row(y), luma->width, first.row(y));
                    }
                // A camera or the simulated camera never ends: one frame unless --frames.
                if (args.frames == 0 && endless)
                    return makeError(ErrorKind::EndOfStream, "one frame of an endless source");
                return {};
            },
            onDamaged, onStart);
        if (!st && st.error().kind != ErrorKind::EndOfStream) return reportError(kName, st.error());
        if (damaged) {
            std::cerr << "infocus check: " << damaged << " damaged frame(s) skipped\n";
            return kExitFailure;
        }
        if (verdicts.empty())
            return reportError(
                kName,
                makeError(ErrorKind::Corrupt, "'" + args.source + "' delivered no frame to check"));
    }
    if (args.json)
        std::cout << qa::verdictJson(verdicts, args.source) << std::endl;
    else
        std::cout << qa::verdictTable(verdicts, args.source);
    if (!args.junit.empty())
        if (auto s = writeFileAtomically(args.junit, qa::verdictJunit(verdicts, args.source)); !s)
            return reportError(kName, s.error());
    if (!args.report.empty())
        if (auto s = writeFileAtomically(
                args.report, qaReportHtml(verdicts, through, first.view(), args.source));
            !s)
            return reportError(kName, s.error());
    std::cout.flush();
    if (!std::cout)
        return reportError(kName, makeError(ErrorKind::Io, "writing to standard output failed"));
    for (const qa::Verdict& v : verdicts)
        if (!v.pass) return kExitSpecFailed;
    return 0;
}

}  // namespace

Command addCheckCommand(CLI::App& app) {
    auto args = std::make_shared<CheckArgs>();
    CLI::App* sub = app.add_subcommand(
        "check", "Pass/fail gate: MTF50 by zone, blur, tilt and focus against a spec file");
    sub->add_option("SOURCE", args->source,
                    "Frames to check: a camera, sim:, a recording, a video, images; with "
                    "--positions, a focus stack")
        ->required();
    sub->add_option("--spec", args->spec, "The spec: JSON limits (docs/qa.md)")->required();
    sub->add_flag("--json", args->json, "Print the verdicts as one JSON object");
    sub->add_option("--junit", args->junit, "Also write the verdicts as JUnit XML to FILE");
    sub->add_option("--report", args->report,
                    "Also write the QA page (zones in pass/fail colours, criteria, curves) to "
                    "FILE.html");
    sub->add_option("--positions", args->positions,
                    "CSV of frame,position,unit: SOURCE is a stack, judged through focus at each "
                    "region's best MTF50");
    sub->add_option("--frames", args->frames,
                    "Frames to check (default: all of a file or recording, one of a camera)")
        ->check(frameCount());
    args->lens.add(sub, LensOptionSet{.coc = false, .pitch = true});
    sub->footer(
        "Exit status: 0 every frame passed, 3 a frame failed (too dark or without edges fails\n"
        "too), 1 a runtime error, 2 a usage error (a malformed spec names its key and line).\n\n"
        "Example:\n"
        "  infocus check sim:focus=1m --spec line.json --junit check.xml");
    return {sub, [args] { return runCheck(*args); }};
}

}  // namespace infocus::cli
