// SPDX-License-Identifier: MIT
// Synthetic optics: analytic edges, painted scenes, PSF convolution and pixel-area integration.
#include "infocus/synth.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "rng.h"

namespace infocus::synth {

namespace {

constexpr double kPi = std::numbers::pi;

double normalCdf(double z) {
    return 0.5 * std::erfc(-z / std::numbers::sqrt2);
}
double normalPdf(double z) {
    return std::exp(-0.5 * z * z) / std::sqrt(2.0 * kPi);
}

// The core of @p psf alone (no halo).
Psf coreOf(const Psf& psf) {
    Psf c = psf;
    c.haloFraction = 0.0;
    return c;
}

// The halo of @p psf as a Gaussian PSF of its own.
Psf haloOf(const Psf& psf) {
    return Psf::gaussian(psf.haloSigmaPx());
}

bool hasHalo(const Psf& psf) {
    return psf.haloFraction > 0.0 && psf.sizePx > 0.0;
}

// Edge spread of a disc of radius r with spherical aberration k (intensity ∝ 1 + k(2ρ² − 1)),
// t = u/r in −1..1, s = √(1 − t²): its projection is (2s/π)(1 − k/3 + 4k t²/3), integrated with
// ∫s = (ts + asin t)/2 and ∫t²s = (asin t − ts(1 − 2t²))/8.
double aberratedDiscSpread(double t, double k) {
    const double s = std::sqrt(std::max(0.0, 1.0 - t * t)), as = std::asin(t);
    const double a = 1.0 - k / 3.0, b = k / 6.0;
    return 2.0 / kPi *
           (a * (0.5 * (t * s + as) + 0.25 * kPi) +
            b * (as - t * s * (1.0 - 2.0 * t * t) + 0.5 * kPi));
}

// Antiderivative of the core's edge spread, G(u) = ∫_{-∞}^{u} ESF(t) dt, so that the mean of the
// ESF over an interval is exact: used to integrate a pixel analytically along one axis.
double coreSpreadIntegral(const Psf& psf, double u) {
    if (psf.sizePx <= 0.0) return std::max(u, 0.0);
    if (psf.shape == PsfShape::Gaussian) {
        // ∫ Φ(t/σ) dt = t Φ(t/σ) + σ φ(t/σ)
        const double s = psf.sizePx;
        return u * normalCdf(u / s) + s * normalPdf(u / s);
    }
    const double r = 0.5 * psf.sizePx;
    if (u <= -r) return 0.0;
    if (u >= r) return u;
    if (psf.rimWeight == 0.0) {
        // ∫ of the semicircle CDF 1/2 + (t√(r²−t²) + r² asin(t/r))/(π r²), from −r to u.
        const double q = std::sqrt(std::max(0.0, r * r - u * u));
        const double r2 = r * r;
        return 0.5 * (u + r) +
               (-q * q * q / 3.0 + r2 * u * std::asin(u / r) + r2 * q - r2 * r * kPi / 2.0) /
                   (kPi * r2);
    }
    // ∫ of aberratedDiscSpread from −1 to t, with ∫ts = −s³/3, ∫asin t = t asin t + s and
    // ∫t³s = −s³/3 + s⁵/5; both parts vanish at t = −1 and reach t at t = 1.
    const double t = u / r, k = psf.rimWeight;
    const double s = std::sqrt(std::max(0.0, 1.0 - t * t)), as = std::asin(t);
    const double s3 = s * s * s;
    const double a = 1.0 - k / 3.0, b = k / 6.0;
    const double pa = -s3 / 6.0 + 0.5 * (t * as + s) + 0.25 * kPi * t;
    const double pb = t * as + s - s3 / 3.0 + 0.4 * s3 * s * s + 0.5 * kPi * t;
    return r * 2.0 / kPi * (a * pa + b * pb);
}

// The same for the whole PSF: the core and the halo mixed in their shares.
double edgeSpreadIntegral(const Psf& psf, double u) {
    if (!hasHalo(psf)) return coreSpreadIntegral(psf, u);
    const double f = psf.haloFraction;
    return (1.0 - f) * coreSpreadIntegral(psf, u) + f * coreSpreadIntegral(haloOf(psf), u);
}

// Kernel of @p psf integrated over cells of 1/@p cellsPerPx pixels, normalised to sum 1.
cv::Mat psfKernel(const Psf& psf, int cellsPerPx) {
    const double scale = cellsPerPx;
    if (psf.shape == PsfShape::Gaussian) {
        // Separable: the cell integral of a 1-D Gaussian is a difference of Φ. Returned as a
        // 1-column kernel; the caller applies it along both axes.
        const double s = psf.sizePx * scale;
        const int half = static_cast<int>(std::ceil(5.0 * s + 1.0));
        cv::Mat k(2 * half + 1, 1, CV_32F);
        double sum = 0.0;
        for (int i = -half; i <= half; ++i) {
            const double v = normalCdf((i + 0.5) / s) - normalCdf((i - 0.5) / s);
            k.at<float>(i + half) = static_cast<float>(v);
            sum += v;
        }
        return k / sum;
    }
    const double r = 0.5 * psf.sizePx * scale;
    const int half = static_cast<int>(std::ceil(r + 0.5));
    cv::Mat k(2 * half + 1, 2 * half + 1, CV_32F);
    // Area of the disc inside each cell, by 16 × 16 sub-cells.
    double sum = 0.0;
    for (int j = -half; j <= half; ++j) {
        for (int i = -half; i <= half; ++i) {
            // Spherical aberration weighs the covered area by the intensity at the cell's
            // centre, 1 + k(2ρ² − 1), ρ capped at the rim.
            const double rho2 = std::min(1.0, (i * i + j * j) / (r * r));
            const double v =
                discPixelCoverage(i, j, r, 16) * (1.0 + psf.rimWeight * (2.0 * rho2 - 1.0));
            k.at<float>(j + half, i + half) = static_cast<float>(v);
            sum += v;
        }
    }
    if (sum <= 0.0) {  // a disc far below one cell: a point
        k.setTo(0.0f);
        k.at<float>(half, half) = 1.0f;
        return k;
    }
    return k / sum;
}

cv::Mat wrap(Image<float>& img) {
    return cv::Mat(img.height(), img.width(), CV_32F, img.data());
}

// Convolves @p src (fine samples) with the core of @p psf alone at @p cellsPerPx cells per
// pixel, borders replicated (a scene extends past the frame rather than turning black).
void convolveCore(const cv::Mat& src, cv::Mat& dst, const Psf& psf, int cellsPerPx) {
    if (psf.sizePx <= 0.0) {
        src.copyTo(dst);
        return;
    }
    const cv::Mat k = psfKernel(psf, cellsPerPx);
    if (psf.shape == PsfShape::Gaussian)
        cv::sepFilter2D(src, dst, CV_32F, k, k, cv::Point(-1, -1), 0.0, cv::BORDER_REPLICATE);
    else
        cv::filter2D(src, dst, CV_32F, k, cv::Point(-1, -1), 0.0, cv::BORDER_REPLICATE);
}

// The same with the halo: the core's and the halo's images mixed in their shares (the PSF is
// their sum, and convolution is linear).
void convolve(const cv::Mat& src, cv::Mat& dst, const Psf& psf, int cellsPerPx) {
    convolveCore(src, dst, coreOf(psf), cellsPerPx);
    if (!hasHalo(psf)) return;
    cv::Mat halo;
    convolveCore(src, halo, haloOf(psf), cellsPerPx);
    cv::addWeighted(dst, 1.0 - psf.haloFraction, halo, psf.haloFraction, 0.0, dst);
}

}  // namespace

double Psf::sigmaPx() const {
    if (shape == PsfShape::Gaussian) return sizePx;
    // Projection variance of a radial intensity is E[r²]/2 = R²(3 + k)/12 (k = 0: d²/16).
    return sizePx * std::sqrt((3.0 + rimWeight) / 48.0);
}

double Psf::discDiameterPx() const {
    // A disc's projection is a semicircle of variance r²/4 = d²/16, so equal moments: d = 4σ.
    return 4.0 * sigmaPx();
}

double Psf::edgeRisePx() const {
    if (shape == PsfShape::Gaussian) return 2.5631 * sizePx;
    if (rimWeight == 0.0) return 0.68705 * sizePx;
    // The 10 % and 90 % crossings of the aberrated disc's spread, by bisection in t = u/r.
    auto crossing = [k = rimWeight](double level) {
        double lo = -1.0, hi = 1.0;
        for (int i = 0; i < 60; ++i) {
            const double mid = 0.5 * (lo + hi);
            (aberratedDiscSpread(mid, k) < level ? lo : hi) = mid;
        }
        return 0.5 * (lo + hi);
    };
    return 0.5 * sizePx * (crossing(0.9) - crossing(0.1));
}

double edgeSpread(const Psf& psf, double u) {
    if (hasHalo(psf)) {
        const double f = psf.haloFraction;
        return (1.0 - f) * edgeSpread(coreOf(psf), u) + f * edgeSpread(haloOf(psf), u);
    }
    if (psf.sizePx <= 0.0) return u < 0.0 ? 0.0 : (u > 0.0 ? 1.0 : 0.5);
    if (psf.shape == PsfShape::Gaussian) return normalCdf(u / psf.sizePx);
    const double r = 0.5 * psf.sizePx;
    if (u <= -r) return 0.0;
    if (u >= r) return 1.0;
    if (psf.rimWeight != 0.0) return aberratedDiscSpread(u / r, psf.rimWeight);
    return 0.5 + (u * std::sqrt(r * r - u * u) + r * r * std::asin(u / r)) / (kPi * r * r);
}

SynthImage renderEdge(int width, int height, const Edge& edge, const Imaging& imaging) {
    SynthImage out{Image<float>(width, height), imaging.psf, imaging.noiseSigma};
    const double th = edge.angleDeg * kPi / 180.0;
    const double nx = std::cos(th), ny = std::sin(th);
    // Integrate analytically (through G = ∫ESF) along the axis where the normal is steeper, and
    // by the midpoint rule along the other: exact for axis-aligned edges, and the residual
    // sampling variance is below (1/12)/n² px² otherwise.
    const bool alongX = std::abs(nx) >= std::abs(ny);
    const double ca = alongX ? nx : ny;  // normal component on the analytic axis
    const double cb = alongX ? ny : nx;  // ... and on the sampled axis
    const int n = std::max(1, imaging.supersample * 2);
    const float contrast = edge.bright - edge.dark;
    for (int y = 0; y < height; ++y) {
        float* row = out.pixels.row(y);
        for (int x = 0; x < width; ++x) {
            const double s0 = (x + 0.5 - edge.cx) * nx + (y + 0.5 - edge.cy) * ny - edge.offsetPx;
            double acc = 0.0;
            for (int b = 0; b < n; ++b) {
                const double s = s0 + (-0.5 + (b + 0.5) / n) * cb;
                acc += (edgeSpreadIntegral(imaging.psf, s + 0.5 * std::abs(ca)) -
                        edgeSpreadIntegral(imaging.psf, s - 0.5 * std::abs(ca))) /
                       std::abs(ca);
            }
            row[x] = edge.dark + contrast * static_cast<float>(acc / n);
        }
    }
    if (imaging.noiseSigma > 0.0) addNoise(out.pixels, imaging.noiseSigma, imaging.seed);
    return out;
}

Scene edgeScene(const Edge& edge) {
    const double th = edge.angleDeg * kPi / 180.0;
    const double nx = std::cos(th), ny = std::sin(th);
    return [=](double x, double y) {
        const double s = (x - edge.cx) * nx + (y - edge.cy) * ny - edge.offsetPx;
        return s >= 0.0 ? edge.bright : edge.dark;
    };
}

Scene squareScene(double cx, double cy, double sidePx, double angleDeg, float value) {
    const double th = angleDeg * kPi / 180.0;
    const double c = std::cos(th), s = std::sin(th), h = 0.5 * sidePx;
    return [=](double x, double y) {
        const double u = (x - cx) * c + (y - cy) * s;
        const double v = -(x - cx) * s + (y - cy) * c;
        return (std::abs(u) <= h && std::abs(v) <= h) ? value
                                                      : std::numeric_limits<float>::quiet_NaN();
    };
}

Scene checkerboardScene(double cellPx, double angleDeg, float dark, float bright) {
    const double th = angleDeg * kPi / 180.0;
    const double c = std::cos(th), s = std::sin(th);
    return [=](double x, double y) {
        const auto u = static_cast<long long>(std::floor((x * c + y * s) / cellPx));
        const auto v = static_cast<long long>(std::floor((-x * s + y * c) / cellPx));
        return ((u + v) & 1) ? bright : dark;
    };
}

Scene slantedEdgeChartScene(double pitchPx, double angleDeg, float dark, float bright) {
    const double th = angleDeg * kPi / 180.0;
    const double c = std::cos(th), s = std::sin(th), h = 0.25 * pitchPx;
    return [=](double x, double y) {
        // Each pitch cell holds one square about the cell centre, rotated by the chart angle.
        const double cx = (std::floor(x / pitchPx) + 0.5) * pitchPx;
        const double cy = (std::floor(y / pitchPx) + 0.5) * pitchPx;
        const double u = (x - cx) * c + (y - cy) * s;
        const double v = -(x - cx) * s + (y - cy) * c;
        return (std::abs(u) <= h && std::abs(v) <= h) ? dark : bright;
    };
}

SharpCanvas makeCanvas(int width, int height, int supersample, float background) {
    const int k = std::max(1, supersample);
    return SharpCanvas{Image<float>(width * k, height * k, background), k};
}

void paint(SharpCanvas& canvas, const Scene& scene) {
    const double step = 1.0 / canvas.supersample;
    for (int j = 0; j < canvas.fine.height(); ++j) {
        float* row = canvas.fine.row(j);
        const double y = (j + 0.5) * step;
        for (int i = 0; i < canvas.fine.width(); ++i) {
            const float v = scene((i + 0.5) * step, y);
            if (!std::isnan(v)) row[i] = v;
        }
    }
}

void paintDeadLeaves(SharpCanvas& canvas, uint64_t seed, double minRadiusPx, double maxRadiusPx,
                     float lo, float hi) {
    Rng rng(seed);
    const double k = canvas.supersample;
    const double w = canvas.width(), h = canvas.height();
    const double a = 1.0 / (minRadiusPx * minRadiusPx), b = 1.0 / (maxRadiusPx * maxRadiusPx);
    // E[r²] for a density ∝ r⁻³ on [rmin, rmax]; paint enough discs to cover the frame about five
    // times over, leaving e⁻⁵ ≈ 0.7 % of the background uncovered.
    const double meanR2 = std::log(maxRadiusPx / minRadiusPx) / (0.5 * (a - b));
    const auto count =
        static_cast<long>(5.0 * (w + 2 * maxRadiusPx) * (h + 2 * maxRadiusPx) / (kPi * meanR2));
    for (long n = 0; n < count; ++n) {
        const double r = 1.0 / std::sqrt(a - rng.uniform() * (a - b));  // inverse CDF
        const double cx = -maxRadiusPx + rng.uniform() * (w + 2 * maxRadiusPx);
        const double cy = -maxRadiusPx + rng.uniform() * (h + 2 * maxRadiusPx);
        const auto v = static_cast<float>(lo + rng.uniform() * (hi - lo));
        const int j0 = std::max(0, static_cast<int>(std::floor((cy - r) * k)));
        const int j1 =
            std::min(canvas.fine.height() - 1, static_cast<int>(std::ceil((cy + r) * k)));
        const int i0 = std::max(0, static_cast<int>(std::floor((cx - r) * k)));
        const int i1 = std::min(canvas.fine.width() - 1, static_cast<int>(std::ceil((cx + r) * k)));
        for (int j = j0; j <= j1; ++j) {
            const double dy = (j + 0.5) / k - cy;
            float* row = canvas.fine.row(j);
            for (int i = i0; i <= i1; ++i) {
                const double dx = (i + 0.5) / k - cx;
                if (dx * dx + dy * dy <= r * r) row[i] = v;
            }
        }
    }
}

SharpCanvas deadLeavesWithSquares(int width, int height) {
    SharpCanvas canvas = makeCanvas(width, height, 2);
    paintDeadLeaves(canvas, 2024, 4.0, 120.0);
    for (int i = 0; i < 12; ++i)
        paint(canvas, squareScene(160.0 + 140.0 * i, 200.0 + 60.0 * (i % 5), 90.0, 5.0 + 7.0 * i,
                                  i % 2 ? 30.0f : 220.0f));
    return canvas;
}

SynthImage renderSharp(const SharpCanvas& canvas, const Imaging& imaging) {
    const int k = canvas.supersample;
    Image<float> fine = canvas.fine;  // shares pixels: only read below
    const cv::Mat src(fine.height(), fine.width(), CV_32F, const_cast<float*>(fine.data()));
    cv::Mat blurred;
    convolve(src, blurred, imaging.psf, k);
    SynthImage out{Image<float>(canvas.width(), canvas.height()), imaging.psf, imaging.noiseSigma};
    cv::Mat dst = wrap(out.pixels);
    if (k == 1)
        blurred.copyTo(dst);
    else  // INTER_AREA at an integer factor is the exact k × k box mean: pixel-area integration
        cv::resize(blurred, dst, dst.size(), 0, 0, cv::INTER_AREA);
    if (imaging.noiseSigma > 0.0) addNoise(out.pixels, imaging.noiseSigma, imaging.seed);
    return out;
}

Image<float> blurImage(const Image<float>& image, const Psf& psf) {
    Image<float> out(image.width(), image.height());
    const cv::Mat src(image.height(), image.width(), CV_32F, const_cast<float*>(image.data()));
    cv::Mat dst = wrap(out);
    cv::Mat tmp;
    convolve(src, tmp, psf, 1);
    tmp.copyTo(dst);
    return out;
}

Image<uint8_t> blurImage(const Luma8& image, const Psf& psf) {
    return toLuma8(blurImage(toFloat(image), psf));
}

void addNoise(Image<float>& image, double sigma, uint64_t seed) {
    Rng rng(seed ^ 0xA5A5A5A5DEADBEEFull);
    for (int y = 0; y < image.height(); ++y) {
        float* row = image.row(y);
        for (int x = 0; x < image.width(); ++x)
            row[x] += static_cast<float>(sigma * rng.normal());
    }
}

Image<uint8_t> toLuma8(const Image<float>& image) {
    Image<uint8_t> out(image.width(), image.height());
    for (int y = 0; y < image.height(); ++y) {
        const float* src = image.row(y);
        uint8_t* dst = out.row(y);
        for (int x = 0; x < image.width(); ++x)
            dst[x] = static_cast<uint8_t>(std::clamp(std::lround(src[x]), 0l, 255l));
    }
    return out;
}

Image<float> toFloat(const Luma8& image) {
    Image<float> out(image.width, image.height);
    for (int y = 0; y < image.height; ++y) {
        const uint8_t* src = image.row(y);
        float* dst = out.row(y);
        for (int x = 0; x < image.width; ++x)
            dst[x] = src[x];
    }
    return out;
}

}  // namespace infocus::synth
