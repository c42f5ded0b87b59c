// SPDX-License-Identifier: MIT
// Zones, criteria and verdicts of `infocus check` on one frame and on a stack (docs/qa.md).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "infocus/depth_map.h"
#include "infocus/plane_fit.h"
#include "infocus/qa.h"
#include "infocus/sfr.h"

namespace infocus::qa {

namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

// MTF50 (cy/px) of regions grouped by zone, and what the criteria read from them.
struct ZoneValues {
    std::vector<double> zone[3];
    std::vector<double> all;
    double weighted = 0.0, weights = 0.0;
    void add(Zone z, double v) {
        zone[static_cast<int>(z)].push_back(v);
        all.push_back(v);
        weighted += zoneWeight(z) * v;
        weights += zoneWeight(z);
    }
    static std::optional<double> mean(const std::vector<double>& v) {
        if (v.empty()) return std::nullopt;
        double s = 0.0;
        for (double x : v)
            s += x;
        return s / static_cast<double>(v.size());
    }
};

// The limit @p m in its unit, and @p cyPx in the same unit (@p pitch checked by the caller).
struct InUnit {
    double limit;
    std::string unit;
    double (*convert)(double, double);
};
InUnit unitOf(const MtfLimit& m) {
    if (m.lpMm)
        return {*m.lpMm, "lp/mm", [](double v, double pitch) { return cyPxToLpMm(v, pitch); }};
    return {*m.cyPx, "cy/px", [](double v, double) { return v; }};
}

Criterion minimum(std::string name, std::string unit, double limit, std::optional<double> v,
                  const std::string& missing) {
    Criterion c{std::move(name), std::move(unit), true, limit, v, false, ""};
    c.pass = v && *v >= limit;
    if (!v)
        c.reason = missing;
    else if (!c.pass)
        c.reason = "below the limit";
    return c;
}

Criterion maximum(std::string name, std::string unit, double limit, std::optional<double> v,
                  const std::string& missing) {
    Criterion c{std::move(name), std::move(unit), false, limit, v, false, ""};
    c.pass = v && *v <= limit;
    if (!v)
        c.reason = missing;
    else if (!c.pass)
        c.reason = "above the limit";
    return c;
}

// The MTF50 criteria (zones, every region, weighted, corner/centre) on @p values, with the
// regions' own pass flags in @p regions.
void mtfCriteria(const ZoneValues& values, const Spec& spec, const LensData& lens,
                 std::vector<RegionVerdict>& regions, Verdict& v) {
    const double pitch = lens.pixelPitch.value_or(0.0);
    for (int z = 0; z < 3; ++z) {
        if (!spec.zoneMin[z]) continue;
        const InUnit u = unitOf(*spec.zoneMin[z]);
        auto m = ZoneValues::mean(values.zone[z]);
        if (m) m = u.convert(*m, pitch);
        v.criteria.push_back(minimum(std::string(zoneName(static_cast<Zone>(z))) + "_mtf50", u.unit,
                                     u.limit, m, "no confident region in the zone"));
        for (RegionVerdict& r : regions)
            if (static_cast<int>(r.zone) == z && r.mtf50CyPx &&
                u.convert(*r.mtf50CyPx, pitch) < u.limit)
                r.pass = false;
    }
    if (spec.everyRegionMin) {
        const InUnit u = unitOf(*spec.everyRegionMin);
        std::optional<double> least;
        if (!values.all.empty())
            least = u.convert(*std::min_element(values.all.begin(), values.all.end()), pitch);
        v.criteria.push_back(
            minimum("every_region_mtf50", u.unit, u.limit, least, "no confident region"));
        for (RegionVerdict& r : regions)
            if (r.mtf50CyPx && u.convert(*r.mtf50CyPx, pitch) < u.limit) r.pass = false;
    }
    if (spec.weightedMin) {
        const InUnit u = unitOf(*spec.weightedMin);
        std::optional<double> w;
        if (values.weights > 0) w = u.convert(values.weighted / values.weights, pitch);
        v.criteria.push_back(minimum("weighted_mtf50", u.unit, u.limit, w, "no confident region"));
    }
    if (spec.minCornerCentreRatio) {
        const auto c = ZoneValues::mean(values.zone[0]), k = ZoneValues::mean(values.zone[2]);
        std::optional<double> ratio;
        if (c && k && *c > 0) ratio = *k / *c;
        v.criteria.push_back(minimum("corner_centre_ratio", "", *spec.minCornerCentreRatio, ratio,
                                     "no confident region in the centre or the corners"));
    }
}

// Least squares of z = c0 + c1 x + c2 y + c3 ρ² over @p pts (x, y, ρ², z); false when singular.
bool fitSurface(const std::vector<std::array<double, 4>>& pts, int terms, double c[4]) {
    double a[4][5] = {};
    for (const auto& p : pts) {
        const double f[4] = {1.0, p[0], p[1], p[2]};
        for (int i = 0; i < terms; ++i) {
            for (int j = 0; j < terms; ++j)
                a[i][j] += f[i] * f[j];
            a[i][4] += f[i] * p[3];
        }
    }
    for (int i = 0; i < terms; ++i) {
        int best = i;
        for (int r = i + 1; r < terms; ++r)
            if (std::abs(a[r][i]) > std::abs(a[best][i])) best = r;
        if (std::abs(a[best][i]) < 1e-12) return false;
        std::swap(a[i], a[best]);
        for (int r = 0; r < terms; ++r) {
            if (r == i) continue;
            const double k = a[r][i] / a[i][i];
            for (int j = i; j < 5; ++j)
                a[r][j] -= k * a[i][j];
        }
    }
    for (int i = 0; i < 4; ++i)
        c[i] = i < terms ? a[i][4] / a[i][i] : 0.0;
    return true;
}

// µm per axis unit where the axis is a length (a stage's Z), else empty.
std::optional<double> umPerUnit(const std::string& unit) {
    if (unit == "mm") return 1e3;
    if (unit == "um" || unit == "µm") return 1.0;
    if (unit == "nm") return 1e-3;
    if (unit == "cm") return 1e4;
    return std::nullopt;
}

}  // namespace

