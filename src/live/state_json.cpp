// SPDX-License-Identifier: MIT
// The live state as JSON: `live --ui json` and the web view's /state.
#include <cmath>
#include <nlohmann/json.hpp>

#include "infocus/live.h"
#include "src/live/present.h"

namespace infocus {

namespace {

using Json = nlohmann::ordered_json;

Json number(const std::optional<double>& v) {
    if (!v || std::isnan(*v)) return nullptr;
    if (std::isinf(*v)) return "inf";
    return *v;
}

}  // namespace

std::string liveStateJson(const LiveState& s) {
    Json j;
    j["frame"] = s.frame;
    j["source"] = s.source;
    j["sequence"] = s.sequence;
    j["live_camera"] = s.liveCamera;
    j["elapsed_s"] = s.elapsedS;
    j["width"] = s.width;
    j["height"] = s.height;
    j["fps"] = s.fps;
    j["dropped"] = s.dropped;
    j["damaged"] = s.damaged;
    j["skipped"] = s.skipped;
    j["latency_p50_ms"] = s.latencyP50Ms;
    j["latency_p99_ms"] = s.latencyP99Ms;
    j["metric"] = s.metric;
    j["score"] = s.score;
    j["peak"] = s.peak;
    j["percent_of_peak"] = s.percentOfPeak;
    j["trend"] = std::string(trendName(s.trend));
    j["past_peak"] = s.pastPeak;
    j["blur_px"] = number(s.blurPx);
    j["blur_um"] = number(s.blurUm);
    if (s.lens && std::isfinite(s.lens->value)) {
        j["lens_position"] = {{"value", s.lens->value},
                              {"unit", s.lens->unit},
                              {"dioptres", number(s.lens->dioptres)}};
    } else {
        j["lens_position"] = nullptr;
    }
    j["in_focus_distance_m"] = number(s.inFocusDistanceM);
    j["autofocus_running"] = s.autofocusRunning;
    j["autofocus"] = {{"mode", liveAutofocusModeName(s.autofocus.mode)},
                      {"state", liveAutofocusStateName(s.autofocus.state)},
                      {"frames", s.autofocus.frames},
                      {"reason", s.autofocus.reason}};
    j["has_focus_control"] = s.hasFocusControl;
    if (s.focusRange)
        j["focus_range"] = {{"min", s.focusRange->min},
                            {"max", s.focusRange->max},
                            {"step", s.focusRange->step},
                            {"unit", s.focusRange->unit}};
    else
        j["focus_range"] = nullptr;
    j["coc_px"] = s.cocPx;
    j["coc_from_lens"] = s.cocFromLens;
    j["diffraction_px"] = number(s.diffractionPx);
    j["regions_with_blur"] = s.regionsWithBlur;
    j["regions_in_coc"] = s.regionsInCoc;
    j["dof_near_m"] = number(s.dofNearM);
    j["dof_far_m"] = number(s.dofFarM);
    if (s.inFocusLine)
        j["in_focus_line"] = {{"x0", s.inFocusLine->x0},
                              {"y0", s.inFocusLine->y0},
                              {"x1", s.inFocusLine->x1},
                              {"y1", s.inFocusLine->y1}};
    else
        j["in_focus_line"] = nullptr;
    j["tilt_deg"] = number(s.tiltDeg);
    j["status"] = s.status;
    Json history = Json::array();
    for (const HistoryPoint& p : s.history)
        history.push_back({p.tS, p.score});
    j["history"] = std::move(history);
    j["history_peak"] =
        s.historyPeak ? Json{s.historyPeak->tS, s.historyPeak->score} : Json(nullptr);
    j["grid"] = {s.cols, s.rows};
    Json regions = Json::array();
    for (const LiveRegion& r : s.regions)
        regions.push_back(
            {{"col", r.col},
             {"row", r.row},
             {"x", r.rect.x},
             {"y", r.rect.y},
             {"w", r.rect.w},
             {"h", r.rect.h},
             {"sharpness", r.status == RegionStatus::Ok ? Json(r.sharpness) : Json()},
             {"blur_px", number(r.blurPx)},
             {"mtf50_cy_px", number(r.mtf50CyPx)},
             {"mtf50p_cy_px", number(r.mtf50pCyPx)},
             {"confidence", r.confidence},
             {"status", std::string(regionStatusName(r.status))},
             {"depth_m",
              r.depthNearM ? Json::array({number(r.depthNearM), number(r.depthFarM)}) : Json()},
             {"heat", std::string(present::heatName(present::heatOf(r, s.cocPx)))}});
    j["regions"] = std::move(regions);
    j["peaking"] = std::string(peakingModeName(s.peaking));
    j["roi"] = s.scoreRoi ? Json{s.scoreRoi->x, s.scoreRoi->y, s.scoreRoi->w, s.scoreRoi->h}
                          : Json(nullptr);
    if (s.magnifier)
        j["magnifier"] = {
            {"x", s.magnifier->x}, {"y", s.magnifier->y}, {"zoom", s.magnifier->zoom}};
    else
        j["magnifier"] = nullptr;
    if (s.preview)
        j["preview"] = {{"width", s.preview->width()}, {"height", s.preview->height()}};
    else
        j["preview"] = nullptr;
    return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

}  // namespace infocus
