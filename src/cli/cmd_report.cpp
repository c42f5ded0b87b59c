// SPDX-License-Identifier: MIT
// `infocus report`: a self-contained HTML report of where a source is focused, what lies inside
// the depth of field and how the scene is tilted (include/infocus/report.h).
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "infocus/luma.h"
#include "infocus/pipeline.h"
#include "infocus/report.h"
#include "lens_options.h"
#include "parse.h"
#include "progress.h"

namespace infocus::cli {

namespace {

constexpr const char* kName = "report";

struct ReportArgs {
    std::string source;
    std::string output;
    std::string title;
    LensOptions lens;
    std::string grid = "16x9";
    uint64_t frames = 1;
    std::string transfer = "linear";
    DepthMapOptions depth;
    unsigned jobs = defaultJobs();
    bool quiet = false;
};

// The report's optics from the lens options: what is missing stays empty (the report then says
// what it would add), but half a lens is worth a word, since it is most likely a slip.
Result<ReportOptics> opticsFrom(const LensValues& v) {
    ReportOptics p;
    if (v.focalLength && v.fNumber)
        p.lens = optics::ThinLens{*v.focalLength, *v.fNumber};
    else if (v.focalLength || v.fNumber)
        std::cerr << "infocus report: "
                  << (v.focalLength ? "--focal without --fnumber" : "--fnumber without --focal")
                  << ": the report stays in pixels; give both, or --lens PRESET\n";
    p.pixelPitch = v.pixelPitch;
    if (v.focusDistance) {
        if (p.lens && !(*v.focusDistance > p.lens->focalLength))
            return makeError(
                ErrorKind::Usage,
                "the focus distance " + formatDistance(*v.focusDistance) +
                    " is at or inside the focal length; focus farther, e.g. --focus 1m");
        p.focusDistance = v.focusDistance;
        p.focusSource = "--focus";
    }
    if (v.coc) {
        if (!v.pixelPitch)
            return makeError(
                ErrorKind::Usage,
                "a circle of confusion on the sensor needs the pixel size to be compared "
                "with blur in pixels: add --pixel-pitch, e.g. --pixel-pitch 1.4um, or give "
                "--coc-px");
        p.cocPx = *v.coc / *v.pixelPitch;
        p.cocSource = v.cocSource;
    } else {
        p.cocPx = 2.0;
        p.cocSource = "2 px, the default; set it with --coc, --coc-px or --sensor";
    }
    return p;
}

int runReport(const ReportArgs& args) {
    auto values = args.lens.resolve();
    if (!values) return reportError(kName, values.error());
    auto optics = opticsFrom(*values);
    if (!optics) return reportError(kName, optics.error());
    if (const std::string u = depthMapOptionsUsage(args.depth); !u.empty())
        return usageError(kName, u);
    // The output's folder is checked before a camera is opened or a long stream read.
    const std::filesystem::path out(args.output);
    const std::filesystem::path dir = out.has_parent_path() ? out.parent_path() : ".";
    std::error_code ec;
    if (std::filesystem::is_directory(out, ec))
        return usageError(kName, "-o " + args.output +
                                     " is a folder; name the report's file, e.g. -o " +
                                     (out / "report.html").string());
    if (!std::filesystem::is_directory(dir, ec))
        return usageError(kName, "-o " + args.output + ": the folder " + dir.string() +
                                     " does not exist; create it or write elsewhere");
    AnalysisOptions options;
    const auto grid = parseGrid(args.grid);
    if (!grid) return usageError(kName, gridUsage(args.grid));
    options.cols = grid->first;
    options.rows = grid->second;
    if (!parseTransfer(args.transfer, options))
        return usageError(kName, transferUsage(args.transfer));

    ReportOptions ro;
    ro.source = args.source;
    if (!args.title.empty()) ro.title = args.title;
    ro.optics = std::move(*optics);
    ro.depth = args.depth;
    ReportWriter writer(std::move(ro));
    LumaConverter converter;
    bool warnedSharpened = false;
    uint64_t damaged = 0;
    const auto sink = [&](const FrameAnalysis& a, const Frame& frame) -> Status {
        warnIfSharpened(kName, a, warnedSharpened);
        auto luma = converter.toLuma8(frame);
        if (!luma) return luma.error();
        return writer.add(a, *luma);
    };
    ProgressLine progress(kName, args.quiet);
    const auto onDamaged = [&](const Error& e) {
        ++damaged;
        progress.clear();
        std::cerr << "infocus report: skipped a damaged frame: " << e.message << "\n";
    };
    const auto onStart = [&](const SourceInfo& info, const AnalysisOptions& used) {
        if (info.liveCamera) progress.disable();
        noteTransfer(kName, info, used);
    };
    StreamOptions stream;
    stream.jobs = args.jobs;
    stream.progress = [&](uint64_t done, uint64_t total) { progress.update(done, total); };
    const Status st =
        analyzeSourceFrames(args.source, options, args.frames, sink, onDamaged, onStart, stream);
    progress.clear();
    if (!st && writer.frames() == 0) return reportError(kName, st.error());
    if (writer.frames() == 0)
        return reportError(
            kName, makeError(ErrorKind::Corrupt, "'" + args.source +
                                                     "' delivered no frame to report on; "
                                                     "check the source with 'infocus analyze'"));
    // Frames measured before a failure are still reported: the report says how many it holds.
    const std::string html = writer.html();
    if (const Status w = writeFileAtomically(args.output, html); !w)
        return reportError(kName, w.error());
    std::cerr << "infocus report: wrote " << args.output << " (" << writer.frames() << " frame"
              << (writer.frames() == 1 ? "" : "s") << ", " << (html.size() + 1023) / 1024
              << " KiB)\n";
    if (damaged) std::cerr << "infocus report: " << damaged << " damaged frame(s) skipped\n";
    if (!st) return reportError(kName, st.error());
    // As analyze: the report of the intact frames is written, the damage still fails the run.
    return damaged ? kExitFailure : 0;
}

}  // namespace

Command addReportCommand(CLI::App& app) {
    auto args = std::make_shared<ReportArgs>();
    CLI::App* sub = app.add_subcommand(
        "report",
        "Write a self-contained HTML report: what is in focus, the depth of field and the tilt");
    sub->add_option("SOURCE", args->source,
                    "Camera, recording, video, image(s) or sim: (see 'infocus --help')")
        ->required();
    sub->add_option("-o,--output", args->output, "The HTML file to write")->required();
    args->lens.add(sub, LensOptionSet{.coc = true, .pitch = true});
    sub->add_option("--grid", args->grid, "Regions as columns x rows")->capture_default_str();
    sub->add_option("--frames", args->frames, "Frames to report on (0: every frame of the source)")
        ->check(frameCount())
        ->capture_default_str();
    sub->add_option("--transfer", args->transfer,
                    "How grey levels encode light: linear, srgb, rec709 or auto (the source's own)")
        ->capture_default_str();
    addDepthMapOptions(sub, args->depth);
    sub->add_option("--jobs", args->jobs,
                    "Frames of a file or recording measured at once (the report is the same as "
                    "with 1); cameras run one at a time")
        ->check(CLI::Range(1u, 256u))
        ->default_str("the machine's cores");
    sub->add_flag("--quiet", args->quiet,
                  "No progress line on stderr (it is shown only when stderr is a terminal)");
    sub->add_option("--title", args->title, "The report's title");
    sub->footer(
        "The report embeds each frame with its regions tinted by blur, the blur and\n"
        "sharpness maps, the blur against the distance from the in-focus line, and a\n"
        "table of every region. With the lens (--focal and --fnumber, or --lens), the\n"
        "pixel pitch and the focus (--focus, or the frames' own lens position in\n"
        "dioptres) it adds distances, the depth of field and the tilt.\n\n"
        "Examples:\n"
        "  infocus report sim:scene=tilted,focus=0.5m -o tilted.html \\\n"
        "      --lens rpi-cam3 --pixel-pitch 5.04um\n"
        "  infocus report 'stack/img_*.jpg' --frames 0 -o stack.html");
    return {sub, [args] { return runReport(*args); }};
}

}  // namespace infocus::cli