std::string_view zoneName(Zone z) {
    switch (z) {
        case Zone::Centre:
            return "centre";
        case Zone::Corners:
            return "corners";
        case Zone::Middle:
            break;
    }
    return "middle";
}

Zone zoneOf(double x, double y, int width, int height) {
    const double dx = x - 0.5 * width, dy = y - 0.5 * height;
    const double r = std::hypot(dx, dy) / std::hypot(0.5 * width, 0.5 * height);
    return r <= 0.30 ? Zone::Centre : r > 0.75 ? Zone::Corners : Zone::Middle;
}

double zoneWeight(Zone z) {
    return z == Zone::Centre ? 1.0 : z == Zone::Middle ? 0.75 : 0.25;
}

Verdict judgeFrame(const FrameAnalysis& a, const Spec& spec, const LensData& lens) {
    Verdict v;
    v.frame = a.frame;
    v.width = a.width, v.height = a.height;
    ZoneValues values;
    std::vector<optics::BlurSample> blur;
    std::optional<double> widest;
    int ok = 0;
    for (const RegionResult& r : a.regions) {
        RegionVerdict rv;
        rv.rect = r.rect;
        const double cx = r.rect.x + 0.5 * r.rect.w, cy = r.rect.y + 0.5 * r.rect.h;
        rv.zone = zoneOf(cx, cy, a.width, a.height);
        ok += r.status == RegionStatus::Ok;
        const bool confident = r.status == RegionStatus::Ok && r.confidence >= spec.minConfidence;
        if (confident && r.mtf50CyPx) {
            rv.mtf50CyPx = r.mtf50CyPx;
            values.add(rv.zone, *r.mtf50CyPx);
        }
        if (confident && r.blurWidthPx) {
            blur.push_back({cx, cy, *r.blurWidthPx, r.confidence});
            widest = std::max(widest.value_or(0.0), *r.blurWidthPx);
        }
        v.regions.push_back(rv);
    }
    if (ok == 0)
        v.reason = "no region could be measured: the frame is too dark or clipped";
    else if (values.all.empty())
        v.reason = "no edge with a confident MTF50 in any region";
    mtfCriteria(values, spec, lens, v.regions, v);
    const double pitch = lens.pixelPitch.value_or(0.0);
    if (spec.maxBlurWidthPx)
        v.criteria.push_back(
            maximum("blur_width", "px", *spec.maxBlurWidthPx, widest, "no confident blur width"));
    if (spec.maxBlurWidthUm) {
        std::optional<double> um;
        if (widest) um = *widest * pitch * 1e6;
        v.criteria.push_back(
            maximum("blur_width", "µm", *spec.maxBlurWidthUm, um, "no confident blur width"));
    }
    if (spec.maxTiltDeg || spec.maxTiltUm) {
        std::optional<double> deg, um;
        const auto plane = blur.size() >= 3 && lens.fNumber
                               ? optics::fitBlurPlane(blur, a.width, a.height)
                               : std::nullopt;
        if (plane) {
            const double n = *lens.fNumber;
            deg = std::atan(plane->gradient * n) * kDeg;
            um = (std::abs(plane->p[1]) * a.width + std::abs(plane->p[2]) * a.height) * pitch * n *
                 1e6;
        }
        const std::string missing = "fewer than 3 confident blur widths to fit a plane";
        if (spec.maxTiltDeg)
            v.criteria.push_back(maximum("tilt", "deg", *spec.maxTiltDeg, deg, missing));
        if (spec.maxTiltUm)
            v.criteria.push_back(maximum("tilt", "µm", *spec.maxTiltUm, um, missing));
    }
    if (spec.minInFocusM || spec.maxInFocusM) {
        const std::optional<double> d = focusFromLensPosition(a);
        const std::string missing = "the frame carries no lens position in dioptres";
        if (spec.minInFocusM)
            v.criteria.push_back(minimum("in_focus_distance", "m", *spec.minInFocusM, d, missing));
        if (spec.maxInFocusM)
            v.criteria.push_back(maximum("in_focus_distance", "m", *spec.maxInFocusM, d, missing));
    }
    if (spec.minConfidentRegions)
        v.criteria.push_back(minimum("confident_regions", "", *spec.minConfidentRegions,
                                     static_cast<double>(values.all.size()), ""));
    v.pass = v.reason.empty() && std::all_of(v.criteria.begin(), v.criteria.end(),
                                             [](const Criterion& c) { return c.pass; });
    return v;
}

