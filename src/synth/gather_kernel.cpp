// SPDX-License-Identifier: MIT
// PSFs as weights on whole pixels, for renderers that gather each output pixel from a texture.
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>

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

GatherKernel discGatherKernel(double diameterPx) {
    GatherKernel k;
    const double r = diameterPx / 2;
    if (r < 1e-9) {
        k.taps.push_back({0, 0, 1.0});
        return k;
    }
    const int ext = static_cast<int>(std::ceil(r + 0.5));
    const int side = 2 * ext + 1;
    std::vector<double> cov(static_cast<size_t>(side) * side);
    double total = 0.0;
    for (int dy = -ext; dy <= ext; ++dy)
        for (int dx = -ext; dx <= ext; ++dx) {
            const double c = discPixelCoverage(dx, dy, r, 64);
            cov[(dy + ext) * side + dx + ext] = c;
            total += c;
        }
    k.fullWeight = 1.0 / total;
    for (int dy = -ext; dy <= ext; ++dy) {
        int a = INT_MAX, b = INT_MIN;
        for (int dx = -ext; dx <= ext; ++dx) {
            const double c = cov[(dy + ext) * side + dx + ext];
            if (c >= 1.0) {
                a = std::min(a, dx);
                b = std::max(b, dx);
            } else if (c > 0.0) {
                k.taps.push_back({dy, dx, c / total});
            }
        }
        if (a <= b) k.runs.push_back({dy, a, b});
    }
    return k;
}

}  // namespace infocus::synth
