// SPDX-License-Identifier: MIT
// A focus sweep's summary as JSON, and its table and region grids for people.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "infocus/optics.h"
#include "infocus/sweep_output.h"
#include "print.h"

namespace infocus {

namespace {

using Json = nlohmann::ordered_json;
using output::print;

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
    return formatDistance(optics::distanceFromDioptres(dioptres));
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
        if (r.blurWidthPx && r.status == RegionStatus::Ok) w.push_back(*r.blurWidthPx);
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

// One line per row of regions, each cell from @p cell (empty: "-").
void writeRegionGrid(std::ostream& out, const SweepResult& r,
                     const std::function<std::string(size_t region)>& cell) {
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
            print(out, "%12s", cells[static_cast<size_t>(row) * cols + col].c_str());
        out << "\n";
    }
}

// A position for a grid cell: the distance in focus for a dioptre control.
std::string cellText(double position, const std::string& unit) {
    return unit == "dioptre" ? inFocusText(position) : positionText(position, unit);
}

}  // namespace

std::string sweepSummaryJson(std::string_view source, const SweepResult& r, int settleFrames,
                             int indent) {
    const std::string& unit = r.range.unit;
    Json j;
    j["source"] = source;
    j["unit"] = unit;
    j["range"] = {{"min", r.range.min}, {"max", r.range.max}, {"step", r.range.step}};
    j["settle_frames"] = settleFrames;
    Json steps = Json::array();
    for (const SweepStep& s : r.steps) {
        const auto [blur, withBlur] = medianBlur(s.analysis);
        steps.push_back(
            {{"pass", s.pass},
             {"commanded", s.commanded},
             {"lens_position",
              {{"value", s.lens.value},
               {"unit", s.lens.unit},
               {"dioptres", s.lens.dioptres ? Json(*s.lens.dioptres) : Json(nullptr)}}},
             {"frame", s.analysis.frame},
             {"frame_sharpness",
              hasMeasurableRegion(s.analysis) ? Json(s.analysis.frameSharpness) : Json(nullptr)},
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
    return j.dump(indent);
}

void writeSweepHeader(std::ostream& out, std::string_view source, const FocusRange& range,
                      double from, double to, int steps, int refineSteps, int settleFrames) {
    print(out, "sweep of %.*s: lens %s to %s, %d positions", static_cast<int>(source.size()),
          source.data(), positionText(from, range.unit).c_str(),
          positionText(to, range.unit).c_str(), steps);
    if (refineSteps) print(out, ", then %d about the sharpest", refineSteps);
    print(out, "; %d frame(s) discarded after each move\n", settleFrames);
    print(out, "%5s %14s %12s %16s %22s\n", "pass", "lens", "in focus at", "frame sharpness",
          "blur px (median, n)");
}

void writeSweepStep(std::ostream& out, const SweepStep& s) {
    const auto [blur, n] = medianBlur(s.analysis);
    const auto d = s.lens.dioptres;
    char blurText[32] = "-";
    if (blur) std::snprintf(blurText, sizeof blurText, "%.2f (%d)", *blur, n);
    char sharpText[32] = "-";  // no region Ok: too dark or clipped to score
    if (hasMeasurableRegion(s.analysis))
        std::snprintf(sharpText, sizeof sharpText, "%.6g", s.analysis.frameSharpness);
    print(out, "%5d %14s %12s %16s %22s\n", s.pass + 1,
          positionText(s.lens.value, s.lens.unit).c_str(), d ? inFocusText(*d).c_str() : "-",
          sharpText, blurText);
}

void writeSweepSummary(std::ostream& out, const SweepResult& r, bool movedToBest) {
    if (!r.best) return;
    const FocusPeak& best = *r.best;
    const std::string& unit = r.range.unit;
    print(out, "best focus: %s", positionText(best.position, unit).c_str());
    if (const auto d = dioptresOf(best.position, unit))
        print(out, " (in focus at %s from the lens)", inFocusText(*d).c_str());
    print(out, ", frame sharpness %.6g, %.0f %% above the sweep's lowest; %s\n", best.score,
          100.0 * best.prominence,
          movedToBest ? "the lens is left there" : "the lens stays at the last position");
    print(out, "sharpest position of each region (%s; * at the sweep's end):\n",
          unit == "dioptre" ? "distance in focus" : unit.c_str());
    writeRegionGrid(out, r, [&](size_t i) -> std::string {
        if (i >= r.regionBest.size() || !r.regionBest[i]) return {};
        const FocusPeak& p = *r.regionBest[i];
        return cellText(p.position, unit) + (p.atEnd ? "*" : "");
    });
    std::vector<double> slopes, rms;
    for (const auto& f : r.regionBlurFit)
        if (f) slopes.push_back(f->slopePxPerUnit), rms.push_back(f->rmsPx);
    if (slopes.empty()) return;
    print(out, "where each region's blur width vanishes (a V fitted to its blur widths, %s):\n",
          unit == "dioptre" ? "distance in focus" : unit.c_str());
    writeRegionGrid(out, r, [&](size_t i) -> std::string {
        if (i >= r.regionBlurFit.size() || !r.regionBlurFit[i]) return {};
        return cellText(r.regionBlurFit[i]->position, unit);
    });
    print(out,
          "blur widths grow %.3g px per %s of defocus (median of %zu regions; RMS of the fits "
          "%.2g px)\n",
          median(slopes), unit == "dioptre" ? "dioptre" : unit.c_str(), slopes.size(), median(rms));
}

}  // namespace infocus
