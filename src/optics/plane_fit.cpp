// SPDX-License-Identifier: MIT
// Robust fit of the thin-lens model's blur "V": measured blur = |p0 + p1 x + p2 y|.
//
// The absolute value makes the problem non-linear, but once each sample's side of the in-focus
// line is known it is ordinary weighted least squares on s_i·b_i. So: (1) least median of
// squares (Rousseeuw 1984) over random triples, solving each triple for the 4 sign patterns that
// differ by more than the global sign; (2) iteratively reweighted least squares with Tukey's
// biweight, re-deciding each sample's side from the current plane.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "infocus/plane_fit.h"

namespace infocus::optics {

namespace {

struct Point {
    double x, y, b, w;
    size_t index;
    bool censored;  // read at or below the blur floor: only |model| ≤ floor is known
};

// Solves the 3x3 system m·q = r by Gaussian elimination with partial pivoting.
std::optional<std::array<double, 3>> solve3(std::array<std::array<double, 3>, 3> m,
                                            std::array<double, 3> r) {
    double scale = 0.0;
    for (const auto& row : m)
        for (double v : row)
            scale = std::max(scale, std::abs(v));
    if (scale == 0.0) return std::nullopt;
    for (int c = 0; c < 3; ++c) {
        int pivot = c;
        for (int i = c + 1; i < 3; ++i)
            if (std::abs(m[i][c]) > std::abs(m[pivot][c])) pivot = i;
        if (std::abs(m[pivot][c]) <= 1e-12 * scale) return std::nullopt;
        std::swap(m[c], m[pivot]);
        std::swap(r[c], r[pivot]);
        for (int i = c + 1; i < 3; ++i) {
            const double k = m[i][c] / m[c][c];
            for (int j = c; j < 3; ++j)
                m[i][j] -= k * m[c][j];
            r[i] -= k * r[c];
        }
    }
    std::array<double, 3> q{};
    for (int i = 2; i >= 0; --i) {
        double s = r[i];
        for (int j = i + 1; j < 3; ++j)
            s -= m[i][j] * q[j];
        q[i] = s / m[i][i];
    }
    return q;
}

double eval(const std::array<double, 3>& q, const Point& p) {
    return q[0] + q[1] * p.x + q[2] * p.y;
}

double median(std::vector<double>& v) {
    const size_t mid = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<ptrdiff_t>(mid), v.end());
    return v[mid];
}

// Residual of @p p under @p q: measured − |model|; for a censored sample (at or below the floor
// @p floor) only the model's excess over the floor counts, as a negative residual.
double residual(const std::array<double, 3>& q, const Point& p, double floor) {
    const double m = std::abs(eval(q, p));
    return p.censored ? -std::max(0.0, m - floor) : p.b - m;
}

// The LMedS cost of a hypothesis: the median of |residual|. With censored samples it is the
// median over the measured ones plus the median excess over the censored ones: a region read at
// the floor says only that the blur there is small, and when more than half the regions read so
// the plain median would be zero for the flat plane p = 0, whatever the rest show.
double lmedsCost(const std::array<double, 3>& q, const std::vector<Point>& pts, double floor,
                 std::vector<double>& scratch) {
    double cost = 0.0;
    for (const bool censored : {false, true}) {
        scratch.clear();
        for (const auto& p : pts)
            if (p.censored == censored) scratch.push_back(std::abs(residual(q, p, floor)));
        if (!scratch.empty()) cost += median(scratch);
    }
    return cost;
}

// Robust scale: 1.4826 × the median |residual| of the measured (uncensored) samples, times
// @p correction.
double madSigma(const std::vector<double>& residuals, const std::vector<Point>& pts,
                double correction, std::vector<double>& scratch) {
    scratch.clear();
    for (size_t i = 0; i < pts.size(); ++i)
        if (!pts[i].censored) scratch.push_back(std::abs(residuals[i]));
    return 1.4826 * correction * median(scratch);
}

// Weighted least squares of s_i·b_i ≈ q·(1, x, y) with weights w_i.
std::optional<std::array<double, 3>> weightedFit(const std::vector<Point>& pts,
                                                 const std::vector<double>& weights,
                                                 const std::array<double, 3>& signsFrom) {
    std::array<std::array<double, 3>, 3> m{};
    std::array<double, 3> r{};
    for (size_t i = 0; i < pts.size(); ++i) {
        const double w = weights[i];
        if (w <= 0.0) continue;
        const auto& p = pts[i];
        const double s = eval(signsFrom, p) < 0.0 ? -1.0 : 1.0;
        const std::array<double, 3> phi{1.0, p.x, p.y};
        for (int a = 0; a < 3; ++a) {
            for (int b = 0; b < 3; ++b)
                m[a][b] += w * phi[a] * phi[b];
            r[a] += w * phi[a] * s * p.b;
        }
    }
    return solve3(m, r);
}

double tukey(double r, double c) {
    const double t = r / c;
    return std::abs(t) >= 1.0 ? 0.0 : (1.0 - t * t) * (1.0 - t * t);
}

double wrapDegrees180(double deg) {
    double a = std::fmod(deg, 180.0);
    if (a < 0.0) a += 180.0;
    return a >= 180.0 ? 0.0 : a;
}

double degrees(double rad) {
    return rad * 180.0 / std::numbers::pi;
}

// The part of the line p0 + p1 x + p2 y = 0 inside [0, w] × [0, h].
std::optional<ImageSegment> clipLine(const std::array<double, 3>& p, double w, double h) {
    std::vector<std::pair<double, double>> hits;
    const auto add = [&](double x, double y) {
        if (x < -1e-9 || x > w + 1e-9 || y < -1e-9 || y > h + 1e-9) return;
        for (const auto& q : hits)
            if (std::abs(q.first - x) < 1e-9 && std::abs(q.second - y) < 1e-9) return;
        hits.emplace_back(std::clamp(x, 0.0, w), std::clamp(y, 0.0, h));
    };
    if (p[2] != 0.0) {
        add(0.0, -p[0] / p[2]);
        add(w, -(p[0] + p[1] * w) / p[2]);
    }
    if (p[1] != 0.0) {
        add(-p[0] / p[1], 0.0);
        add(-(p[0] + p[2] * h) / p[1], h);
    }
    if (hits.size() < 2) return std::nullopt;
    return ImageSegment{hits[0].first, hits[0].second, hits[1].first, hits[1].second};
}

}  // namespace

