// SPDX-License-Identifier: MIT
// `infocus analyze`: per-region sharpness and blur width of every frame of a source, as JSONL or
// CSV, written frame by frame so that nothing measured is lost when a later frame fails.
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include <unistd.h>

#include "commands.h"
#include "infocus/analysis.h"
#include "infocus/analysis_output.h"
#include "infocus/metrics.h"
#include "infocus/pipeline.h"
#include "infocus/source.h"
#include "parse.h"
#include "progress.h"

namespace infocus::cli {

namespace {

struct AnalyzeArgs {
    std::string source;
    std::string grid = "16x9";
    std::vector<std::string> rois;
    std::string metric;
    uint64_t frames = 0;
    std::string format = "jsonl";
    std::string output;
    bool noBlur = false;
    bool centreWeighted = false;
    std::string blurSearch = "auto";
    bool blurSearchGiven = false;  // --blur-search on the command line (not its default)
    std::string transfer = "linear";
    unsigned jobs = defaultJobs();
    bool quiet = false;
};

// What --blur-search asks of AnalysisOptions: the regions searched afresh a frame (0: all), the
// seconds their searches may take (0: no limit), and whether a live camera is tracked instead.
struct BlurSearch {
    int perFrame = 0;
    double budgetS = 0.0;
    bool trackLiveCamera = false;
};

// The blur searches of --blur-search @p text, or none when @p text is not all, auto or a count.
std::optional<BlurSearch> blurSearch(const std::string& text) {
    if (text == "all") return BlurSearch{};
    // A live camera's stream is tracked (BlurTracker) so that the blur keeps up with the frame
    // rate; recordings, files and sim: are searched in full on every frame, for the best reading
    // of each. The stream loop asks the source which it is.
    if (text == "auto") return BlurSearch{0, 0.0, true};
    int n = 0;
    if (!readsWhole(text, n) || n < 1 || n > 65536) return std::nullopt;
    return BlurSearch{n, 0.0};
}

int runAnalyze(const AnalyzeArgs& args) {
    const std::string cmd = "analyze";
    AnalysisOptions options;
    const auto grid = parseGrid(args.grid);
    if (!grid) return usageError(cmd, gridUsage(args.grid));
    options.cols = grid->first;
    options.rows = grid->second;
    for (const auto& r : args.rois) {
        const auto roi = parseRoi(r);
        if (!roi)
            return usageError(cmd,
                              "--roi " + r + ": give x,y,w,h in pixels, e.g. --roi 100,80,320,240");
        options.rois.push_back(*roi);
    }
    options.metric = args.metric;
    // Both asked for: one of them is a mistake, and which is not ours to guess.
    if (args.noBlur && args.blurSearchGiven)
        return usageError(cmd,
                          "--blur-search chooses how blur is searched, and --no-blur "
                          "measures none; drop one of them");
    options.measureBlur = !args.noBlur;
    options.centreWeighted = args.centreWeighted;
    const auto search = blurSearch(args.blurSearch);
    if (!search)
        return usageError(cmd, "--blur-search " + args.blurSearch +
                                   ": use all, auto or a number of regions 1-65536, e.g. 16");
    if (!parseTransfer(args.transfer, options))
        return usageError(cmd, transferUsage(args.transfer));
    options.blurSearchesPerFrame = search->perFrame;
    options.blurSearchBudgetS = search->budgetS;
    options.trackLiveCamera = search->trackLiveCamera;
    if (args.format != "jsonl" && args.format != "csv" && args.format != "table")
        return usageError(cmd, "--format " + args.format + ": use jsonl, csv or table");

    // The file is opened (and emptied) with the first frame measured: a source that does not
    // open, or options it refuses, leave an existing file as it was.
    const bool toFile = !args.output.empty() && args.output != "-";
    std::ofstream file;
    std::ostream& out = toFile ? static_cast<std::ostream&>(file) : std::cout;
    const std::string where = toFile ? args.output : "standard output";
    uint64_t written = 0, damaged = 0;
    std::streamoff complete = 0;  // bytes of the frames written whole
    bool warnedSharpened = false;
    ProgressLine progress(cmd, args.quiet);
    // Results on the same terminal as the line: erase it before each, the next update redraws.
    const bool stdoutTerminal = !toFile && isatty(STDOUT_FILENO) == 1;
    StreamOptions stream;
    stream.jobs = args.jobs;
    stream.progress = [&](uint64_t done, uint64_t total) { progress.update(done, total); };
    const Status st = analyzeSource(
        args.source, options, args.frames,
        [&](const FrameAnalysis& a) -> Status {
            warnIfSharpened(cmd, a, warnedSharpened);
            std::ostringstream text;
            if (args.format == "csv")
                writeAnalysisCsv(text, a, written == 0);
            else if (args.format == "table")
                writeAnalysisTable(text, a, options.rois.empty());
            else
                text << toJsonLine(a) << '\n';
            const std::string bytes = text.str();
            if (toFile && !file.is_open()) {
                file.open(args.output, std::ios::out | std::ios::trunc);
                if (!file)
                    return makeError(ErrorKind::Io, "cannot write '" + args.output +
                                                        "'; check the folder exists and is "
                                                        "writable");
            }
            if (stdoutTerminal) progress.clear();
            errno = 0;
            out << bytes;
            out.flush();  // a frame measured is a frame kept
            if (!out) {
                const int e = errno;
                // A disk that fills up leaves part of this frame: cut it off, so that the file
                // ends with the last whole frame (a JSONL reader then reads every line).
                if (file.is_open()) {
                    file.close();
                    std::error_code ec;
                    std::filesystem::resize_file(args.output, static_cast<uintmax_t>(complete), ec);
                }
                return makeError(ErrorKind::Io,
                                 "writing frame " + std::to_string(written) + " to " + where +
                                     " failed" + (e ? std::string(": ") + std::strerror(e) : "") +
                                     (written ? "; the " + std::to_string(written) +
                                                    " frame(s) before it are complete there"
                                              : std::string()) +
                                     "; free disk space or write elsewhere (-o FILE)");
            }
            complete += static_cast<std::streamoff>(bytes.size());
            ++written;
            return {};
        },
        [&](const Error& e) {
            ++damaged;
            progress.clear();
            std::cerr << "infocus analyze: skipped a damaged frame: " << e.message << "\n";
        },
        [&](const SourceInfo& info, const AnalysisOptions& used) {
            // A camera has no end to count towards, and its frames pace themselves.
            if (info.liveCamera) progress.disable();
            noteTransfer(cmd, info, used);
        },
        stream);
    progress.clear();
    if (!st) {
        if (written)
            std::cerr << "infocus analyze: " << written << " frame(s) written before the error\n";
        return reportError(cmd, st.error());
    }
    if (damaged) {
        std::cerr << "infocus analyze: " << damaged << " damaged frame(s) skipped, " << written
                  << " analysed\n";
        return kExitFailure;
    }
    if (written == 0)
        return reportError(
            cmd, makeError(ErrorKind::Corrupt, "source '" + args.source + "' delivered no frame"));
    return 0;
}

}  // namespace

Command addAnalyzeCommand(CLI::App& app) {
    auto args = std::make_shared<AnalyzeArgs>();
    CLI::App* sub = app.add_subcommand(
        "analyze", "Per-region sharpness and blur width of every frame of a source");
    sub->add_option("SOURCE", args->source,
                    "Camera, recording, video, image, directory or glob of images, or sim:")
        ->required();
    sub->add_option("--grid", args->grid, "Regions as columns x rows")->capture_default_str();
    sub->add_option("--roi", args->rois, "Region x,y,w,h in pixels instead of the grid (repeat)")
        ->take_all();
    sub->add_option("--metric", args->metric,
                    "Focus operator: lapv, lapm, teng (default), tenv, brenner, glvn, dctr");
    sub->add_option("--frames", args->frames, "Stop after N frames (default: all)")
        ->check(frameCount());
    sub->add_option("--format", args->format,
                    "jsonl (one object per frame), csv (one row per region) or table (for people)")
        ->capture_default_str();
    sub->add_option("-o,--output", args->output, "Write to FILE instead of stdout");
    sub->add_flag("--no-blur", args->noBlur, "Sharpness only: skip the blur-width measurement");
    CLI::Option* blurSearch =
        sub->add_option("--blur-search", args->blurSearch,
                        "Regions whose edges are searched afresh each frame: all, or N to measure "
                        "the edges found before again and search N regions a frame (video rate); "
                        "auto: for live cameras 16 a frame within 1.5 ms (above 30 frames/s, 480 "
                        "within 45 ms a second), all otherwise")
            ->capture_default_str();
    sub->add_option("--transfer", args->transfer,
                    "How grey levels encode light, for the blur width (measured in linear "
                    "light): linear, srgb (JPEG files, most webcams), rec709 (HD video), or "
                    "auto: the curve the camera's format, the recording or the file names")
        ->capture_default_str();
    sub->add_option("--jobs", args->jobs,
                    "Frames of a file or recording measured at once (output as with 1, in "
                    "order); cameras and --blur-search N run one at a time")
        ->check(CLI::Range(1u, 256u))
        ->default_str("the machine's cores");
    sub->add_flag("--quiet", args->quiet,
                  "No progress line on stderr (it is shown only when stderr is a terminal)");
    sub->add_flag(
        "--centre-weighted", args->centreWeighted,
        "frame_sharpness weights regions near the centre more (Gaussian, σ = diagonal/4)");
    return {sub, [args, blurSearch] {
                args->blurSearchGiven = blurSearch->count() > 0;
                return runAnalyze(*args);
            }};
}

}  // namespace infocus::cli
