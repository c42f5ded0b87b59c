// SPDX-License-Identifier: MIT
// The slanted-edge SFR (ISO 12233): the binned ESF resampled on its bins' grid, differentiated,
// windowed and Fourier-transformed at the frequencies asked for (docs/qa.md, "SFR").
#include "infocus/sfr.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace infocus {

namespace {

constexpr double kPi = std::numbers::pi;

// sin(πx)/(πx).
double sinc(double x) {
    const double a = kPi * x;
    return std::abs(a) < 1e-9 ? 1.0 : std::sin(a) / a;
}

// The window's half-width in σ of the line spread and past that in px, and the share of it
// tapered at each end. A Gaussian keeps 99.99 % of its line spread within 4 σ and a disc all of
// it within 2 σ; the taper starts beyond 3.2 σ, where noise is all that is left.
constexpr double kWindowSigmas = 4.0, kWindowPadPx = 1.5, kTaperShare = 0.2;

// The windowed line spread of an ESF on a uniform grid: d[k] between x0 + kΔ and x0 + (k+1)Δ.
struct LineSpread {
    std::vector<double> d;
    double dx = 0.0;
    double dc = 0.0;         // Σ d: the transform at 0
    double withinVar = 0.0;  // mean spread of the positions within a bin, px²
};

// Builds @p out from @p esf; false when it has no bins or no contrast.
bool lineSpread(const EsfProfile& esf, LineSpread& out) {
    const size_t n = std::min(esf.pos.size(), esf.value.size());
    if (n < 2 || !(esf.hi > esf.lo) || !(esf.binPx > 0.0)) return false;
    const double dx = esf.binPx;
    const double half = kWindowSigmas * std::max(esf.spreadPx, 0.3) + kWindowPadPx;
    const int steps = static_cast<int>(std::ceil(2.0 * half / dx));
    // The grid's points on the bins' centres (a step's ends), the centroid about its middle.
    const double x0 =
        esf.binCentrePx + std::round((esf.centrePx - 0.5 * steps * dx - esf.binCentrePx) / dx) * dx;
    out.dx = dx;
    out.d.resize(static_cast<size_t>(steps));
    // The ESF at the grid's points by linear interpolation between the bins' mean positions, the
    // plateau levels at the window's ends and beyond the bins.
    size_t j = 0;
    double prev = esf.lo, sumVar = 0.0;
    int nVar = 0;
    const double taperFrom = (1.0 - kTaperShare) * 0.5 * steps * dx;
    const double taperLen = kTaperShare * 0.5 * steps * dx;
    double dc = 0.0;
    for (int k = 1; k <= steps; ++k) {
        const double x = x0 + k * dx;
        double e;
        if (k == steps) {
            e = esf.hi;
        } else {
            while (j < n && esf.pos[j] <= x)
                ++j;
            if (j == 0)
                e = esf.lo;
            else if (j == n)
                e = esf.hi;
            else {
                const double a = esf.pos[j - 1], b = esf.pos[j];
                const double t = b > a ? (x - a) / (b - a) : 0.5;
                e = esf.value[j - 1] + t * (esf.value[j] - esf.value[j - 1]);
                if (j - 1 < esf.withinVar.size()) sumVar += esf.withinVar[j - 1], ++nVar;
            }
        }
        // Tukey window about the centroid, at the step's midpoint.
        const double r = std::abs(x - 0.5 * dx - esf.centrePx) - taperFrom;
        const double w = r <= 0.0 ? 1.0 : 0.5 * (1.0 + std::cos(kPi * std::min(r / taperLen, 1.0)));
        const double step = w * (e - prev);
        out.d[static_cast<size_t>(k - 1)] = step;
        dc += step;
        prev = e;
    }
    out.dc = dc;
    out.withinVar = nVar > 0 ? sumVar / nVar : dx * dx / 12.0;
    return dc > 0.0;
}

// The SFR of @p l at @p f: |Σ d_k e^(−2πi f kΔ)| / Σ d_k, divided by what the finite difference
// (sinc(fΔ)) and the bins' own extent (a Gaussian of their within-bin variance) take.
double response(const LineSpread& l, double f) {
    const double th = 2.0 * kPi * f * l.dx;
    const double wr = std::cos(th), wi = -std::sin(th);
    double zr = 1.0, zi = 0.0, re = 0.0, im = 0.0;
    for (const double d : l.d) {
        re += d * zr, im += d * zi;
        const double t = zr * wr - zi * wi;
        zi = zr * wi + zi * wr;
        zr = t;
    }
    const double m = std::hypot(re, im) / l.dc;
    return m / sinc(f * l.dx) * std::exp(2.0 * kPi * kPi * f * f * l.withinVar);
}

// The frequency in (a, b] where @p l's response falls to @p level, given r(a) > level ≥ r(b):
// regula falsi with the Illinois step, to 1e-4 cy/px.
double solve(const LineSpread& l, double a, double ra, double b, double rb, double level) {
    int side = 0;
    for (int i = 0; i < 40 && b - a > 1e-4; ++i) {
        const double c = b - (rb - level) * (b - a) / (rb - ra);
        const double rc = response(l, c);
        if (rc > level) {
            a = c, ra = rc;
            if (side == -1) rb = level + 0.5 * (rb - level);
            side = -1;
        } else {
            b = c, rb = rc;
            if (side == 1) ra = level + 0.5 * (ra - level);
            side = 1;
        }
    }
    return 0.5 * (a + b);
}

}  // namespace

