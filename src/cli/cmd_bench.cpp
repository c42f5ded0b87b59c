// SPDX-License-Identifier: MIT
// `infocus bench`: measured speed of this machine, infocus beside a baseline from the same run.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bench/bench_module.h"
#include "commands.h"
#include "infocus/luma.h"
#include "infocus/source.h"

namespace infocus::cli {

namespace {

struct BenchArgs {
    bool json = false;
    bool accuracy = false;
    double seconds = 0.25;
    double liveSeconds = 20.0;  ///< each live run's length (0: no live rows)
    std::string only;           ///< one family of rows; empty: all
    bool imagesGiven = false;   ///< --images: time the blur engine on this source's frames instead
    std::string images;         ///< the source string given to --images
    uint64_t frames = 32;       ///< at most this many of them (0: all)
};

// Up to @p maxFrames frames of @p source (0: all) as 8-bit luma, copied out of the source's
// buffers. A damaged frame is skipped with a message, as `infocus analyze` does; @p damaged
// counts them.
Result<std::vector<Image<uint8_t>>> readFrames(const std::string& source, uint64_t maxFrames,
                                               uint64_t& damaged) {
    auto src = openSource(source);
    if (!src) return src.error();
    FrameSource& s = **src;
    if (auto st = s.start(); !st) return st.error();
    LumaConverter converter;
    std::vector<Image<uint8_t>> frames;
    Status failed;
    while (maxFrames == 0 || frames.size() < maxFrames) {
        auto frame = s.next();
        Result<Luma8> luma = frame ? converter.toLuma8(*frame) : Result<Luma8>(frame.error());
        if (!luma && luma.error().kind == ErrorKind::Corrupt) {
            ++damaged;
            std::cerr << "infocus bench: skipped a damaged frame: " << luma.error().message << "\n";
            continue;
        }
        if (!luma) {
            if (luma.error().kind != ErrorKind::EndOfStream) failed = luma.error();
            break;
        }
        Image<uint8_t> copy(luma->width, luma->height);
        for (int y = 0; y < luma->height; ++y)
            std::copy_n(luma->row(y), luma->width, copy.row(y));
        frames.push_back(std::move(copy));
    }
    s.stop();
    if (!failed) return failed.error();
    if (frames.empty())
        return makeError(ErrorKind::Corrupt, "source '" + source + "' delivered no frame");
    return frames;
}

// The blur engine's accuracy table: true vs measured width on synthetic edges.
void runAccuracyTable(const bench::BenchModule& module, bool json) {
    const auto& angles = module.accuracyAngles();
    if (!json) {
        std::printf(
            "blur accuracy: synthetic edges, pixel-integrated, 8-bit, contrast 150 grey levels\n");
        std::printf("%-8s %6s %6s", "model", "true", "noise%");
        for (double a : angles)
            std::printf(" %6.1f°", a);
        std::printf(" %7s  %s\n", "worst%", "target");
    }
    int misses = 0;
    module.runAccuracy([&](const bench::AccuracyRow& row) {
        if (row.inTarget && !row.pass) ++misses;
        if (json) {
            nlohmann::ordered_json j;
            j["what"] = "blur_accuracy";
            j["model"] = row.model == "disc d" ? "disc_diameter" : "gaussian_sigma";
            j["true_px"] = row.truePx;
            j["noise_pct"] = row.noisePct;
            nlohmann::ordered_json m = nlohmann::ordered_json::array();
            for (size_t i = 0; i < angles.size(); ++i)
                m.push_back(
                    {{"angle_deg", angles[i]},
                     {"measured_px", row.measuredPx[i] ? nlohmann::ordered_json(*row.measuredPx[i])
                                                       : nlohmann::ordered_json()}});
            j["measured"] = m;
            j["worst_error_pct"] = row.worstErrorPct;
            j["tolerance_pct"] = row.tolerancePct;
            j["in_target"] = row.inTarget;
            j["pass"] = row.pass;
            std::cout << j.dump() << std::endl;
            return;
        }
        std::printf("%-8s %6.2f %6.1f", row.model.c_str(), row.truePx, row.noisePct);
        for (const auto& m : row.measuredPx) {
            if (m)
                std::printf(" %7.3f", *m);
            else
                std::printf(" %7s", "none");
        }
        std::printf(" %7.2f  ", row.worstErrorPct);
        if (row.inTarget)
            std::printf("±%.0f%% %s\n", row.tolerancePct, row.pass ? "ok" : "MISS");
        else
            std::printf("(outside target range)\n");
        std::fflush(stdout);
    });
    if (!json) std::printf("%d row(s) inside the target ranges missed their tolerance\n", misses);
}

// The slanted-square figures over a set of cases: how many read with confidence, and the 95th
// percentile (nearest rank) and worst error of those. The p95 target is the whole table's: a
// subset of 16 cases has its worst case for a 95th percentile.
struct SquareSummary {
    int cases = 0;
    int confident = 0;
    double sharePct = 0.0;
    double p95Pct = 0.0;
    double worstPct = 0.0;
    bool wholeTable = false;
    bool met() const {
        return sharePct >= bench::kSquareConfidentSharePct &&
               (!wholeTable || p95Pct <= bench::kSquareP95Pct) &&
               worstPct <= bench::kSquareWorstPct;
    }
};

SquareSummary summarise(const std::vector<bench::SquareRow>& rows) {
    SquareSummary s;
    std::vector<double> errors;
    for (const bench::SquareRow& r : rows) {
        ++s.cases;
        if (r.measuredPx && r.confidence >= bench::kSquareMinConfidence)
            errors.push_back(r.errorPct);
    }
    s.confident = static_cast<int>(errors.size());
    if (s.cases) s.sharePct = 100.0 * s.confident / s.cases;
    if (errors.empty()) return s;
    std::sort(errors.begin(), errors.end());
    const size_t rank = static_cast<size_t>(std::ceil(0.95 * errors.size()));
    s.p95Pct = errors[std::max<size_t>(rank, 1) - 1];
    s.worstPct = errors.back();
    return s;
}

// The slanted-square table: each random case, then the summary lines the test reads.
void runSquareTable(const bench::BenchModule& module, bool json) {
    if (!json) {
        std::printf(
            "\nblur accuracy: slanted squares, %d random cases (seed %llu), each frame one "
            "region, pixel-integrated, 8-bit\n",
            bench::kSquareCases, static_cast<unsigned long long>(bench::kSquareSeed));
        std::printf("%4s %-8s %6s %6s %6s %9s %6s %7s %-5s %8s %5s %7s\n", "case", "model", "true",
                    "noise%", "contr", "frame", "side", "angle", "sq", "measured", "conf",
                    "error%");
    }
    std::vector<bench::SquareRow> all, nearAxis, wide;
    module.runSquareAccuracy([&](const bench::SquareRow& r) {
        all.push_back(r);
        if (r.nearAxis) nearAxis.push_back(r);
        if (r.wideDisc) wide.push_back(r);
        if (json) {
            nlohmann::ordered_json j;
            j["what"] = "blur_square_accuracy";
            j["case"] = r.index;
            j["model"] = r.model == "disc d" ? "disc_diameter" : "gaussian_sigma";
            j["true_px"] = r.truePx;
            j["noise_pct"] = r.noisePct;
            j["contrast"] = r.contrast;
            j["dark_square"] = r.darkSquare;
            j["width"] = r.width;
            j["height"] = r.height;
            j["side_px"] = r.sidePx;
            j["angle_deg"] = r.angleDeg;
            j["measured_px"] =
                r.measuredPx ? nlohmann::ordered_json(*r.measuredPx) : nlohmann::ordered_json();
            j["confidence"] = r.confidence;
            j["error_pct"] = r.errorPct;
            std::cout << j.dump() << std::endl;
            return;
        }
        char frame[32];
        std::snprintf(frame, sizeof frame, "%dx%d", r.width, r.height);
        char measured[16] = "none";
        if (r.measuredPx) std::snprintf(measured, sizeof measured, "%.3f", *r.measuredPx);
        std::printf("%4d %-8s %6.2f %6.2f %6.1f %9s %6.1f %7.2f %-5s %8s %5.2f %7.2f\n", r.index,
                    r.model.c_str(), r.truePx, r.noisePct, r.contrast, frame, r.sidePx, r.angleDeg,
                    r.darkSquare ? "dark" : "light", measured, r.confidence, r.errorPct);
        std::fflush(stdout);
    });
    const std::pair<const char*, const std::vector<bench::SquareRow>*> sets[] = {
        {"all", &all}, {"near-axis", &nearAxis}, {"wide-disc", &wide}};
    bool met = true;
    for (const auto& [name, rows] : sets) {
        SquareSummary s = summarise(*rows);
        s.wholeTable = rows == &all;
        met = met && s.met();
        if (json) {
            nlohmann::ordered_json j;
            j["what"] = "blur_square_summary";
            j["cases"] = name;
            j["count"] = s.cases;
            j["confident"] = s.confident;
            j["confident_pct"] = s.sharePct;
            j["p95_error_pct"] = s.p95Pct;
            j["worst_error_pct"] = s.worstPct;
            j["met"] = s.met();
            std::cout << j.dump() << std::endl;
            continue;
        }
        std::printf(
            "squares %-9s %3d cases, confidence >= %.2f: %3d (%5.1f %%), error p95 %5.2f %%, "
            "worst %6.2f %% %s\n",
            name, s.cases, bench::kSquareMinConfidence, s.confident, s.sharePct, s.p95Pct,
            s.worstPct, s.met() ? "ok" : "MISS");
    }
    if (!json)
        std::printf(
            "squares: targets (>= %.0f %% confident, p95 <= %.0f %% over all, worst <= %.0f "
            "%%) %s\n",
            bench::kSquareConfidentSharePct, bench::kSquareP95Pct, bench::kSquareWorstPct,
            met ? "met" : "missed");
    // MTF50 of the same squares against their analytic SFR: the 95th percentile (nearest rank)
    // of the errors of all cases, a case without MTF50 counted as 100 %.
    std::vector<double> errors;
    for (const bench::SquareRow& r : all)
        errors.push_back(r.mtfErrorPct);
    std::sort(errors.begin(), errors.end());
    const size_t rank = static_cast<size_t>(std::ceil(0.95 * errors.size()));
    const double p95 = errors.empty() ? 100.0 : errors[std::max<size_t>(rank, 1) - 1];
    const double worst = errors.empty() ? 100.0 : errors.back();
    const bool mtfMet = p95 <= bench::kMtfSquareP95Pct;
    if (json) {
        nlohmann::ordered_json j;
        j["what"] = "mtf50_square_summary";
        j["count"] = errors.size();
        j["p95_error_pct"] = p95;
        j["worst_error_pct"] = worst;
        j["met"] = mtfMet;
        std::cout << j.dump() << std::endl;
    } else {
        std::printf(
            "squares MTF50 %3zu cases, error p95 %5.2f %%, worst %6.2f %% (target p95 <= "
            "%.0f %%) %s\n",
            errors.size(), p95, worst, bench::kMtfSquareP95Pct, mtfMet ? "met" : "MISS");
    }
}

// The MTF50 accuracy table: measured against analytic MTF50 on synthetic edges.
void runMtfTable(const bench::BenchModule& module, bool json) {
    const auto& angles = module.mtfAccuracyAngles();
    if (!json) {
        std::printf(
            "\nMTF50 accuracy: synthetic edges, pixel-integrated, 8-bit, contrast 150 "
            "grey levels; true MTF50 (cy/px) of PSF x pixel, then error %% per angle\n");
        std::printf("%-8s %6s %6s %7s", "model", "true", "noise%", "MTF50");
        for (double a : angles)
            std::printf(" %6.1f°", a);
        std::printf(" %7s  %s\n", "worst%", "target");
    }
    int misses = 0;
    module.runMtfAccuracy([&](const bench::MtfRow& row) {
        if (!row.pass) ++misses;
        if (json) {
            nlohmann::ordered_json j;
            j["what"] = "mtf50_accuracy";
            j["model"] = row.model == "disc d" ? "disc_diameter" : "gaussian_sigma";
            j["true_px"] = row.truePx;
            j["noise_pct"] = row.noisePct;
            nlohmann::ordered_json m = nlohmann::ordered_json::array();
            for (size_t i = 0; i < angles.size(); ++i)
                m.push_back({{"angle_deg", angles[i]},
                             {"true_cy_px", row.trueMtf50[i]},
                             {"measured_cy_px", row.measuredMtf50[i]
                                                    ? nlohmann::ordered_json(*row.measuredMtf50[i])
                                                    : nlohmann::ordered_json()}});
            j["measured"] = m;
            j["worst_error_pct"] = row.worstErrorPct;
            j["tolerance_pct"] = row.tolerancePct;
            j["pass"] = row.pass;
            std::cout << j.dump() << std::endl;
            return;
        }
        // The true MTF50 at the table's middle angle; each angle's own truth sets its error.
        std::printf("%-8s %6.2f %6.1f %7.4f", row.model.c_str(), row.truePx, row.noisePct,
                    row.trueMtf50[angles.size() / 2]);
        for (size_t i = 0; i < angles.size(); ++i) {
            if (row.measuredMtf50[i])
                std::printf(" %+7.2f",
                            100.0 * (*row.measuredMtf50[i] - row.trueMtf50[i]) / row.trueMtf50[i]);
            else
                std::printf(" %7s", "none");
        }
        std::printf(" %7.2f  ±%.0f%% %s\n", row.worstErrorPct, row.tolerancePct,
                    row.pass ? "ok" : "MISS");
        std::fflush(stdout);
    });
    if (!json) std::printf("%d MTF50 row(s) missed their tolerance\n", misses);
}

// A live row's targets: no frame dropped; at 1080p also the latency within one frame interval
// and at most one of two cores. Each as its text and whether the run met it.
std::vector<std::pair<std::string, bool>> liveTargets(const bench::BenchRow& row) {
    const bench::LiveRun& r = *row.live;
    std::vector<std::pair<std::string, bool>> t{{"0 dropped", r.dropped == 0}};
    if (row.height <= 1080 && row.nominalFps) {
        const double intervalMs = 1000.0 / *row.nominalFps;
        char text[48];
        std::snprintf(text, sizeof text, "p99 <= %.1f ms", intervalMs);
        t.emplace_back(text, r.latencyP99Ms <= intervalMs);
        t.emplace_back("<= 1 core", r.cpuCores <= 1.0);
    }
    return t;
}

nlohmann::ordered_json liveJson(const bench::BenchRow& row) {
    nlohmann::ordered_json j;
    j["what"] = row.what;
    j["width"] = row.width;
    j["height"] = row.height;
    j["format"] = row.format;
    if (row.nominalFps) j["nominal_fps"] = *row.nominalFps;
    const auto put = [&](const std::string& prefix, const std::optional<bench::LiveRun>& r) {
        if (!r) return;
        j[prefix + "fps"] = r->fps;
        j[prefix + "frames"] = r->frames;
        j[prefix + "dropped"] = r->dropped;
        j[prefix + "latency_p50_ms"] = r->latencyP50Ms;
        j[prefix + "latency_p99_ms"] = r->latencyP99Ms;
        j[prefix + "cpu_cores"] = r->cpuCores;
    };
    put("", row.live);
    if (row.liveBaseline) j["baseline"] = row.baseline;
    put("baseline_", row.liveBaseline);
    if (row.live) {
        nlohmann::ordered_json targets = nlohmann::ordered_json::array();
        for (const auto& [text, met] : liveTargets(row))
            targets.push_back({{"target", text}, {"met", met}});
        j["targets"] = targets;
    }
    if (!row.note.empty()) j["note"] = row.note;
    return j;
}

// A live row as text: infocus's run and the baseline's, side by side, then the targets.
void printLive(const bench::BenchRow& row, bool& headerShown) {
    if (!headerShown) {
        headerShown = true;
        std::printf("\nlive: a recording replayed at its own pace through the live pipeline (%s)\n",
                    row.note.c_str());
        std::printf("%-17s %11s %-6s %5s  %-8s %7s %7s %7s %7s %7s %6s  %s\n", "what", "size",
                    "format", "fps", "who", "fps", "frames", "dropped", "p50 ms", "p99 ms", "cores",
                    "targets");
    }
    char size[32];
    std::snprintf(size, sizeof size, "%dx%d", row.width, row.height);
    const auto line = [](const char* who, const bench::LiveRun& r) {
        std::printf("%-8s %7.2f %7llu %7llu %7.2f %7.2f %6.2f", who, r.fps,
                    static_cast<unsigned long long>(r.frames),
                    static_cast<unsigned long long>(r.dropped), r.latencyP50Ms, r.latencyP99Ms,
                    r.cpuCores);
    };
    std::printf("%-17s %11s %-6s %5.0f  ", row.what.c_str(), size, row.format.c_str(),
                row.nominalFps.value_or(0.0));
    if (!row.live) {
        std::printf("%s\n", row.note.c_str());
        return;
    }
    line("infocus", *row.live);
    std::printf(" ");
    const auto targets = liveTargets(row);
    for (size_t i = 0; i < targets.size(); ++i)
        std::printf("%s %s %s", i ? "," : "", targets[i].first.c_str(),
                    targets[i].second ? "ok" : "missed");
    std::printf("\n");
    if (row.liveBaseline) {
        std::printf("%-17s %11s %-6s %5s  ", "", "", "", "");
        line("baseline", *row.liveBaseline);
        std::printf("  %s\n", row.baseline.c_str());
    }
    std::fflush(stdout);
}

// Most process CPU the focusmeter element may add to a pipeline at 1080p60, in cores.
constexpr double kGstreamerAddedCores = 0.15;

// A gstreamer row's targets: the element adds at most kGstreamerAddedCores, and no buffer is
// later at the sink than through identity.
std::vector<std::pair<std::string, bool>> gstreamerTargets(const bench::BenchRow& row) {
    const bench::LiveRun& m = *row.live;
    const bench::LiveRun& b = *row.liveBaseline;
    char text[48];
    std::snprintf(text, sizeof text, "<= %.2f core added", kGstreamerAddedCores);
    return {{text, m.cpuCores - b.cpuCores <= kGstreamerAddedCores},
            {"no more late than identity", m.dropped <= b.dropped}};
}

// The autofocus row as JSON: frames and errors of infocus and of the contrast baseline.
nlohmann::ordered_json autofocusJson(const bench::BenchRow& row) {
    const bench::AutofocusRun& a = *row.autofocus;
    nlohmann::ordered_json j;
    j["what"] = row.what;
    j["width"] = row.width;
    j["height"] = row.height;
    j["frames_median"] = a.framesMedian;
    j["frames_worst"] = a.framesWorst;
    j["error_dpt_worst"] = a.errorDptWorst;
    j["in_focus"] = a.inFocus;
    j["runs"] = a.runs;
    j["baseline"] = row.baseline;
    j["baseline_frames_median"] = a.baselineFramesMedian;
    j["baseline_frames_worst"] = a.baselineFramesWorst;
    j["baseline_error_dpt_worst"] = a.baselineErrorDptWorst;
    j["baseline_in_focus"] = a.baselineInFocus;
    j["note"] = row.note;
    return j;
}

// The autofocus row as text: frames to focus beside the baseline's.
void printAutofocus(const bench::BenchRow& row) {
    const bench::AutofocusRun& a = *row.autofocus;
    std::printf("\nautofocus: frames from the command to focus (%s)\n", row.note.c_str());
    std::printf("  %-34s %7s %6s %16s %9s\n", "", "median", "worst", "worst error dpt", "in focus");
    std::printf("  %-34s %7.1f %6.0f %16.3f %5d/%d\n", "infocus (blur width)", a.framesMedian,
                a.framesWorst, a.errorDptWorst, a.inFocus, a.runs);
    std::printf("  %-34s %7.1f %6.0f %16.3f %5d/%d\n", row.baseline.c_str(), a.baselineFramesMedian,
                a.baselineFramesWorst, a.baselineErrorDptWorst, a.baselineInFocus, a.runs);
    std::fflush(stdout);
}

nlohmann::ordered_json gstreamerJson(const bench::BenchRow& row) {
    nlohmann::ordered_json j;
    j["what"] = row.what;
    j["width"] = row.width;
    j["height"] = row.height;
    j["format"] = row.format;
    if (row.nominalFps) j["nominal_fps"] = *row.nominalFps;
    if (row.intervalNs) j["interval_ns"] = *row.intervalNs;
    if (row.live && row.liveBaseline) {
        j["frames_analysed"] = row.live->frames;
        j["analysed_fps"] = row.live->fps;
        j["late"] = row.live->dropped;
        j["cpu_cores"] = row.live->cpuCores;
        j["baseline"] = row.baseline;
        j["baseline_frames"] = row.liveBaseline->frames;
        j["baseline_late"] = row.liveBaseline->dropped;
        j["baseline_cpu_cores"] = row.liveBaseline->cpuCores;
        j["added_cores"] = row.live->cpuCores - row.liveBaseline->cpuCores;
        nlohmann::ordered_json targets = nlohmann::ordered_json::array();
        for (const auto& [text, met] : gstreamerTargets(row))
            targets.push_back({{"target", text}, {"met", met}});
        j["targets"] = targets;
    }
    if (!row.note.empty()) j["note"] = row.note;
    return j;
}

// A gstreamer row as text: focusmeter's run and identity's, then the targets.
void printGstreamer(const bench::BenchRow& row, bool& headerShown) {
    if (!headerShown) {
        headerShown = true;
        std::printf(
            "\ngstreamer: a live videotestsrc at its rate through focusmeter, beside "
            "identity\n");
        std::printf("%-17s %11s %-6s %5s  %-10s %8s %7s %7s %5s %6s %6s  %s\n", "what", "size",
                    "format", "fps", "element", "interval", "frames", "fps", "late", "cores",
                    "added", "targets");
    }
    char size[32];
    std::snprintf(size, sizeof size, "%dx%d", row.width, row.height);
    std::printf("%-17s %11s %-6s %5.0f  ", row.what.c_str(), size, row.format.c_str(),
                row.nominalFps.value_or(0.0));
    if (!row.live || !row.liveBaseline) {
        std::printf("%s\n", row.note.c_str());
        return;
    }
    const bench::LiveRun& m = *row.live;
    const bench::LiveRun& b = *row.liveBaseline;
    std::printf("%-10s %6.0fms %7llu %7.2f %5llu %6.2f %6.2f ", "focusmeter",
                static_cast<double>(row.intervalNs.value_or(0)) / 1e6,
                static_cast<unsigned long long>(m.frames), m.fps,
                static_cast<unsigned long long>(m.dropped), m.cpuCores, m.cpuCores - b.cpuCores);
    const auto targets = gstreamerTargets(row);
    for (size_t i = 0; i < targets.size(); ++i)
        std::printf("%s %s %s", i ? "," : "", targets[i].first.c_str(),
                    targets[i].second ? "ok" : "missed");
    std::printf("\n%-17s %11s %-6s %5s  %-10s %8s %7llu %7.2f %5llu %6.2f %6s  (%s)\n", "", "", "",
                "", "identity", "", static_cast<unsigned long long>(b.frames), b.fps,
                static_cast<unsigned long long>(b.dropped), b.cpuCores, "", row.note.c_str());
    std::fflush(stdout);
}

int runBench(const BenchArgs& args) {
    if (args.accuracy && args.imagesGiven)
        return usageError("bench", "--accuracy and --images each choose what to run; give one");
    if (!args.only.empty() && args.imagesGiven)
        return usageError("bench", "--only and --images each choose what to run; give one");
    // The rows live in a module of their own, which brings OpenCV: loaded before any frame is read.
    auto module = bench::loadBench("measuring this machine's speed");
    if (!module) return reportError("bench", module.error());
    if (args.accuracy) {
        runAccuracyTable(**module, args.json);
        runSquareTable(**module, args.json);
        runMtfTable(**module, args.json);
        return 0;
    }
    bench::BenchOptions options;
    options.secondsPerCase = args.seconds;
    options.liveSeconds = args.liveSeconds;
    options.only = args.only;
    std::vector<Image<uint8_t>> frames;
    uint64_t damaged = 0;
    if (args.imagesGiven) {
        auto read = readFrames(args.images, args.frames, damaged);
        if (!read) return reportError("bench", read.error());
        frames = std::move(*read);
    }
    if (!args.json && args.only != "live" && args.only != "gstreamer" && args.only != "autofocus")
        std::printf("%-17s %11s %12s %12s %9s  %s\n", "what", "size", "infocus ms", "baseline ms",
                    "speedup", "baseline");
    bool liveHeader = false;
    bool gstreamerHeader = false;
    const auto print = [&](const bench::BenchRow& row) {
        if (row.what == "gstreamer") {
            if (args.json)
                std::cout << gstreamerJson(row).dump() << std::endl;
            else
                printGstreamer(row, gstreamerHeader);
            return;
        }
        if (row.autofocus) {
            if (args.json)
                std::cout << autofocusJson(row).dump() << std::endl;
            else
                printAutofocus(row);
            return;
        }
        if (row.what == "live") {
            if (args.json)
                std::cout << liveJson(row).dump() << std::endl;
            else
                printLive(row, liveHeader);
            return;
        }
        if (args.json) {
            nlohmann::ordered_json j;
            j["what"] = row.what;
            j["width"] = row.width;
            j["height"] = row.height;
            j["ms"] = row.ms;
            if (row.baselineMs) {
                j["baseline_ms"] = *row.baselineMs;
                j["speedup"] = *row.baselineMs / row.ms;
                j["baseline"] = row.baseline;
            }
            if (!row.focusOperator.empty()) j["operator"] = row.focusOperator;
            if (row.frameBlurPx) j["frame_blur_width_px"] = *row.frameBlurPx;
            if (row.regionsWithEdge) j["regions_with_edge"] = *row.regionsWithEdge;
            if (!row.input.empty()) j["input"] = row.input;
            if (row.inputFrame) j["input_frame"] = *row.inputFrame;
            if (!row.note.empty()) j["note"] = row.note;
            std::cout << j.dump() << std::endl;
            return;
        }
        char size[32];
        std::snprintf(size, sizeof size, "%dx%d", row.width, row.height);
        if (row.baselineMs)
            std::printf("%-17s %11s %12.3f %12.3f %8.1fx  %s", row.what.c_str(), size, row.ms,
                        *row.baselineMs, *row.baselineMs / row.ms, row.baseline.c_str());
        else
            std::printf("%-17s %11s %12.3f %12s %9s  -", row.what.c_str(), size, row.ms, "-", "-");
        if (row.inputFrame)
            std::printf(" (frame %d of %s; %s)", *row.inputFrame, row.input.c_str(),
                        row.note.c_str());
        else if (!row.input.empty())
            std::printf(" (%s; %s)", row.input.c_str(), row.note.c_str());
        else if (!row.note.empty())
            std::printf(" (%s)", row.note.c_str());
        std::printf("\n");
        std::fflush(stdout);
    };
    if (frames.empty()) {
        (*module)->runAll(options, print);
        return 0;
    }
    (*module)->benchBlurImages(options, args.images, frames, print);
    if (damaged) {
        std::cerr << "infocus bench: " << damaged << " damaged frame(s) skipped, " << frames.size()
                  << " timed\n";
        return kExitFailure;
    }
    return 0;
}

}  // namespace

Command addBenchCommand(CLI::App& app) {
    auto args = std::make_shared<BenchArgs>();
    CLI::App* sub = app.add_subcommand(
        "bench", "Measure this machine's speed: infocus beside a baseline timed in the same run");
    sub->add_flag("--json", args->json, "One JSON object per line instead of a table");
    sub->add_flag(
        "--accuracy", args->accuracy,
        "Print the blur engine's accuracy on synthetic edges and slanted squares of known blur "
        "instead");
    sub->add_option("--seconds", args->seconds, "Time budget per measured case")
        ->check(secondsIn(0.0, 10.0, "0.5"))
        ->capture_default_str();
    sub->add_option("--live-seconds", args->liveSeconds,
                    "Length of each live pipeline run (0: leave the live rows out)")
        ->check(CLI::Range(0.0, 3600.0).description("S"))
        ->capture_default_str();
    sub->add_option("--only", args->only, "Run only this family of rows")
        ->check(CLI::IsMember(bench::benchFamilies()))
        ->type_name("FAMILY");
    CLI::Option* images =
        sub->add_option(
               "--images", args->images,
               "Time the blur engine on the frames of SOURCE (images, a directory or glob of "
               "them, a recording, a camera), each scaled to 1920x1080, instead")
            ->type_name("SOURCE");
    sub->add_option("--frames", args->frames, "At most N frames of --images (0: all)")
        ->check(frameCount())
        ->capture_default_str()
        ->needs(images);
    return {sub, [args, images] {
                args->imagesGiven = images->count() > 0;
                return runBench(*args);
            }};
}

}  // namespace infocus::cli
