// SPDX-License-Identifier: MIT
// The blur V of a stack's regions (stack_internal.h): a Huber M-estimate of the thin-lens V on
// a lens's axis, and on a distance axis (a stage's Z) the V over the axis's own dioptres with
// the blur engine's floor.
#include <algorithm>
#include <array>
#include <cmath>

#include "stack_internal.h"

namespace infocus::stack_detail {

namespace {

// Blur widths above this share of a region's shorter side are left out of its V: on texture a
// disc wider than about a sixth of the region reads low (docs/blur.md, Textured scenes).
constexpr double kMaxBlurShare = 0.15;
// A blur V whose arms rise over the stack by less than this many times its RMS residual is a
// cloud of readings, not a V: its vertex is not reported.
constexpr double kMinVRiseOverRms = 3.0;
constexpr double kHuberC = 1.345;  // 95 % efficiency on Gaussian residuals
constexpr int kHuberPasses = 6;

// The floored V at q: √(k²(q − q0)² + floor²).
double flooredV(const BlurVFit& f, double q) {
    return std::hypot(f.slopePxPerUnit * (q - f.position), f.floorPx);
}

// For a vertex q0: k and floor of b² = k²(q − q0)² + floor² by weighted least squares on the
// squares, each weighted by w / (4 b²) (d(b²) = 2b·db, so the residuals count in pixels, as in
// the cost); a floor or slope that comes out negative is 0. Returns the cost Σ w·(b − model)².
double flooredAt(const std::vector<std::array<double, 3>>& pts, double q0, BlurVFit& f) {
    double s00 = 0, s01 = 0, s11 = 0, y0 = 0, y1 = 0;
    for (const auto& [q, b, w] : pts) {
        const double d2 = (q - q0) * (q - q0), ww = w / (4 * std::max(b * b, 1.0));
        s00 += ww * d2 * d2;
        s01 += ww * d2;
        s11 += ww;
        y0 += ww * d2 * b * b;
        y1 += ww * b * b;
    }
    double k2 = -1, f2 = -1;
    if (const double det = s00 * s11 - s01 * s01; det > 0) {
        k2 = (y0 * s11 - s01 * y1) / det;
        f2 = (s00 * y1 - s01 * y0) / det;
    }
    if (!(k2 >= 0 && f2 >= 0)) f2 = 0, k2 = s00 > 0 ? std::max(0.0, y0 / s00) : 0.0;
    f.position = q0;
    f.slopePxPerUnit = std::sqrt(k2);
    f.floorPx = std::sqrt(f2);
    double cost = 0;
    for (const auto& [q, b, w] : pts) {
        const double r = b - flooredV(f, q);
        cost += w * r * r;
    }
    return cost;
}

// The floored V through readings (q, b, w) with the least cost, its vertex searched over the
// readings' span; @p cost receives it. nullopt with fewer than 4 weighted readings.
std::optional<BlurVFit> fitFloored(std::span<const double> q, std::span<const double> b,
                                   std::span<const double> w, double& cost) {
    std::vector<std::array<double, 3>> pts;
    for (size_t i = 0; i < q.size(); ++i)
        if (w[i] > 0) pts.push_back({q[i], b[i], w[i]});
    if (pts.size() < 4) return std::nullopt;
    const auto [lo, hi] = std::minmax_element(pts.begin(), pts.end());
    const double q0 = (*lo)[0], q1 = (*hi)[0];
    BlurVFit best, f;
    cost = HUGE_VAL;
    constexpr int kGrid = 200;
    for (int i = 0; i <= kGrid; ++i)
        if (const double c = flooredAt(pts, q0 + (q1 - q0) * i / kGrid, f); c < cost)
            cost = c, best = f;
    const double cell = (q1 - q0) / kGrid, centre = best.position;
    for (int i = -20; i <= 20; ++i)
        if (const double c = flooredAt(pts, std::clamp(centre + cell * i / 20, q0, q1), f);
            c < cost)
            cost = c, best = f;
    double wsum = 0;
    for (const auto& p : pts)
        wsum += p[2];
    best.rmsPx = std::sqrt(std::max(0.0, cost) / wsum);
    best.points = static_cast<int>(pts.size());
    return best;
}

// The floored V with a vertex that has two weighted readings on each side (fitBlurV's rule).
std::optional<BlurVFit> fitFlooredV(std::span<const double> q, std::span<const double> b,
                                    std::span<const double> w) {
    double cost = 0;
    auto f = fitFloored(q, b, w, cost);
    if (!f) return f;
    int below = 0, above = 0;
    for (size_t i = 0; i < q.size(); ++i) {
        below += w[i] > 0 && q[i] < f->position;
        above += w[i] > 0 && q[i] > f->position;
    }
    if (below < 2 || above < 2) return std::nullopt;
    return f;
}

// The V (plain or floored) as a Huber M-estimate (iteratively reweighted least squares): each
// reading keeps its confidence as weight while its residual is within kHuberC robust σ
// (1.4826·MAD of the residuals, at least 0.5 px) and is weighted down in proportion beyond. A
// region's readings come from its strongest edges, which on a slanted surface lie at different
// depths from frame to frame; a plain least-squares V lets those of an edge at the region's
// border pull the vertex towards it. The RMS reported is that of the down-weighted readings:
// the V's rise is judged against the scatter of the readings that place it.
std::optional<BlurVFit> robustV(std::span<const double> q, std::span<const double> b,
                                std::span<const double> w, bool floored) {
    const auto fit1 = [&](std::span<const double> weights) {
        return floored ? fitFlooredV(q, b, weights) : fitBlurV(q, b, weights);
    };
    auto fit = fit1(w);
    if (!fit) return fit;
    std::vector<double> res(q.size()), sorted, w2(w.begin(), w.end());
    for (int pass = 0; pass < kHuberPasses; ++pass) {
        sorted.clear();
        for (size_t i = 0; i < q.size(); ++i) {
            res[i] = std::abs(b[i] - flooredV(*fit, q[i]));
            if (w[i] > 0) sorted.push_back(res[i]);
        }
        std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
        const double limit = kHuberC * std::max(0.5, 1.4826 * sorted[sorted.size() / 2]);
        for (size_t i = 0; i < q.size(); ++i)
            w2[i] = res[i] > limit ? w[i] * limit / res[i] : w[i];
        auto refit = fit1(w2);
        if (!refit) break;
        const bool settled = std::abs(refit->position - fit->position) <=
                             1e-6 * std::max(1.0, std::abs(fit->position));
        fit = refit;
        if (settled) break;
    }
    // A V whose arms do not rise above its floor by a few times its scatter is a cloud.
    double top = 0;
    for (size_t i = 0; i < q.size(); ++i)
        if (w[i] > 0) top = std::max(top, flooredV(*fit, q[i]));
    if (!(top - fit->floorPx >= kMinVRiseOverRms * fit->rmsPx)) return std::nullopt;
    return fit;
}

// The axis value @p x as seen by the V: 1/(x − pole) with a pole, else x.
double onV(double x, std::optional<double> pole) {
    return pole ? 1.0 / (x - *pole) : x;
}

}  // namespace

BlurReadings blurReadings(const StackRegion& g, const StackResult& r) {
    BlurReadings out;
    for (size_t i = 0; i < r.frames.size(); ++i) {
        // A blur wider than kMaxBlurShare of the region reads low on texture and leaves little
        // room for an edge's profile inside it: such a reading mixes in the neighbours' depths.
        if (!g.usable[i] || !g.blurWidth[i] ||
            !(*g.blurWidth[i] <= kMaxBlurShare * std::min(g.rect.w, g.rect.h)))
            continue;
        out.x.push_back(r.axis[i]);
        out.b.push_back(*g.blurWidth[i]);
        out.w.push_back(g.confidence[i]);
    }
    return out;
}

std::optional<double> chooseBlurPole(const std::vector<BlurReadings>& regions,
                                     const StackResult& r) {
    const auto [lo, hi] = std::minmax_element(r.axis.begin(), r.axis.end());
    const double span = *hi - *lo;
    std::vector<std::optional<double>> poles{std::nullopt};
    for (double share : {1.0 / 16, 1.0 / 8, 1.0 / 4, 1.0 / 2, 1.0, 2.0, 4.0}) {
        poles.push_back(*lo - span * share);
        poles.push_back(*hi + span * share);
    }
    std::optional<double> best;
    double bestCost = HUGE_VAL;
    std::vector<double> q;
    for (const std::optional<double>& pole : poles) {
        double total = 0;
        for (const BlurReadings& g : regions) {
            q.clear();
            for (double x : g.x)
                q.push_back(onV(x, pole));
            double cost = 0;
            if (fitFloored(q, g.b, g.w, cost)) total += cost;
        }
        if (total < bestCost) bestCost = total, best = pole;
    }
    return best;
}

std::optional<BlurVFit> fitRegionBlurV(const BlurReadings& in, const StackResult& r) {
    // The floor goes with the pole: where the axis is the lens's own (no pole), the plain V
    // places the vertex as well on a lens's steps as in dioptres, and a floor there takes up
    // the readings that place it.
    std::vector<double> q;
    for (double x : in.x)
        q.push_back(onV(x, r.blurPole));
    auto fit = robustV(q, in.b, in.w, r.blurPole.has_value());
    if (!fit || !r.blurPole) return fit;
    // Back on the axis: the vertex, and the slope of the V there in pixels per axis unit.
    const double d = 1.0 / fit->position;
    fit->position = *r.blurPole + d;
    fit->slopePxPerUnit /= d * d;
    return fit;
}

}  // namespace infocus::stack_detail
