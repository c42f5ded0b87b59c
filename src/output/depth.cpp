// SPDX-License-Identifier: MIT
// `infocus depth`'s view of a frame's depth map: one JSON object, or a table for people.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "infocus/depth_output.h"
#include "json_fields.h"
#include "print.h"

namespace infocus {

namespace {

using Json = nlohmann::ordered_json;
using output::print;

// JSON has no infinity: a distance that is infinite or missing is null.
Json metresOrNull(const std::optional<double>& v) {
    return v && std::isfinite(*v) ? Json(*v) : Json(nullptr);
}

std::string lengthOrDash(const std::optional<double>& v) {
    if (!v) return "-";
    return formatDistance(*v);
}

}  // namespace

std::string depthJsonLine(const FrameAnalysis& a, const DepthMap& map, const DepthCamera& camera) {
    const auto& fit = map.plane;
    Json j;
    j["frame"] = a.frame;
    j["width"] = a.width;
    j["height"] = a.height;
    j["focus_m"] = metresOrNull(camera.focusDistance);
    j["focus_source"] = camera.focusSource;
    j["focal_length_m"] = camera.lens.focalLength;
    j["f_number"] = camera.lens.fNumber;
    j["pixel_pitch_um"] = camera.pixelPitch * 1e6;
    j["blur_floor_px"] = camera.blurFloorPx;
    j["far_root_limit_px"] = map.farRootLimitPx;
    Json regions = Json::array();
    for (const auto& d : map.regions) {
        const RegionResult& r = a.regions[d.region];
        Json o;
        output::putRegionPlace(o, r.col, r.row, r.rect);
        o["blur_width_px"] = metresOrNull(r.blurWidthPx);
        o["confidence"] = r.confidence;
        o["status"] = regionStatusName(r.status);
        if (r.status != RegionStatus::Ok) o["reason"] = r.statusReason;
        if (d.roots) {
            o["defocus_px"] = d.roots->defocusBlur / camera.pixelPitch;
            o["near_m"] = d.roots->nearRoot;
            o["far_m"] = metresOrNull(d.roots->farRoot);
        } else {
            o["defocus_px"] = nullptr;
            o["near_m"] = nullptr;
            o["far_m"] = nullptr;
        }
        o["side"] = d.side;
        regions.push_back(std::move(o));
    }
    j["regions"] = std::move(regions);
    if (fit) {
        Json p;
        p["p0_px"] = fit->p[0];
        p["p1"] = fit->p[1];
        p["p2"] = fit->p[2];
        p["gradient"] = fit->gradient;
        p["line_angle_deg"] = fit->lineAngleDeg;
        if (fit->inFocusLine) {
            const auto& s = *fit->inFocusLine;
            p["in_focus_line_px"] = {s.x0, s.y0, s.x1, s.y1};
        } else {
            p["in_focus_line_px"] = nullptr;
        }
        p["rms_residual_px"] = fit->rmsResidual;
        p["samples"] = fit->samples;
        p["inliers"] = fit->inliers;
        Json hyps = Json::array();
        if (map.scenes)
            for (const auto& s : *map.scenes)
                hyps.push_back({{"a", s.a},
                                {"b", s.b},
                                {"c", s.c},
                                {"tilt_deg", s.tiltDeg},
                                {"axis_deg", s.axisAngleDeg},
                                {"recedes_towards_deg", s.recedesTowardsDeg},
                                {"depth_on_axis_m", metresOrNull(s.depthOnAxis)}});
        p["scene_planes"] = std::move(hyps);
        j["plane"] = std::move(p);
    } else {
        j["plane"] = nullptr;
    }
    return j.dump();
}

void writeDepthTable(std::ostream& out, const FrameAnalysis& a, const DepthMap& map,
                     const DepthCamera& camera) {
    const auto& fit = map.plane;
    print(out, "frame %llu  %dx%d  %g mm f/%g  focus %s (%s)  pitch %.3g um\n",
          static_cast<unsigned long long>(a.frame), a.width, a.height,
          camera.lens.focalLength * 1e3, camera.lens.fNumber,
          formatDistance(camera.focusDistance).c_str(), camera.focusSource.c_str(),
          camera.pixelPitch * 1e6);
    print(out, "  blur beyond %.1f px has no far root (a point at infinity blurs that much)\n\n",
          map.farRootLimitPx);
    out << "  col row   blur px  conf   near root     far root   side\n";
    for (const auto& d : map.regions) {
        const RegionResult& r = a.regions[d.region];
        char blur[32];
        if (r.status != RegionStatus::Ok)
            std::snprintf(blur, sizeof blur, "%8s",
                          r.status == RegionStatus::Dark ? "dark" : "clip");
        else if (r.blurWidthPx)
            std::snprintf(blur, sizeof blur, "%8.2f", *r.blurWidthPx);
        else
            std::snprintf(blur, sizeof blur, "%8s", "-");
        print(out, "  %3d %3d  %s  %4.2f  %10s  %11s   %s\n", r.col, r.row, blur, r.confidence,
              d.roots ? formatDistance(d.roots->nearRoot).c_str() : "-",
              d.roots ? lengthOrDash(d.roots->farRoot).c_str() : "-",
              d.side > 0 ? "+" : (d.side < 0 ? "-" : " "));
    }
    if (!fit) {
        out << "\n  in-focus plane: not enough regions with a blur measurement (need 3 not on one "
               "line)\n\n";
        return;
    }
    print(out, "\n  in-focus plane  |p0 + p1 x + p2 y| fitted to %d of %d regions, rms %.2f px\n",
          fit->inliers, fit->samples, fit->rmsResidual);
    print(out, "  blur gradient   %.4g px per px; zero line at %.1f deg from the x axis\n",
          fit->gradient, fit->lineAngleDeg);
    if (fit->inFocusLine)
        print(out, "  in-focus line   (%.0f, %.0f) to (%.0f, %.0f) px\n", fit->inFocusLine->x0,
              fit->inFocusLine->y0, fit->inFocusLine->x1, fit->inFocusLine->y1);
    else
        out << "  in-focus line   outside the image: every region is on one side of focus\n";
    if (map.scenes) {
        for (int k = 0; k < 2; ++k) {
            const auto& s = (*map.scenes)[k];
            print(out,
                  "  %s  tilt %.2f deg about an axis at %.1f deg, receding towards %.0f "
                  "deg; on axis at %s (aX+bY+cZ=1: a=%.4g b=%.4g c=%.4g /m)\n",
                  k == 0 ? "if + is beyond focus " : "if + is before focus", s.tiltDeg,
                  s.axisAngleDeg, s.recedesTowardsDeg, formatDistance(s.depthOnAxis).c_str(), s.a,
                  s.b, s.c);
        }
        out << "  one focus setting cannot tell which side is nearer: regions marked + share a "
               "side; a second focus setting decides it\n";
    }
    out << "\n";
}

}  // namespace infocus
