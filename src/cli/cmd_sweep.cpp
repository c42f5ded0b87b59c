// SPDX-License-Identifier: MIT
// `infocus sweep`: moves a motorised lens through its range, measures every position, and
// leaves the lens where the frame is sharpest (include/infocus/sweep.h).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "infocus/output.h"
#include "infocus/sweep.h"
#include "lens_options.h"
#include "parse.h"

namespace infocus::cli {

namespace {

constexpr const char* kName = "sweep";

struct SweepArgs {
    std::string source;
    std::string from, to;
    int steps = 15;
    int refine = 9;
    std::optional<int> settle;
    std::string grid = "8x6";
    std::string metric;
    std::string output;
    bool noBlur = false;
    bool noMove = false;
    bool json = false;
};

using Json = nlohmann::ordered_json;

// A position given on the command line, in the control's unit. A dioptre control takes a
// distance or dioptres with their unit ("1.2m", "0.8dpt", "inf"), as --focus does; a control in
// the driver's own steps takes a plain number.
Result<double> parsePosition(const std::string& text, const std::string& option,
                             const FocusRange& range, const std::string& source) {
    if (range.unit == "dioptre") {
        auto m = parseFocus(text, option);
        if (!m) return m.error();
        return std::isinf(*m) ? 0.0 : 1.0 / *m;
    }
    double v = 0;
    if (!readsWhole(text, v) || !std::isfinite(v)) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%g to %g", range.min, range.max);
        return makeError(ErrorKind::Usage, option + " " + text + ": the lens control of " + source +
                                               " counts in its driver's own steps (unit " +
                                               range.unit + ", range " + buf +
                                               "), not in distances; give a number in that range");
    }
    return v;
}

// "1.002 dpt", or a number in the driver's unit.
std::string positionText(double v, const std::string& unit) {
    char buf[48];
    if (unit == "dioptre")
        std::snprintf(buf, sizeof buf, "%.3f dpt", v);
    else
        std::snprintf(buf, sizeof buf, "%g %s", v, unit.c_str());
    return buf;
}

// The distance in focus at @p dioptres, for people ("infinity" at 0).
std::string inFocusText(double dioptres) {
    return formatDistance(dioptres > 0 ? 1.0 / dioptres : HUGE_VAL);
}

// JSON of a distance in focus: metres, null for infinity (as dof --json writes far_m).
Json inFocusJson(std::optional<double> dioptres) {
    if (!dioptres) return nullptr;
    return *dioptres > 0 ? Json(1.0 / *dioptres) : Json(nullptr);
}

// The upper median of @p v (not empty).
double median(std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
}

// Median blur width (disc diameter) over the regions that have one, and how many do.
std::pair<std::optional<double>, int> medianBlur(const FrameAnalysis& a) {
    std::vector<double> w;
    for (const RegionResult& r : a.regions)
        if (r.blurWidthPx) w.push_back(*r.blurWidthPx);
    if (w.empty()) return {std::nullopt, 0};
    return {median(w), static_cast<int>(w.size())};
}

std::optional<double> dioptresOf(double position, const std::string& unit) {
    if (unit == "dioptre") return position;
    return std::nullopt;
}

Json peakJson(const std::optional<FocusPeak>& p, const std::string& unit) {
    if (!p) return nullptr;
    Json j;
    j["position"] = p->position;
    j["unit"] = unit;
    const auto d = dioptresOf(p->position, unit);
    j["dioptres"] = d ? Json(*d) : Json(nullptr);
    j["in_focus_distance_m"] = inFocusJson(d);
    j["sharpness"] = p->score;
    j["at_end"] = p->atEnd;
    j["prominence"] = p->prominence;
    return j;
}

Json summaryJson(const std::string& source, const SweepResult& r, int settle) {
    const std::string& unit = r.range.unit;
    Json j;
    j["source"] = source;
    j["unit"] = unit;
    j["range"] = {{"min", r.range.min}, {"max", r.range.max}, {"step", r.range.step}};
    j["settle_frames"] = settle;
    Json steps = Json::array();
    for (const SweepStep& s : r.steps) {
        const auto [blur, withBlur] = medianBlur(s.analysis);
        steps.push_back({{"pass", s.pass},
                         {"commanded", s.commanded},
                         {"lens_position",
                          {{"value", s.lens.value},
                           {"unit", s.lens.unit},
                           {"dioptres", s.lens.dioptres ? Json(*s.lens.dioptres) : Json(nullptr)}}},
                         {"frame", s.analysis.frame},
                         {"frame_sharpness", s.analysis.frameSharpness},
                         {"median_blur_width_px", blur ? Json(*blur) : Json(nullptr)},
                         {"regions_with_blur", withBlur}});
    }
    j["steps"] = steps;
    j["best"] = peakJson(r.best, unit);
    Json regions = Json::array();
    const FrameAnalysis* first = r.steps.empty() ? nullptr : &r.steps.front().analysis;
    for (size_t i = 0; first && i < r.regionBest.size() && i < first->regions.size(); ++i) {
        const RegionResult& reg = first->regions[i];
        Json e = {{"col", reg.col},  {"row", reg.row},  {"x", reg.rect.x},
                  {"y", reg.rect.y}, {"w", reg.rect.w}, {"h", reg.rect.h}};
        e["best"] = peakJson(r.regionBest[i], unit);
        const std::optional<BlurVFit> fit =
            i < r.regionBlurFit.size() ? r.regionBlurFit[i] : std::nullopt;
        if (fit) {
            const auto d = dioptresOf(fit->position, unit);
            e["blur_fit"] = {{"position", fit->position},
                             {"dioptres", d ? Json(*d) : Json(nullptr)},
                             {"in_focus_distance_m", inFocusJson(d)},
                             {"slope_px_per_unit", fit->slopePxPerUnit},
                             {"rms_px", fit->rmsPx},
                             {"points", fit->points}};
        } else {
            e["blur_fit"] = nullptr;
        }
        regions.push_back(e);
    }
    j["metric"] = first ? first->metric : std::string();
    j["regions"] = regions;
    if (r.finalPosition)
        j["lens_left_at"] = {{"value", r.finalPosition->value}, {"unit", r.finalPosition->unit}};
    else
        j["lens_left_at"] = nullptr;
    return j;
}

// One line per row of regions, each cell from @p cell (empty: "-").
void printRegionGrid(const SweepResult& r, const std::function<std::string(size_t region)>& cell) {
    if (r.steps.empty()) return;
    const FrameAnalysis& a = r.steps.front().analysis;
    int cols = 0, rows = 0;
    for (const RegionResult& reg : a.regions)
        cols = std::max(cols, reg.col + 1), rows = std::max(rows, reg.row + 1);
    std::vector<std::string> cells(static_cast<size_t>(cols) * rows, "-");
    for (size_t i = 0; i < a.regions.size(); ++i)
        if (std::string c = cell(i); !c.empty())
            cells[static_cast<size_t>(a.regions[i].row) * cols + a.regions[i].col] = std::move(c);
    for (int row = 0; row < rows; ++row) {
        for (int col = 0; col < cols; ++col)
            std::printf("%12s", cells[static_cast<size_t>(row) * cols + col].c_str());
        std::printf("\n");
    }
}

// A position for a grid cell: the distance in focus for a dioptre control.
std::string cellText(double position, const std::string& unit) {
    return unit == "dioptre" ? inFocusText(position) : positionText(position, unit);
}

int runSweepCommand(const SweepArgs& args) {
    const std::string cmd = kName;
    SweepOptions options;
    const auto grid = parseGrid(args.grid);
    if (!grid) return usageError(cmd, gridUsage(args.grid));
    options.analysis.cols = grid->first;
    options.analysis.rows = grid->second;
    options.analysis.metric = args.metric;
    options.analysis.measureBlur = !args.noBlur;
    options.steps = args.steps;
    options.refineSteps = args.refine;
    options.settleFrames = args.settle;
    options.moveToBest = !args.noMove;
    // Options are checked before the source opens: a mistyped operator must not move a lens.
    if (auto a = Analyzer::create(options.analysis); !a) return reportError(cmd, a.error());

    namespace fs = std::filesystem;
    std::ofstream jsonl;
    fs::path dir;
    if (!args.output.empty()) {
        dir = args.output;
        std::error_code ec;
        if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
            return usageError(
                cmd, "-o " + args.output + " is a file; give a directory for the sweep's files");
        for (const char* f : {"sweep.jsonl", "summary.json"})
            if (fs::exists(dir / f, ec))
                return usageError(cmd, "-o " + args.output + " already holds a sweep (" + f +
                                           "); give a new or empty directory");
        fs::create_directories(dir, ec);
        jsonl.open(dir / "sweep.jsonl", std::ios::out | std::ios::trunc);
        if (ec || !jsonl)
            return reportError(
                cmd, makeError(ErrorKind::Io, "cannot write in '" + args.output +
                                                  "'; check that it can be created and written"));
    }

    auto source = openSource(args.source);
    if (!source) return reportError(cmd, source.error());
    FrameSource& src = **source;
    FocusControl* control = src.focusControl();
    if (!control) return reportError(cmd, noFocusControlError(args.source));
    const FocusRange range = control->range();
    for (auto [text, slot] : {std::pair{&args.from, &options.from}, {&args.to, &options.to}}) {
        if (text->empty()) continue;
        auto v =
            parsePosition(*text, slot == &options.from ? "--from" : "--to", range, args.source);
        if (!v) return reportError(cmd, v.error());
        *slot = *v;
    }
    const int settle = args.settle.value_or(control->settleFrames());
    // Said with the first position measured, once the sweep's options have been accepted.
    const auto printHeader = [&] {
        std::printf("sweep of %s: lens %s to %s, %d positions", args.source.c_str(),
                    positionText(options.from.value_or(range.min), range.unit).c_str(),
                    positionText(options.to.value_or(range.max), range.unit).c_str(), args.steps);
        if (args.refine) std::printf(", then %d about the sharpest", args.refine);
        std::printf("; %d frame(s) discarded after each move\n", settle);
        std::printf("%5s %14s %12s %16s %22s\n", "pass", "lens", "in focus at", "frame sharpness",
                    "blur px (median, n)");
    };
    if (auto s = src.start(); !s) return reportError(cmd, s.error());
    size_t written = 0;
    auto result = runSweep(src, options, [&](const SweepStep& s) -> Status {
        if (jsonl.is_open()) {
            jsonl << toJsonLine(s.analysis) << '\n';
            jsonl.flush();  // a position measured is a position kept
            if (!jsonl)
                return makeError(ErrorKind::Io, "writing " + (dir / "sweep.jsonl").string() +
                                                    " failed after " + std::to_string(written) +
                                                    " position(s); free disk space or write "
                                                    "elsewhere (-o DIR)");
        }
        if (args.json) {
            ++written;
            return {};
        }
        if (written++ == 0) printHeader();
        const auto [blur, n] = medianBlur(s.analysis);
        const auto d = s.lens.dioptres;
        char blurText[32] = "-";
        if (blur) std::snprintf(blurText, sizeof blurText, "%.2f (%d)", *blur, n);
        std::printf("%5d %14s %12s %16.6g %22s\n", s.pass + 1,
                    positionText(s.lens.value, s.lens.unit).c_str(),
                    d ? inFocusText(*d).c_str() : "-", s.analysis.frameSharpness, blurText);
        std::fflush(stdout);
        return {};
    });
    src.stop();
    if (!result) {
        if (written)
            std::cerr << "infocus sweep: " << written << " position(s) measured before the error"
                      << (jsonl.is_open() ? " are in " + (dir / "sweep.jsonl").string() : "")
                      << "\n";
        return reportError(cmd, result.error());
    }
    const Json summary = summaryJson(args.source, *result, settle);
    if (jsonl.is_open()) {
        std::ofstream f(dir / "summary.json", std::ios::out | std::ios::trunc);
        f << summary.dump(2) << '\n';
        f.flush();
        if (!f)
            return reportError(
                cmd, makeError(ErrorKind::Io, "writing " + (dir / "summary.json").string() +
                                                  " failed; the measurements are in sweep.jsonl"));
    }
    if (args.json) {
        std::cout << summary.dump() << '\n';
        std::cout.flush();
        return std::cout ? 0
                         : reportError(
                               cmd, makeError(ErrorKind::Io, "writing to standard output failed"));
    }
    if (!result->best) {
        std::fprintf(stderr,
                     "infocus sweep: no position scored above zero: nothing in the frame "
                     "to focus on (a blank scene, a capped lens, or the lens does not "
                     "move); the lens was left where it was\n");
        return kExitFailure;
    }
    const FocusPeak& best = *result->best;
    std::printf("best focus: %s", positionText(best.position, range.unit).c_str());
    if (const auto d = dioptresOf(best.position, range.unit))
        std::printf(" (in focus at %s from the lens)", inFocusText(*d).c_str());
    std::printf(
        ", frame sharpness %.6g, %.0f %% above the sweep's lowest; %s\n", best.score,
        100.0 * best.prominence,
        options.moveToBest ? "the lens is left there" : "the lens stays at the last position");
    const std::string& unit = range.unit;
    std::printf("sharpest position of each region (%s; * at the sweep's end):\n",
                unit == "dioptre" ? "distance in focus" : unit.c_str());
    printRegionGrid(*result, [&](size_t i) -> std::string {
        if (i >= result->regionBest.size() || !result->regionBest[i]) return {};
        const FocusPeak& p = *result->regionBest[i];
        return cellText(p.position, unit) + (p.atEnd ? "*" : "");
    });
    std::vector<double> slopes, rms;
    for (const auto& f : result->regionBlurFit)
        if (f) slopes.push_back(f->slopePxPerUnit), rms.push_back(f->rmsPx);
    if (!slopes.empty()) {
        std::printf(
            "where each region's blur width vanishes (a V fitted to its blur widths, "
            "%s):\n",
            unit == "dioptre" ? "distance in focus" : unit.c_str());
        printRegionGrid(*result, [&](size_t i) -> std::string {
            if (i >= result->regionBlurFit.size() || !result->regionBlurFit[i]) return {};
            return cellText(result->regionBlurFit[i]->position, unit);
        });
        std::printf(
            "blur widths grow %.3g px per %s of defocus (median of %zu regions; RMS of "
            "the fits %.2g px)\n",
            median(slopes), unit == "dioptre" ? "dioptre" : unit.c_str(), slopes.size(),
            median(rms));
    }
    std::fflush(stdout);
    if (best.atEnd)
        std::fprintf(stderr,
                     "infocus sweep: the sharpest position is the sweep's %s one: the best focus "
                     "may lie beyond it; sweep a wider range (--from, --to)\n",
                     best.index == 0 ? "first" : "last");
    if (best.prominence < 0.1)
        std::fprintf(stderr,
                     "infocus sweep: the frame's sharpness changes by only %.0f %% over the sweep: "
                     "the scene may lack texture, or the lens may not move; check the best focus "
                     "by eye\n",
                     100.0 * best.prominence);
    return std::cout
               ? 0
               : reportError(cmd, makeError(ErrorKind::Io, "writing to standard output failed"));
}

}  // namespace