ThroughFocus throughFocus(const StackResult& stack, double minConfidence,
                          std::optional<double> thresholdCyPx) {
    ThroughFocus tf;
    tf.axisUnit = stack.axisUnit;
    tf.axis = stack.axis;
    const size_t n = stack.axis.size();
    std::vector<std::array<double, 4>> pts;
    std::vector<Zone> zones;
    const double hw = 0.5 * stack.width, hh = 0.5 * stack.height;
    for (const StackRegion& g : stack.regions) {
        RegionFocus rf;
        rf.col = g.col, rf.row = g.row, rf.rect = g.rect;
        const double cx = g.rect.x + 0.5 * g.rect.w, cy = g.rect.y + 0.5 * g.rect.h;
        rf.zone = zoneOf(cx, cy, stack.width, stack.height);
        for (size_t i = 0; i < n; ++i) {
            std::optional<double> m;
            if (i < g.mtf50.size() && g.usable[i] && g.confidence[i] >= minConfidence)
                m = g.mtf50[i];
            rf.mtf50.push_back(m);
        }
        // The curve read through a mean of three frames, where the frame and one beside it at
        // least were measured: one edge read sharp in one frame (clutter, a lone segment) must
        // not make the peak. A mean of three leaves a parabola's vertex where it was.
        std::vector<std::optional<double>> sm(n);
        int peak = -1, count = 0;
        for (size_t i = 0; i < n; ++i) {
            if (!rf.mtf50[i]) continue;
            double sum = *rf.mtf50[i];
            int k = 1;
            for (size_t j : {i - 1, i + 1})
                if (j < n && rf.mtf50[j]) sum += *rf.mtf50[j], ++k;
            if (k < 2) continue;
            sm[i] = sum / k;
            ++count;
            if (peak < 0 || *sm[i] > *sm[static_cast<size_t>(peak)]) peak = static_cast<int>(i);
        }
        if (count >= 3 && peak >= 0) {
            const size_t p = static_cast<size_t>(peak);
            double best = tf.axis[p], top = *sm[p];
            // A parabola through the peak and its two neighbours where both were measured.
            if (p > 0 && p + 1 < n && sm[p - 1] && sm[p + 1]) {
                const double x0 = tf.axis[p - 1], x1 = tf.axis[p], x2 = tf.axis[p + 1];
                const double y0 = *sm[p - 1], y1 = top, y2 = *sm[p + 1];
                const double d = (x0 - x1) * (x0 - x2) * (x1 - x2);
                const double A = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / d;
                const double B =
                    (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / d;
                if (A < 0) {
                    const double xv = -B / (2 * A);
                    if (xv >= std::min(x0, x2) && xv <= std::max(x0, x2)) {
                        best = xv;
                        top = A * xv * xv + B * xv + (y1 - A * x1 * x1 - B * x1);
                    }
                }
            }
            rf.bestPosition = best;
            rf.bestMtf50 = top;
            rf.thresholdCyPx = thresholdCyPx.value_or(0.8 * top);
            // The span about the peak where MTF50 stays at or above the threshold, linear
            // between frames; a side that never falls below it ends at the stack's end.
            const double thr = rf.thresholdCyPx;
            if (*sm[p] >= thr) {
                auto edge = [&](int step) {
                    size_t i = p;
                    while (true) {
                        const long j = static_cast<long>(i) + step;
                        if (j < 0 || j >= static_cast<long>(n)) return tf.axis[i];
                        const auto& m = sm[static_cast<size_t>(j)];
                        if (!m) return tf.axis[i];
                        if (*m < thr) {
                            const double a0 = *sm[i], t = (a0 - thr) / (a0 - *m);
                            return tf.axis[i] + t * (tf.axis[static_cast<size_t>(j)] - tf.axis[i]);
                        }
                        i = static_cast<size_t>(j);
                    }
                };
                const double lo = edge(-1), hi = edge(+1);
                rf.dofLow = std::min(lo, hi), rf.dofHigh = std::max(lo, hi);
            }
            ++tf.regionsWithPeak;
            const double x = (cx - hw) / hw, y = (cy - hh) / hh;
            const double rho2 =
                ((cx - hw) * (cx - hw) + (cy - hh) * (cy - hh)) / (hw * hw + hh * hh);
            pts.push_back({x, y, rho2, best});
            zones.push_back(rf.zone);
        }
        tf.regions.push_back(std::move(rf));
    }
    // Tilt and curvature need regions spread over the frame: a plane and a bowl.
    double c[4];
    if (pts.size() >= 6 && fitSurface(pts, 4, c)) {
        tf.tiltAcross = 2.0 * (std::abs(c[1]) + std::abs(c[2]));
        tf.tiltDirectionDeg = std::atan2(c[2] / hh, c[1] / hw) * kDeg;
        tf.fieldCurvature = c[3];
        if (const auto um = umPerUnit(tf.axisUnit)) {
            tf.tiltAcrossUm = *tf.tiltAcross * *um;
            tf.fieldCurvatureUm = c[3] * *um;
        }
    }
    return tf;
}

Verdict judgeStack(const StackResult& stack, const ThroughFocus& tf, const Spec& spec,
                   const LensData& lens) {
    Verdict v;
    v.width = stack.width, v.height = stack.height;
    ZoneValues values;
    std::vector<double> centreBest;
    for (const RegionFocus& r : tf.regions) {
        RegionVerdict rv;
        rv.rect = r.rect;
        rv.zone = r.zone;
        if (r.bestMtf50) {
            rv.mtf50CyPx = r.bestMtf50;
            values.add(r.zone, *r.bestMtf50);
            if (r.zone == Zone::Centre) centreBest.push_back(*r.bestPosition);
        }
        v.regions.push_back(rv);
    }
    if (values.all.empty()) v.reason = "no region has a through-focus peak of its MTF50";
    mtfCriteria(values, spec, lens, v.regions, v);
    if (spec.maxBlurWidthPx || spec.maxBlurWidthUm)
        v.reason += std::string(v.reason.empty() ? "" : "; ") +
                    "a blur width limit applies to single frames, not to a stack";
    if (spec.maxTiltDeg || spec.maxTiltUm) {
        // The best positions' tilt in µm: a stage axis directly; a dioptre axis on the image
        // side, Δz ≈ Δ(1/u)·f² (needs the focal length).
        std::optional<double> um = tf.tiltAcrossUm;
        if (!um && tf.tiltAcross && tf.axisUnit == "dioptre" && lens.focalLength)
            um = *tf.tiltAcross * *lens.focalLength * *lens.focalLength * 1e6;
        std::optional<double> deg;
        if (um && lens.pixelPitch) {
            const double across = (stack.width + stack.height) * *lens.pixelPitch * 1e6;
            deg = std::atan(*um / across) * kDeg;
        }
        const std::string missing =
            "no tilt: too few regions with a peak, or an axis that is no length (give "
            "positions in mm, or dioptres with --focal)";
        if (spec.maxTiltDeg)
            v.criteria.push_back(maximum("tilt", "deg", *spec.maxTiltDeg, deg, missing));
        if (spec.maxTiltUm)
            v.criteria.push_back(maximum("tilt", "µm", *spec.maxTiltUm, um, missing));
    }
    if (spec.minInFocusM || spec.maxInFocusM) {
        std::optional<double> d;
        if (tf.axisUnit == "dioptre" && !centreBest.empty()) {
            const auto m = ZoneValues::mean(centreBest);
            d = *m > 0 ? 1.0 / *m : std::numeric_limits<double>::infinity();
        }
        const std::string missing = "the stack's positions are not in dioptres or metres";
        if (spec.minInFocusM)
            v.criteria.push_back(minimum("in_focus_distance", "m", *spec.minInFocusM, d, missing));
        if (spec.maxInFocusM)
            v.criteria.push_back(maximum("in_focus_distance", "m", *spec.maxInFocusM, d, missing));
    }
    if (spec.minConfidentRegions)
        v.criteria.push_back(minimum("confident_regions", "", *spec.minConfidentRegions,
                                     static_cast<double>(values.all.size()), ""));
    v.pass = v.reason.empty() && std::all_of(v.criteria.begin(), v.criteria.end(),
                                             [](const Criterion& c) { return c.pass; });
    return v;
}

}  // namespace infocus::qa
