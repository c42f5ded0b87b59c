// SPDX-License-Identifier: MIT
// A focus stack's analysis as JSON, and its grids for people.
#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

#include "infocus/stack_output.h"
#include "json_fields.h"
#include "print.h"

namespace infocus {

namespace {

using Json = nlohmann::ordered_json;
using output::format;
using output::print;

Json orNull(const std::optional<double>& v) {
    return v && std::isfinite(*v) ? Json(*v) : Json(nullptr);
}

Json listOf(const std::vector<double>& v) {
    Json a = Json::array();
    for (double x : v)
        a.push_back(std::isfinite(x) ? Json(x) : Json(nullptr));
    return a;
}

// "1.250 dpt", "-50 mm", "frame 3.2"
std::string axisText(double v, const std::string& unit) {
    if (unit == "dioptre") return format("%.3f dpt", v);
    if (unit == "frame") return format("frame %.1f", v);
    return format("%g %s", v, unit.c_str());
}

// A region's cell in a grid: @p text where it has a value, else what it is.
std::string cell(const StackRegion& g, const std::optional<double>& v, const char* fmt) {
    if (g.status == StackRegionStatus::Ok) return v ? format(fmt, *v) : std::string("-");
    switch (g.status) {
        case StackRegionStatus::NoTexture:
            return "flat";
        case StackRegionStatus::Dark:
            return "dark";
        default:
            return "clip";
    }
}

void writeGrid(std::ostream& out, const StackResult& r, const std::string& title,
               const std::function<std::string(const StackRegion&)>& text) {
    int cols = 0, rows = 0;
    for (const StackRegion& g : r.regions)
        cols = std::max(cols, g.col + 1), rows = std::max(rows, g.row + 1);
    out << title << "\n";
    for (int row = 0; row < rows; ++row) {
        out << " ";
        for (int col = 0; col < cols; ++col)
            out << format(" %7s", text(r.regions[static_cast<size_t>(row) * cols + col]).c_str());
        out << "\n";
    }
}

}  // namespace

std::string stackJson(const StackResult& r, int indent) {
    Json j;
    j["source"] = r.source;
    j["width"] = r.width;
    j["height"] = r.height;
    j["metric"] = r.metric;
    j["axis_unit"] = r.axisUnit;
    j["position_unit"] = r.hasPositions ? Json(r.positionUnit) : Json(nullptr);
    j["blur_pole"] = r.blurPole ? Json(*r.blurPole) : Json(nullptr);
    Json frames = Json::array();
    for (const StackFrame& f : r.frames) {
        Json o;
        o["frame"] = f.index;
        o["file"] = f.origin.empty() ? Json(nullptr) : Json(f.origin);
        o["position"] = r.hasPositions ? orNull(f.lens->value) : Json(nullptr);
        o["dioptres"] = f.lens ? orNull(f.lens->dioptres) : Json(nullptr);
        o["frame_sharpness"] = f.frameSharpness;
        frames.push_back(std::move(o));
    }
    j["frames"] = std::move(frames);
    Json regions = Json::array();
    for (const StackRegion& g : r.regions) {
        Json o;
        output::putRegionPlace(o, g.col, g.row, g.rect);
        o["status"] = std::string(stackRegionStatusName(g.status));
        o["status_reason"] = g.statusReason.empty() ? Json(nullptr) : Json(g.statusReason);
        o["peak_frame"] = orNull(g.peakFrame);
        o["blur_peak_frame"] = orNull(g.blurPeakFrame);
        o["agree"] = g.agree ? Json(*g.agree) : Json(nullptr);
        o["peak_position"] = orNull(g.peakPosition);
        o["peak_dioptres"] = orNull(g.peakDioptres);
        o["in_focus_distance_m"] = orNull(g.inFocusDistance);
        o["at_end"] = g.peak ? Json(g.peak->atEnd) : Json(nullptr);
        if (g.blurFit) {
            Json b;
            b["position"] = g.blurFit->position;
            b["slope_px_per_unit"] = g.blurFit->slopePxPerUnit;
            b["rms_px"] = g.blurFit->rmsPx;
            b["points"] = g.blurFit->points;
            b["floor_px"] = g.blurFit->floorPx;
            o["blur_fit"] = std::move(b);
        } else {
            o["blur_fit"] = nullptr;
        }
        Json blur = Json::array();
        for (size_t i = 0; i < g.blurWidth.size(); ++i)
            blur.push_back(g.usable[i] ? orNull(g.blurWidth[i]) : Json(nullptr));
        Json sharp = Json::array(), mtf = Json::array(), mtfp = Json::array();
        for (size_t i = 0; i < g.sharpness.size(); ++i) {
            sharp.push_back(g.usable[i] ? Json(g.sharpness[i]) : Json(nullptr));
            mtf.push_back(i < g.mtf50.size() ? orNull(g.mtf50[i]) : Json(nullptr));
            mtfp.push_back(i < g.mtf50p.size() ? orNull(g.mtf50p[i]) : Json(nullptr));
        }
        o["curve"] = {{"sharpness", std::move(sharp)},
                      {"blur_px", std::move(blur)},
                      {"mtf50_cy_px", std::move(mtf)},
                      {"mtf50p_cy_px", std::move(mtfp)},
                      {"confidence", listOf(g.confidence)}};
        regions.push_back(std::move(o));
    }
    j["regions"] = std::move(regions);
    const StackAgreement a = stackAgreement(r);
    j["agreement"] = {{"textured", a.textured}, {"both", a.both}, {"agree", a.agree}};
    if (r.map.cols > 0)
        j["focus_map"] = {{"cols", r.map.cols}, {"rows", r.map.rows}, {"step_px", r.map.stepPx}};
    else
        j["focus_map"] = nullptr;
    j["timing"] = {{"analysis_s", r.analysisSeconds}, {"maps_s", r.mapSeconds}};
    return j.dump(indent);
}

void writeStackTable(std::ostream& out, const StackResult& r) {
    print(out, "%s: %zu frames of %dx%d, %s, curves over %s\n", r.source.c_str(), r.frames.size(),
          r.width, r.height, r.metric.c_str(),
          r.axisUnit == "frame" ? "the frame index (no positions)" : r.axisUnit.c_str());
    if (r.hasPositions)
        print(out, "positions: frame 0 at %s, frame %zu at %s\n",
              axisText(r.frames.front().lens->value, r.positionUnit).c_str(), r.frames.size() - 1,
              axisText(r.frames.back().lens->value, r.positionUnit).c_str());
    writeGrid(out, r, "sharpness peak, frame (flat: no texture; dark, clip: not measurable)",
              [](const StackRegion& g) { return cell(g, g.peakFrame, "%.2f"); });
    writeGrid(out, r, "blur V vertex, frame",
              [](const StackRegion& g) { return cell(g, g.blurPeakFrame, "%.2f"); });
    if (r.hasPositions) {
        writeGrid(out, r, "in-focus position (" + r.positionUnit + ")",
                  [](const StackRegion& g) { return cell(g, g.peakPosition, "%.4g"); });
        if (r.axisUnit == "dioptre")
            writeGrid(out, r, "in-focus distance", [](const StackRegion& g) {
                if (g.status != StackRegionStatus::Ok || !g.inFocusDistance)
                    return cell(g, std::nullopt, "");
                return formatDistance(*g.inFocusDistance);
            });
    }
    writeGrid(out, r, "agree within one frame (yes, NO; -: no blur vertex)",
              [](const StackRegion& g) -> std::string {
                  if (g.status != StackRegionStatus::Ok) return cell(g, std::nullopt, "");
                  return !g.agree ? "-" : *g.agree ? "yes" : "NO";
              });
    const StackAgreement a = stackAgreement(r);
    print(out,
          "agreement: %d of %d textured regions with both a peak and a vertex agree within one "
          "frame (%.0f %%); %d of %zu regions are textured\n",
          a.agree, a.both, a.both ? 100.0 * a.agree / a.both : 0.0, a.textured, r.regions.size());
}

}  // namespace infocus
