// SPDX-License-Identifier: MIT
// The slanted-edge SFR (ISO 12233): the binned ESF resampled on its bins' grid, differentiated,
// windowed and Fourier-transformed at the frequencies asked for (docs/qa.md, "SFR").
#include "infocus/sfr.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace infocus {

namespace {

constexpr double kPi = std::numbers::pi;

// The Taylor coefficients of sin a / a and cos a in powers of a²: (−1)^k/(2k+1)! and (−1)^k/(2k)!.
constexpr auto kTaylor = [] {
    std::array<double, 15> f{};  // n!
    f[0] = 1.0;
    for (size_t n = 1; n < f.size(); ++n)
        f[n] = f[n - 1] * static_cast<double>(n);
    std::array<std::array<double, 8>, 2> t{};  // [0]: sine's 7 terms, [1]: cosine's 8
    for (size_t k = 0; k < 8; ++k) {
        const double sign = k % 2 ? -1.0 : 1.0;
        if (k < 7) t[0][k] = sign / f[2 * k + 1];
        t[1][k] = sign / f[2 * k];
    }
    return t;
}();

// Two doubles in one SSE2 register (GCC's and Clang's vector extension): the transforms below
// run their independent rotators two lanes at a time.
using V2 = double __attribute__((vector_size(16)));

// sin(πx)/(πx).
double sinc(double x) {
    const double a = kPi * x;
    return std::abs(a) < 1e-9 ? 1.0 : std::sin(a) / a;
}

// The window's half-width in σ of the line spread and past that in px, and the share of it
// tapered at each end. A Gaussian keeps 99.99 % of its line spread within 4 σ and a disc all of
// it within 2 σ; the taper starts beyond 3.2 σ, where noise is all that is left.
constexpr double kWindowSigmas = 4.0, kWindowPadPx = 1.0, kTaperShare = 0.2;

// sin and cos of @p a. A response costs one of each and an exponential, which from libm take as
// long as its transform; a transform's angle πfΔ stays within ±π/4 (f ≤ 1 cy/px, Δ = 0.25 px),
// where Taylor series to a¹³ and a¹⁴ are exact to 3e-14. Wider angles take libm's.
void sinCos(double a, double& s, double& c) {
    if (std::abs(a) > 0.7854) {
        s = std::sin(a), c = std::cos(a);
        return;
    }
    // Horner from the highest term.
    const double a2 = a * a;
    double ps = 0.0, pc = 0.0;
    for (int k = 6; k >= 0; --k)
        ps = kTaylor[0][static_cast<size_t>(k)] + a2 * ps;
    for (int k = 7; k >= 0; --k)
        pc = kTaylor[1][static_cast<size_t>(k)] + a2 * pc;
    s = a * ps, c = pc;
}

// e^x for the bins' Gaussian, whose exponent 2π²f²v stays under 0.11 (v ≤ Δ²/12): the series to
// x¹² there is exact to 1e-17 relative; larger exponents take libm's.
double expSmall(double x) {
    if (!(std::abs(x) <= 0.5)) return std::exp(x);
    double term = 1.0, sum = 1.0;
    for (int k = 1; k <= 12; ++k) {
        term *= x / k;
        sum += term;
    }
    return sum;
}

// Builds @p out from @p esf; false when it has no bins or no contrast.
bool buildLineSpread(const EsfProfile& esf, LineSpread& out) {
    const size_t n = std::min(esf.pos.size(), esf.value.size());
    if (n < 2 || !(esf.hi > esf.lo) || !(esf.binPx > 0.0)) return false;
    const double dx = esf.binPx;
    const double half = kWindowSigmas * std::max(esf.spreadPx, 0.3) + kWindowPadPx;
    const int steps = static_cast<int>(std::ceil(2.0 * half / dx));
    // The grid's points on the bins' centres (a step's ends), the centroid about its middle.
    const double m0 = std::round((esf.centrePx - 0.5 * steps * dx - esf.binCentrePx) / dx);
    const double x0 = esf.binCentrePx + m0 * dx;
    out.dx = dx;
    out.spreadPx = esf.spreadPx;
    out.d.resize(static_cast<size_t>(steps));
    // The ESF at the grid's points by linear interpolation between the bins' mean positions, the
    // plateau levels at the window's ends and beyond the bins.
    size_t j = 0;
    // Where no bin is empty (an edge off 0° and 45°), bin b is the grid point b − first's own and
    // the first bin past that point is b or b + 1: read without a loop whose trip count, 0 to 2
    // at random, costs a mispredicted branch a step. Points near the bins' ends take the loop.
    const auto binOf = [&](double p) { return std::floor((p - esf.binCentrePx) / dx + 0.5); };
    const double first = binOf(esf.pos[0]);
    const bool dense = binOf(esf.pos[n - 1]) - first == static_cast<double>(n - 1);
    const long offset = static_cast<long>(m0 - first);
    double prev = esf.lo, sumVar = 0.0;
    int nVar = 0;
    const double taperFrom = (1.0 - kTaperShare) * 0.5 * steps * dx;
    const double taperLen = kTaperShare * 0.5 * steps * dx;
    const double perTaper = 1.0 / taperLen;
    // Σ|step| rather than Σ min(step, 0): noise in the tails flips a step's sign at random, and
    // the magnitude takes no branch.
    double dc = 0.0, magnitude = 0.0;
    for (int k = 1; k <= steps; ++k) {
        const double x = x0 + k * dx;
        double e;
        if (k == steps) {
            e = esf.hi;
        } else {
            const long b = offset + k;
            if (dense && b >= 1 && b + 2 <= static_cast<long>(n)) {
                j = static_cast<size_t>(b) + (esf.pos[static_cast<size_t>(b)] <= x ? 1 : 0);
            } else {
                while (j < n && esf.pos[j] <= x)
                    ++j;
            }
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
        // A flat window about the centroid whose outer fifth falls linearly to 0 (no
        // transcendental per step: this runs for every edge measured).
        const double r = std::abs(x - 0.5 * dx - esf.centrePx) - taperFrom;
        const double w = r <= 0.0 ? 1.0 : std::max(0.0, 1.0 - r * perTaper);
        const double step = w * (e - prev);
        out.d[static_cast<size_t>(k - 1)] = static_cast<float>(step);
        dc += step;
        magnitude += std::abs(step);
        prev = e;
    }
    out.dc = dc;
    out.negative = 0.5 * (dc - magnitude);
    out.withinVar = nVar > 0 ? sumVar / nVar : dx * dx / 12.0;
    return dc > 0.0;
}

// The SFR from the transform (@p re, @p im) of @p l at πfΔ = @p a (sin a = @p sa): its
// magnitude over the sum, divided by the difference's sinc and by the bins' own Gaussian,
// whose inverse is @p gauss.
double corrected(const LineSpread& l, double re, double im, double a, double sa, double gauss) {
    const double sinc = std::abs(a) < 1e-9 ? 1.0 : sa / a;
    return std::sqrt(re * re + im * im) / l.dc / sinc * gauss;
}

// The SFR of @p l at @p f: |Σ d_k e^(−2πi f kΔ)| / Σ d_k, divided by what the finite difference
// (sinc(fΔ)) and the bins' own extent (a Gaussian of their within-bin variance) take.
double response(const LineSpread& l, double f) {
    // Four rotators, each stepping 4Δ over every fourth sample: the sum is the same, and the
    // four chains of complex products run side by side instead of one after another.
    // One sine and cosine of πfΔ give both the rotation by 2πfΔ and the difference's sinc.
    const double a = kPi * f * l.dx;
    double sa, ca;
    sinCos(a, sa, ca);
    const double c1 = 1.0 - 2.0 * sa * sa, s1 = -2.0 * sa * ca;
    const double c2 = c1 * c1 - s1 * s1, s2 = 2.0 * c1 * s1;
    const double c3 = c2 * c1 - s2 * s1, s3 = c2 * s1 + s2 * c1;
    const double c4 = c2 * c2 - s2 * s2, s4 = 2.0 * c2 * s2;
    // Rotators 0 and 1 in one pair of lanes, 2 and 3 in the other: each lane's arithmetic is
    // what a scalar loop does, two at a time.
    V2 zrA{1.0, c1}, zrB{c2, c3}, ziA{0.0, s1}, ziB{s2, s3};
    V2 reA{}, reB{}, imA{}, imB{};
    const V2 cc{c4, c4}, ss{s4, s4};
    const size_t n = l.d.size(), whole = n & ~size_t{3};
    const float* d = l.d.data();
    for (size_t k = 0; k < whole; k += 4) {
        const V2 vA{d[k], d[k + 1]}, vB{d[k + 2], d[k + 3]};
        reA += vA * zrA, imA += vA * ziA;
        reB += vB * zrB, imB += vB * ziB;
        const V2 tA = zrA * cc - ziA * ss, tB = zrB * cc - ziB * ss;
        ziA = zrA * ss + ziA * cc, ziB = zrB * ss + ziB * cc;
        zrA = tA, zrB = tB;
    }
    double re[4] = {reA[0], reA[1], reB[0], reB[1]}, im[4] = {imA[0], imA[1], imB[0], imB[1]};
    const double zr[4] = {zrA[0], zrA[1], zrB[0], zrB[1]}, zi[4] = {ziA[0], ziA[1], ziB[0], ziB[1]};
    for (size_t k = whole; k < n; ++k) {
        const size_t j = k - whole;
        re[j] += d[k] * zr[j], im[j] += d[k] * zi[j];
    }
    const double sr = (re[0] + re[1]) + (re[2] + re[3]), si = (im[0] + im[1]) + (im[2] + im[3]);
    return corrected(l, sr, si, a, sa, expSmall(2.0 * kPi * kPi * f * f * l.withinVar));
}

// The responses at f, 2f, 3f and 4f in one pass: four rotators, one per frequency, whose steps
// are powers of the first; one sine, cosine and exponential serve all four.
std::array<double, 4> responses4(const LineSpread& l, double f) {
    const double a = kPi * f * l.dx;
    double sa, ca;
    sinCos(a, sa, ca);
    std::array<double, 4> wr{}, wi{};
    wr[0] = 1.0 - 2.0 * sa * sa, wi[0] = -2.0 * sa * ca;
    for (int k = 1; k < 4; ++k)
        wr[k] = wr[k - 1] * wr[0] - wi[k - 1] * wi[0],
        wi[k] = wr[k - 1] * wi[0] + wi[k - 1] * wr[0];
    // Frequencies 1 and 2 in one pair of lanes, 3 and 4 in the other.
    const V2 wrA{wr[0], wr[1]}, wrB{wr[2], wr[3]}, wiA{wi[0], wi[1]}, wiB{wi[2], wi[3]};
    V2 zrA{1.0, 1.0}, zrB{1.0, 1.0}, ziA{}, ziB{}, reA{}, reB{}, imA{}, imB{};
    for (const float v : l.d) {
        const V2 d{v, v};
        reA += d * zrA, imA += d * ziA;
        reB += d * zrB, imB += d * ziB;
        const V2 tA = zrA * wrA - ziA * wiA, tB = zrB * wrB - ziB * wiB;
        ziA = zrA * wiA + ziA * wrA, ziB = zrB * wiB + ziB * wrB;
        zrA = tA, zrB = tB;
    }
    const double re[4] = {reA[0], reA[1], reB[0], reB[1]}, im[4] = {imA[0], imA[1], imB[0], imB[1]};
    std::array<double, 4> out{};
    const double e1 = expSmall(2.0 * kPi * kPi * f * f * l.withinVar);
    double e = 1.0, sk = sa, ck = ca;
    for (int k = 0; k < 4; ++k) {
        for (int i = 0; i < 2 * k + 1; ++i)
            e *= e1;  // e1^((k + 1)²): the exponent grows with the frequency squared
        // sin((k + 1)a) by the angle sum from sin a and cos a: no libm call per harmonic.
        const double ak = (k + 1) * a;
        out[static_cast<size_t>(k)] = corrected(l, re[k], im[k], ak, sk, e);
        const double next = sk * ca + ck * sa;
        ck = ck * ca - sk * sa, sk = next;
    }
    return out;
}

// The frequency in (a, b] where @p l's response falls to @p level, given r(a) > level ≥ r(b):
// regula falsi with the Illinois step, to 0.05 % of the frequency.
double solve(const LineSpread& l, double a, double ra, double b, double rb, double level) {
    int side = 0;
    for (int i = 0; i < 40 && b - a > 5e-4 * b; ++i) {
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

std::optional<LineSpread> lineSpreadOf(const EsfProfile& esf) {
    LineSpread l;
    if (!buildLineSpread(esf, l)) return std::nullopt;
    return l;
}

double sfrAt(const LineSpread& l, double cyPx) {
    return l.d.empty() || !(l.dc > 0) ? std::nan("") : response(l, cyPx);
}

double sfrAt(const EsfProfile& esf, double cyPx) {
    LineSpread l;
    if (!buildLineSpread(esf, l)) return std::nan("");
    return response(l, cyPx);
}

std::optional<Mtf50> mtf50Of(const LineSpread& l) {
    if (l.d.empty() || !(l.dc > 0)) return std::nullopt;
    // A Gaussian's SFR is e^(−k f²): from its MTF50 guess √(ln 2 / 2) / (π σ), and each step
    // solves −ln r = c f^p through the last two responses (p = 2 at first), which lands on a
    // Gaussian's MTF50 at once and on a disc's or a real edge's in two or three; a bracket and
    // regula falsi take over where it does not settle.
    double f = std::min(0.18739 / std::max(l.spreadPx, 0.2), kMaxSfrCyPx);
    double a = 0.0, ra = 1.0;   // the highest frequency seen above 0.5
    double b = 0.0, rb = 0.0;   // the lowest seen at or below it (b = 0: none)
    double pf = 0.0, pr = 0.0;  // the previous step's frequency and response (pf = 0: none)
    double plr = 0.0;           // ln pr
    Mtf50 out;
    bool settled = false;
    for (int i = 0; i < 6; ++i) {
        const double r = response(l, f);
        if (std::abs(r - 0.5) < 2.5e-4) {
            out.mtf50CyPx = f;
            settled = true;
            break;
        }
        if (r > 0.5 && f > a) a = f, ra = r;
        if (r <= 0.5 && (b == 0.0 || f < b)) b = f, rb = r;
        if (!(r > 0.0 && r < 1.0)) break;
        const double lr = std::log(r);
        double power = 2.0;
        if (pf > 0.0 && pr > 0.0 && pr < 1.0 && std::abs(f - pf) > 1e-6 * f) {
            const double q = std::log(lr / plr) / std::log(f / pf);
            if (std::isfinite(q)) power = std::clamp(q, 0.5, 4.0);
        }
        const double next = f * std::exp(std::log(std::numbers::ln2 / -lr) / power);
        pf = f, pr = r, plr = lr;
        if (!(next > 0.0) || next > kMaxSfrCyPx) break;
        f = next;
    }
    if (!settled) {
        if (b > 0.0 && a >= b) a = 0.0, ra = 1.0;  // not monotonic there: from 0
        if (b == 0.0) {
            // Step out from the highest frequency above 0.5 until the response falls.
            b = std::min(std::max(1.5 * a, 0.01), kMaxSfrCyPx);
            rb = response(l, b);
            while (rb > 0.5) {
                if (b >= kMaxSfrCyPx) return std::nullopt;
                a = b, ra = rb;
                b = std::min(1.5 * b, kMaxSfrCyPx);
                rb = response(l, b);
            }
        }
        out.mtf50CyPx = solve(l, a, ra, b, rb, 0.5);
    }
    // The peak on a coarse scan below MTF50: above 1 only where the line spread has negative
    // lobes (a sharpened edge, or noise in its tails); a line spread without them has its
    // peak at 0, where MTF50P is MTF50.
    double peak = 1.0, at = 0.0;
    if (l.negative < -0.005 * l.dc) {
        const std::array<double, 4> r = responses4(l, 0.2 * out.mtf50CyPx);
        for (int k = 1; k <= 4; ++k)
            if (r[k - 1] > peak) peak = r[k - 1], at = 0.2 * k * out.mtf50CyPx;
    }
    out.mtf50pCyPx =
        peak > 1.0 ? solve(l, at, peak, out.mtf50CyPx, 0.5, 0.5 * peak) : out.mtf50CyPx;
    return out;
}

std::optional<Mtf50> mtf50FromEsf(const EsfProfile& esf) {
    thread_local LineSpread l;
    if (!buildLineSpread(esf, l)) return std::nullopt;
    return mtf50Of(l);
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
