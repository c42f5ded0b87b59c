// SPDX-License-Identifier: MIT
// `infocus analyze`: per-region sharpness and blur width of every frame of a source, as JSONL or
// CSV, written frame by frame so that nothing measured is lost when a later frame fails.
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "commands.h"
#include "infocus/analysis.h"
#include "infocus/blur.h"
#include "infocus/metrics.h"
#include "infocus/pipeline.h"
#include "infocus/source.h"
#include "parse.h"

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

std::string csvNumber(const std::optional<double>& v) {
    if (!v) return "";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", *v);
    return buf;
}

void writeCsv(std::ostream& out, const FrameAnalysis& a, bool header) {
    if (header)
        out << "frame,timestamp_ns,lens_value,lens_unit,width,height,col,row,x,y,w,h,sharpness,"
               "edge_width_px,blur_sigma_px,blur_width_px,confidence\n";
    for (const auto& r : a.regions) {
        out << a.frame << ',' << a.timestampNs << ',' << (a.lens ? csvNumber(a.lens->value) : "")
            << ',' << (a.lens ? a.lens->unit : "") << ',' << a.width << ',' << a.height << ','
            << r.col << ',' << r.row << ',' << r.rect.x << ',' << r.rect.y << ',' << r.rect.w << ','
            << r.rect.h << ',' << csvNumber(r.sharpness) << ',' << csvNumber(r.edgeWidthPx) << ','
            << csvNumber(r.blurSigmaPx) << ',' << csvNumber(r.blurWidthPx) << ','
            << csvNumber(r.confidence) << '\n';
    }
}

// A frame as a person reads it: the sharpness grid and the blur-width grid, row by row.
void writeTable(std::ostream& out, const FrameAnalysis& a, bool grid) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "frame %llu  %dx%d  t=%.3f s", (unsigned long long)a.frame,
                  a.width, a.height, a.timestampNs * 1e-9);
    out << buf;
    if (a.lens) {
        std::snprintf(buf, sizeof buf, "  lens %.4g %s", a.lens->value, a.lens->unit.c_str());
        out << buf;
    }
    if (a.noiseSigma) {
        std::snprintf(buf, sizeof buf, "  noise σ %.2f", *a.noiseSigma);
        out << buf;
    }
    std::snprintf(buf, sizeof buf, "  whole frame %s %.4g", a.metric.c_str(), a.frameSharpness);
    out << buf;
    out << "\n";
    if (!grid) {
        for (const auto& r : a.regions) {
            std::snprintf(buf, sizeof buf, "  roi %d (%d,%d %dx%d): %s %.4g", r.col, r.rect.x,
                          r.rect.y, r.rect.w, r.rect.h, a.metric.c_str(), r.sharpness);
            out << buf;
            if (r.blurWidthPx) {
                std::snprintf(buf, sizeof buf, "  blur %.2f px (σ %.2f px, confidence %.2f)",
                              *r.blurWidthPx, r.blurSigmaPx.value_or(0), r.confidence);
                out << buf;
            }
            out << "\n";
        }
        return;
    }
    int cols = 0, rows = 0;
    double peak = 0;
    for (const auto& r : a.regions) {
        cols = std::max(cols, r.col + 1);
        rows = std::max(rows, r.row + 1);
        peak = std::max(peak, r.sharpness);
    }
    out << "  sharpness (" << a.metric << ", % of the sharpest region)";
    for (int c = 0; c < std::max(0, cols * 5 - 38); ++c)
        out << ' ';
    out << "   blur width, px (disc diameter; (w) confidence under " << kLowBlurConfidence
        << "; - no edge)\n";
    for (int row = 0; row < rows; ++row) {
        out << "  ";
        for (int c = 0; c < cols; ++c) {
            const auto& r = a.regions[static_cast<size_t>(row * cols + c)];
            std::snprintf(buf, sizeof buf, "%5.0f", peak > 0 ? 100 * r.sharpness / peak : 0.0);
            out << buf;
        }
        out << "   ";
        for (int c = 0; c < cols; ++c) {
            const auto& r = a.regions[static_cast<size_t>(row * cols + c)];
            if (r.blurWidthPx && r.confidence < kLowBlurConfidence) {
                // In parentheses: a width to take with caution (kLowBlurConfidence).
                char low[32];
                std::snprintf(low, sizeof low, *r.blurWidthPx < 99.95 ? "(%.1f)" : "(%.0f)",
                              *r.blurWidthPx);
                std::snprintf(buf, sizeof buf, "%6s", low);
            } else if (r.blurWidthPx)
                std::snprintf(buf, sizeof buf, "%6.1f", *r.blurWidthPx);
            else
                std::snprintf(buf, sizeof buf, "%6s", "-");
            out << buf;
        }
        out << "\n";
    }
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

    std::ofstream file;
    if (!args.output.empty() && args.output != "-") {
        file.open(args.output, std::ios::out | std::ios::trunc);
        if (!file)
            return reportError(cmd, makeError(ErrorKind::Io, "cannot write '" + args.output +
                                                                 "'; check the folder exists and "
                                                                 "is writable"));
    }
    std::ostream& out = file.is_open() ? static_cast<std::ostream&>(file) : std::cout;
    const std::string where = file.is_open() ? args.output : "standard output";
    uint64_t written = 0, damaged = 0;
    std::streamoff complete = 0;  // bytes of the frames written whole
    bool warnedSharpened = false;
    const Status st = analyzeSource(
        args.source, options, args.frames,
        [&](const FrameAnalysis& a) -> Status {
            warnIfSharpened(cmd, a, warnedSharpened);
            std::ostringstream text;
            if (args.format == "csv")
                writeCsv(text, a, written == 0);
            else if (args.format == "table")
                writeTable(text, a, options.rois.empty());
            else
                text << toJsonLine(a) << '\n';
            const std::string bytes = text.str();
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
            std::cerr << "infocus analyze: skipped a damaged frame: " << e.message << "\n";
        },
        [&](const SourceInfo& info, const AnalysisOptions& used) {
            noteTransfer(cmd, info, used);
        });
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
                        "auto: for live cameras 16 a frame within 1.5 ms, all "
                        "otherwise")
            ->capture_default_str();
    sub->add_option("--transfer", args->transfer,
                    "How grey levels encode light, for the blur width (measured in linear "
                    "light): linear, srgb (JPEG files, most webcams), rec709 (HD video), or "
                    "auto: the curve the camera's format, the recording or the file names")
        ->capture_default_str();
    sub->add_flag(
        "--centre-weighted", args->centreWeighted,
        "frame_sharpness weights regions near the centre more (Gaussian, σ = diagonal/4)");
    return {sub, [args, blurSearch] {
                args->blurSearchGiven = blurSearch->count() > 0;
                return runAnalyze(*args);
            }};
}

}  // namespace infocus::cli
