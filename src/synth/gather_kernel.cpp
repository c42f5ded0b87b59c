// SPDX-License-Identifier: MIT
// PSFs as weights on whole pixels, for renderers that gather each output pixel from a texture.
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <vector>

#include "infocus/synth.h"

namespace infocus::synth {

double discPixelCoverage(double cx, double cy, double radiusPx, int subsamples) {
    const double r = radiusPx;
    const double nx = std::max(0.0, std::abs(cx) - 0.5), ny = std::max(0.0, std::abs(cy) - 0.5);
    if (nx * nx + ny * ny >= r * r) return 0.0;
    const double fx = std::abs(cx) + 0.5, fy = std::abs(cy) + 0.5;
    if (fx * fx + fy * fy <= r * r) return 1.0;
    // Boundary pixel: count the sub-pixel points inside the disc.
    const int n = std::max(1, subsamples);
    int inside = 0;
    for (int j = 0; j < n; ++j) {
        const double y = cy - 0.5 + (j + 0.5) / n;
        for (int i = 0; i < n; ++i) {
            const double x = cx - 0.5 + (i + 0.5) / n;
            inside += x * x + y * y <= r * r;
        }
    }
    return static_cast<double>(inside) / (n * n);
}

int GatherKernel::extent() const {
    int e = 0;
    for (const Run& r : runs)
        e = std::max({e, std::abs(r.dy), std::abs(r.a), std::abs(r.b)});
    for (const Tap& t : taps)
        e = std::max({e, std::abs(t.dy), std::abs(t.dx)});
    return e;
}

namespace {

constexpr double kPi = std::numbers::pi;

// Keys' cubic convolution kernel (a = −0.5): it passes through the samples (1 at 0, 0 at other
// integers) and its second moment is 0, so interpolating with it adds no blur.
double keys(double x) {
    x = std::abs(x);
    if (x < 1) return (1.5 * x - 2.5) * x * x + 1;
    if (x < 2) return ((-0.5 * x + 2.5) * x - 4) * x + 2;
    return 0.0;
}

// ∫_{-∞}^{x} keys.
double keysIntegral(double x) {
    const double t = std::min(std::abs(x), 2.0);
    double f = 0.0;  // ∫_0^t keys
    if (t <= 1) {
        f = ((0.375 * t - 2.5 / 3) * t * t + 1) * t;
    } else {
        const auto g = [](double u) { return (((-0.125 * u + 2.5 / 3) * u - 2) * u + 2) * u; };
        f = 0.375 - 2.5 / 3 + 1 + g(t) - g(1);
    }
    return x < 0 ? 0.5 - f : 0.5 + f;
}

// The 1-D profile of the texture's interpolation (Keys) convolved with a Gaussian of σ @p s,
// the Gaussian by 7-point Gauss–Hermite quadrature (nodes at σ√2·t_i, weights w_i/√π).
class CubicProfile {
public:
    explicit CubicProfile(double sigma) : s_(sigma) {}
    double value(double x) const {
        return sum([&](double shift) { return keys(x - shift); });
    }
    // ∫_{-∞}^{x} of value, so a mean over an interval is exact.
    double integral(double x) const {
        return sum([&](double shift) { return keysIntegral(x - shift); });
    }
    // Where the profile is non-zero: |x| < reach().
    double reach() const { return 2.0 + 4.0 * s_; }

private:
    template <typename F>
    double sum(F f) const {
        if (s_ <= 0) return f(0.0);
        static constexpr double kNode[] = {0.0, 0.8162878828589647, 1.6735516287674714,
                                           2.6519613568352335};
        static constexpr double kWeight[] = {0.8102646175568073, 0.4256072526101278,
                                             0.05451558281912703, 0.0009717812450995192};
        double total = kWeight[0] * f(0.0);
        for (int i = 1; i < 4; ++i) {
            const double shift = s_ * std::numbers::sqrt2 * kNode[i];
            total += kWeight[i] * (f(shift) + f(-shift));
        }
        return total / std::sqrt(kPi);
    }
    double s_;
};

}  // namespace

GatherKernel defocusGatherKernel(double discDiameterPx, double sigmaPx) {
    const double r = std::max(0.0, discDiameterPx / 2);
    const CubicProfile h(std::max(0.0, sigmaPx));
    const int ext = static_cast<int>(std::ceil(r + h.reach()));
    const int side = 2 * ext + 1;
    std::vector<double> w(static_cast<size_t>(side) * side, 0.0);
    const auto at = [&](int dx, int dy) -> double& { return w[(dy + ext) * side + dx + ext]; };
    // A pixel whose whole reach lies inside the disc sees the disc's plain density 1/(πr²).
    const auto interior = [&](int dx, int dy) {
        const double fx = std::abs(dx) + h.reach(), fy = std::abs(dy) + h.reach();
        return r > 0 && fx * fx + fy * fy < r * r;
    };
    if (r < 1e-9) {
        for (int dy = -ext; dy <= ext; ++dy)
            for (int dx = -ext; dx <= ext; ++dx)
                at(dx, dy) = h.value(dx) * h.value(dy);
    } else {
        // w(k) = (1/πr²) ∫ over the disc of h(k_x − u_x)·h(k_y − u_y): the x integral is exact
        // (H at the chord's ends), the y integral is the midpoint rule in θ with u_y = r·sin θ,
        // which is smooth at the disc's top and bottom and moves continuously with r.
        const int m = 32 + 8 * static_cast<int>(std::ceil(2 * r));
        const double density = 1.0 / (kPi * r * r);
        std::vector<double> chord(side);
        for (int i = 0; i < m; ++i) {
            const double theta = -kPi / 2 + (i + 0.5) * kPi / m;
            const double uy = r * std::sin(theta), c = r * std::cos(theta);
            const double weight = density * c * (kPi / m);  // du_y = r·cos θ dθ
            for (int dx = -ext; dx <= ext; ++dx)
                chord[dx + ext] = h.integral(dx + c) - h.integral(dx - c);
            const int y0 = std::max(-ext, static_cast<int>(std::floor(uy - h.reach())));
            const int y1 = std::min(ext, static_cast<int>(std::ceil(uy + h.reach())));
            for (int dy = y0; dy <= y1; ++dy) {
                const double hy = h.value(dy - uy);
                if (hy == 0) continue;
                for (int dx = -ext; dx <= ext; ++dx)
                    if (!interior(dx, dy)) at(dx, dy) += weight * hy * chord[dx + ext];
            }
        }
        for (int dy = -ext; dy <= ext; ++dy)
            for (int dx = -ext; dx <= ext; ++dx)
                if (interior(dx, dy)) at(dx, dy) = density;
    }
    double total = 0.0;
    for (double v : w)
        total += v;
    GatherKernel k;
    k.fullWeight = r > 0 ? 1.0 / (kPi * r * r) / total : 0.0;
    for (int dy = -ext; dy <= ext; ++dy) {
        int a = INT_MAX, b = INT_MIN;
        for (int dx = -ext; dx <= ext; ++dx) {
            if (interior(dx, dy)) {
                a = std::min(a, dx);
                b = std::max(b, dx);
            } else if (std::abs(at(dx, dy)) > 1e-12) {
                k.taps.push_back({dy, dx, at(dx, dy) / total});
            }
        }
        if (a <= b) k.runs.push_back({dy, a, b});
    }
    return k;
}

}  // namespace infocus::synth