Command addSweepCommand(CLI::App& app) {
    auto args = std::make_shared<SweepArgs>();
    CLI::App* sub = app.add_subcommand(
        "sweep", "Focus sweep: move the lens through its range and leave it at best focus");
    sub->add_option("SOURCE", args->source, "A camera with a focus motor, or sim:")->required();
    sub->add_option("--from", args->from,
                    "First position: a distance or dioptres for a dioptre lens (1.2m, 0.8dpt, "
                    "inf), a number in the driver's steps otherwise (default: the range's start)");
    sub->add_option("--to", args->to, "Last position, as --from (default: the range's end)");
    sub->add_option("--steps", args->steps, "Positions of the first pass, evenly spaced")
        ->check(CLI::Range(2, 1000))
        ->capture_default_str();
    sub->add_option("--refine", args->refine,
                    "Positions of a second pass between the neighbours of the sharpest (0: none)")
        ->check(CLI::Range(0, 1000))
        ->capture_default_str();
    sub->add_option("--settle", args->settle,
                    "Frames discarded after each move (default: the camera's own)")
        ->check(CLI::Range(0, 1000));
    sub->add_option("--grid", args->grid, "Regions as columns x rows")->capture_default_str();
    sub->add_option("--metric", args->metric,
                    "Focus operator: lapv, lapm, teng (default), tenv, brenner, glvn, dctr");
    sub->add_option("-o,--output", args->output,
                    "Directory for sweep.jsonl (each frame measured, as analyze writes it) and "
                    "summary.json");
    sub->add_flag("--no-blur", args->noBlur, "Sharpness only: skip the blur-width measurement");
    sub->add_flag("--no-move", args->noMove, "Leave the lens at the last position measured");
    sub->add_flag("--json", args->json, "Print the summary as one JSON object instead of a table");
    sub->footer(
        "The best focus is the peak of the whole frame's sharpness over the lens positions, "
        "interpolated by a Gaussian through the sharpest position and its neighbours; each "
        "region's peak is reported too (a tilted sensor or scene peaks at different positions "
        "across the frame).");
    return {sub, [args] { return runSweepCommand(*args); }};
}

}  // namespace infocus::cli
