// SPDX-License-Identifier: MIT
// Scenes painted directly at pixel resolution, and table-driven noise: fast enough to build a
// simulated camera's texture and to add fresh noise to every frame.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "infocus/synth.h"
#include "rng.h"

namespace infocus::synth {

namespace {

constexpr double kPi = std::numbers::pi;

}  // namespace

void paintDeadLeavesPixels(Image<float>& image, uint64_t seed, double minRadiusPx,
                           double maxRadiusPx, float lo, float hi) {
    Rng rng(seed);
    const int w = image.width(), h = image.height();
    const double rMin = minRadiusPx, rMax = maxRadiusPx;
    // Mean disc area of log-uniform radii: π (rMax² − rMin²) / (2 ln(rMax/rMin)); cover ~3×.
    const double meanArea = kPi * (rMax * rMax - rMin * rMin) / (2 * std::log(rMax / rMin));
    const int count = static_cast<int>(3.0 * w * h / meanArea) + 1;
    const double base = lo, range = static_cast<double>(hi) - lo;
    std::fill(image.data(), image.data() + static_cast<size_t>(w) * h, 128.0f);
    for (int n = 0; n < count; ++n) {
        const double r = rMin * std::pow(rMax / rMin, rng.uniform());
        const double cx = rng.uniform() * w, cy = rng.uniform() * h;
        const float grey = static_cast<float>(base + range * rng.uniform());
        const int x0 = std::max(0, static_cast<int>(cx - r - 1));
        const int x1 = std::min(w - 1, static_cast<int>(cx + r + 1));
        const int y0 = std::max(0, static_cast<int>(cy - r - 1));
        const int y1 = std::min(h - 1, static_cast<int>(cy + r + 1));
        for (int y = y0; y <= y1; ++y) {
            float* row = image.row(y);
            for (int x = x0; x <= x1; ++x) {
                const double dist = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
                // Coverage of the pixel by the disc edge, linear across one pixel.
                const double a = std::clamp(r + 0.5 - dist, 0.0, 1.0);
                if (a > 0) row[x] = static_cast<float>(row[x] + a * (grey - row[x]));
            }
        }
    }
}

void paintSlantedSquaresPixels(Image<float>& image, double pitchPx, double angleDeg, double cx,
                               double cy, float dark, float bright) {
    const double period = pitchPx;
    const double half = period / 4;  // half the side of a square
    const double c = std::cos(angleDeg * kPi / 180), s = std::sin(angleDeg * kPi / 180);
    for (int y = 0; y < image.height(); ++y) {
        float* row = image.row(y);
        for (int x = 0; x < image.width(); ++x) {
            const double px = x + 0.5 - cx, py = y + 0.5 - cy;
            const double u = c * px + s * py, v = -s * px + c * py;
            // Position within the cell, centred on a square centre at (period/2, period/2).
            const double lu = u - period * std::floor(u / period) - period / 2;
            const double lv = v - period * std::floor(v / period) - period / 2;
            const double cu = std::clamp(half - std::abs(lu) + 0.5, 0.0, 1.0);
            const double cv = std::clamp(half - std::abs(lv) + 0.5, 0.0, 1.0);
            const double a = cu * cv;
            row[x] = static_cast<float>(bright + a * (dark - bright));
        }
    }
}

NoiseTable::NoiseTable(double sigma, uint64_t seed) : samples_(1 << 16) {
    // One Box–Muller pair of uniforms per sample (its cosine half), so the table for a seed does
    // not depend on the table's length.
    Rng rng(seed);
    for (float& n : samples_) {
        const double u1 = std::max(rng.uniform(), 1e-300), u2 = rng.uniform();
        n = static_cast<float>(std::sqrt(-2 * std::log(u1)) * std::cos(2 * kPi * u2) * sigma);
    }
}

}  // namespace infocus::synth