std::optional<BlurPlane> fitBlurPlane(std::span<const BlurSample> samples, int width, int height,
                                      const PlaneFitOptions& options) {
    // Work in centred, scaled coordinates so the normal equations stay well conditioned.
    const double cx = 0.5 * width, cy = 0.5 * height;
    const double scale = std::max(1.0, 0.5 * std::max(width, height));
    std::vector<Point> pts;
    for (size_t i = 0; i < samples.size(); ++i) {
        const auto& s = samples[i];
        if (!(s.weight > 0.0) || !std::isfinite(s.blur) || s.blur < 0.0 || !std::isfinite(s.x) ||
            !std::isfinite(s.y))
            continue;
        const double f = options.blurFloor;
        const double b = s.blur > f ? std::sqrt(s.blur * s.blur - f * f) : 0.0;
        pts.push_back({(s.x - cx) / scale, (s.y - cy) / scale, b, std::min(s.weight, 1.0), i,
                       f > 0.0 && s.blur <= f});
    }
    const size_t n = pts.size();
    if (n < 3) return std::nullopt;
    // With a floor, a sample at or below it is censored: it bounds the model (|model| ≤ floor,
    // in floor-removed pixels) instead of fixing it. Used when both kinds are present and at
    // least three samples are measured; otherwise every sample counts as measured.
    const double floor = options.blurFloor;
    const size_t censoredCount = static_cast<size_t>(
        std::count_if(pts.begin(), pts.end(), [](const Point& p) { return p.censored; }));
    const bool censoring = censoredCount > 0 && n - censoredCount >= 3;
    if (!censoring)
        for (auto& p : pts)
            p.censored = false;

    // (1) LMedS search over triples and sign patterns (the first sign is fixed: −q fits equally).
    // The median is unweighted on purpose: weighting it by confidence let confident wide-blur
    // regions outvote the in-focus band on the real tilted pcb stack; IRLS uses the weights.
    std::mt19937 rng(options.seed);
    std::uniform_int_distribution<size_t> pick(0, n - 1);
    std::vector<double> scratch;
    scratch.reserve(n);
    std::optional<std::array<double, 3>> best;
    double bestCost = std::numeric_limits<double>::infinity();
    for (int h = 0; h < std::max(1, options.hypotheses); ++h) {
        const size_t i = pick(rng), j = pick(rng), k = pick(rng);
        if (i == j || j == k || i == k) continue;
        const Point* t[3] = {&pts[i], &pts[j], &pts[k]};
        std::array<std::array<double, 3>, 3> m{};
        for (int r = 0; r < 3; ++r)
            m[r] = {1.0, t[r]->x, t[r]->y};
        for (int signs = 0; signs < 4; ++signs) {
            const std::array<double, 3> rhs{t[0]->b, (signs & 1) ? -t[1]->b : t[1]->b,
                                            (signs & 2) ? -t[2]->b : t[2]->b};
            const auto q = solve3(m, rhs);
            if (!q) break;  // collinear triple: no sign pattern helps
            const double cost = lmedsCost(*q, pts, floor, scratch);
            if (cost < bestCost) {
                bestCost = cost;
                best = q;
            }
        }
    }
    if (!best) {
        // Too few distinct triples were drawn (tiny inputs): try them all in order.
        for (size_t i = 0; i < n && !best; ++i)
            for (size_t j = i + 1; j < n && !best; ++j)
                for (size_t k = j + 1; k < n && !best; ++k) {
                    std::array<std::array<double, 3>, 3> m{{{1.0, pts[i].x, pts[i].y},
                                                            {1.0, pts[j].x, pts[j].y},
                                                            {1.0, pts[k].x, pts[k].y}}};
                    best = solve3(m, {pts[i].b, pts[j].b, pts[k].b});
                }
        if (!best) return std::nullopt;
    }

    // (2) IRLS with Tukey's biweight (c = 4.685 σ, 95 % efficiency), σ from the MAD.
    std::array<double, 3> q = *best;
    std::vector<double> weights(n), residuals(n);
    double sigma = 0.0;
    double meanBlur = 0.0;
    for (const auto& p : pts)
        meanBlur += p.b;
    meanBlur /= static_cast<double>(n);
    const double sigmaFloor = 1e-9 * std::max(1.0, meanBlur);
    for (int iter = 0; iter < 50; ++iter) {
        for (size_t i = 0; i < n; ++i)
            residuals[i] = residual(q, pts[i], floor);
        sigma = std::max(madSigma(residuals, pts, 1.0, scratch), sigmaFloor);
        // A censored sample within its bound adds nothing; beyond it, it pulls the model down.
        for (size_t i = 0; i < n; ++i)
            weights[i] = pts[i].censored && residuals[i] == 0.0
                             ? 0.0
                             : pts[i].w * tukey(residuals[i], 4.685 * sigma);
        const auto next = weightedFit(pts, weights, q);
        if (!next) break;
        const double change =
            std::abs((*next)[0] - q[0]) + std::abs((*next)[1] - q[1]) + std::abs((*next)[2] - q[2]);
        q = *next;
        if (change <= 1e-12 * (std::abs(q[0]) + std::abs(q[1]) + std::abs(q[2]) + 1e-300)) break;
    }

    BlurPlane out;
    // Back to pixel coordinates: q0 + q1 (x − cx)/s + q2 (y − cy)/s.
    out.p[1] = q[1] / scale;
    out.p[2] = q[2] / scale;
    out.p[0] = q[0] - out.p[1] * cx - out.p[2] * cy;
    out.gradient = std::hypot(out.p[1], out.p[2]);
    // The zero line runs perpendicular to the gradient (p1, p2).
    out.lineAngleDeg = wrapDegrees180(degrees(std::atan2(out.p[2], out.p[1])) + 90.0);
    out.inFocusLine = clipLine(out.p, width, height);
    out.samples = static_cast<int>(n);
    out.inlier.assign(samples.size(), false);
    out.fitted.assign(samples.size(), 0.0);
    for (size_t i = 0; i < samples.size(); ++i)
        out.fitted[i] = std::abs(out.signedAt(samples[i].x, samples[i].y));
    for (size_t i = 0; i < n; ++i)
        residuals[i] = residual(q, pts[i], floor);
    // LMedS scale with Rousseeuw's small-sample correction.
    const size_t measured = censoring ? n - censoredCount : n;
    out.robustSigma = std::max(
        madSigma(residuals, pts,
                 1.0 + 5.0 / std::max<double>(1.0, static_cast<double>(measured) - 3.0), scratch),
        sigmaFloor);
    double sum2 = 0.0;
    for (size_t i = 0; i < n; ++i) {
        if (std::abs(residuals[i]) > options.inlierSigmas * out.robustSigma) continue;
        out.inlier[pts[i].index] = true;
        ++out.inliers;
        sum2 += residuals[i] * residuals[i];
    }
    out.rmsResidual = out.inliers > 0 ? std::sqrt(sum2 / out.inliers) : 0.0;
    return out;
}