double sfrAt(const EsfProfile& esf, double cyPx) {
    LineSpread l;
    if (!lineSpread(esf, l)) return std::nan("");
    return response(l, cyPx);
}

std::optional<Mtf50> mtf50FromEsf(const EsfProfile& esf) {
    thread_local LineSpread l;
    if (!lineSpread(esf, l)) return std::nullopt;
    // Start at a Gaussian's MTF50 for the spread (√(ln 2 / 2) / (π σ)), then step out by half
    // again until the response is under 0.5: a disc's first zero lies beyond 1.7 times that.
    const double guess = 0.18739 / std::max(esf.spreadPx, 0.2);
    double a = 0.0, ra = 1.0;
    double b = std::min(guess, kMaxSfrCyPx), rb = response(l, b);
    while (rb > 0.5) {
        if (b >= kMaxSfrCyPx) return std::nullopt;
        a = b, ra = rb;
        b = std::min(1.5 * b, kMaxSfrCyPx);
        rb = response(l, b);
    }
    Mtf50 out;
    out.mtf50CyPx = solve(l, a, ra, b, rb, 0.5);
    // The peak on a coarse scan below MTF50: above 1 only where the edge was sharpened.
    double peak = 1.0, at = 0.0;
    for (int k = 1; k <= 4; ++k) {
        const double f = 0.2 * k * out.mtf50CyPx;
        const double r = response(l, f);
        if (r > peak) peak = r, at = f;
    }
    out.mtf50pCyPx =
        peak > 1.0 ? solve(l, at, peak, out.mtf50CyPx, 0.5, 0.5 * peak) : out.mtf50CyPx;
    return out;
}

double gaussianMtf(double cyPx, double sigmaPx) {
    return std::exp(-2.0 * kPi * kPi * sigmaPx * sigmaPx * cyPx * cyPx);
}

double discMtf(double cyPx, double diameterPx) {
    const double x = kPi * diameterPx * cyPx;
    return x < 1e-9 ? 1.0 : 2.0 * std::cyl_bessel_j(1.0, x) / x;
}

double pixelMtf(double cyPx, double angleDeg) {
    const double th = angleDeg * kPi / 180.0;
    return sinc(cyPx * std::cos(th)) * sinc(cyPx * std::sin(th));
}

}  // namespace infocus