ScenePlane makeScenePlane(double a, double b, double c) {
    ScenePlane s;
    s.a = a;
    s.b = b;
    s.c = c;
    // The plane of focus is Z = const (normal (0, 0, 1)); the angle between the planes is the
    // angle between their normals.
    s.tiltDeg = degrees(std::atan2(std::hypot(a, b), std::abs(c)));
    s.axisAngleDeg = wrapDegrees180(degrees(std::atan2(b, a)) + 90.0);
    // Along a chief ray 1/Z = (a x + b y)/z_s + c, so depth grows fastest along −(a, b).
    double towards = degrees(std::atan2(-b, -a));
    if (towards < 0.0) towards += 360.0;
    s.recedesTowardsDeg = towards;
    s.depthOnAxis = c != 0.0 ? 1.0 / c : std::numeric_limits<double>::infinity();
    return s;
}

std::optional<std::array<ScenePlane, 2>> scenePlanes(const BlurPlane& plane,
                                                     const CameraGeometry& camera) {
    const ThinLens& lens = camera.lens;
    if (!lens.valid() || !(camera.pixelPitch > 0.0) || !std::isfinite(camera.pixelPitch))
        return std::nullopt;
    const auto zs = sensorDistanceForFocus(lens.focalLength, camera.focusDistance);
    if (!zs) return std::nullopt;
    const double aperture = lens.aperture();
    const double atCentre = plane.signedAt(camera.cx, camera.cy);
    const double inverseU = 1.0 / camera.focusDistance;
    std::array<ScenePlane, 2> out;
    for (int k = 0; k < 2; ++k) {
        const double sign = k == 0 ? 1.0 : -1.0;
        // signed_px = A z_s (1/u − c)/pitch − A a (x − cx) − A b (y − cy).
        const double a = -sign * plane.p[1] / aperture;
        const double b = -sign * plane.p[2] / aperture;
        const double c = inverseU - sign * atCentre * camera.pixelPitch / (aperture * *zs);
        out[k] = makeScenePlane(a, b, c);
    }
    return out;
}

}  // namespace infocus::optics
