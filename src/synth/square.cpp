// SPDX-License-Identifier: MIT
// Exact rendering of a blurred, rotated square: the reference for slanted-square accuracy.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "infocus/synth.h"

namespace infocus::synth {

namespace {

constexpr double kPi = std::numbers::pi;

struct Vec {
    double x, y;
};
double cross(Vec a, Vec b) {
    return a.x * b.y - a.y * b.x;
}
double dot(Vec a, Vec b) {
    return a.x * b.x + a.y * b.y;
}
// Signed angle from a to b.
double angle(Vec a, Vec b) {
    return std::atan2(cross(a, b), dot(a, b));
}

// Signed area of the intersection of the disc of radius r about the origin with the triangle
// (origin, a, b): the part of the segment inside the disc adds a triangle, the parts outside a
// circular sector.
double discTriangleArea(Vec a, Vec b, double r) {
    const double r2 = r * r;
    const Vec d{b.x - a.x, b.y - a.y};
    const double qa = d.x * d.x + d.y * d.y;
    if (qa <= 0.0) return 0.0;
    const double qb = dot(a, d);
    const double qc = dot(a, a) - r2;
    const double disc = qb * qb - qa * qc;
    if (disc <= 0.0) return 0.5 * r2 * angle(a, b);
    const double sq = std::sqrt(disc);
    const double t1 = std::max((-qb - sq) / qa, 0.0);
    const double t2 = std::min((-qb + sq) / qa, 1.0);
    if (t1 >= t2) return 0.5 * r2 * angle(a, b);
    const Vec p1{a.x + t1 * d.x, a.y + t1 * d.y};
    const Vec p2{a.x + t2 * d.x, a.y + t2 * d.y};
    return 0.5 * (r2 * angle(a, p1) + cross(p1, p2) + r2 * angle(p2, b));
}

double normalCdf(double z) {
    return 0.5 * std::erfc(-z / std::numbers::sqrt2);
}

}  // namespace

SynthImage renderSquare(int width, int height, const Square& square, const Imaging& imaging) {
    SynthImage out{Image<float>(width, height), imaging.psf, imaging.noiseSigma};
    const double th = square.angleDeg * kPi / 180.0;
    const double c = std::cos(th), s = std::sin(th);
    const double h = 0.5 * square.sidePx;
    const Psf& psf = imaging.psf;
    const bool gaussian = psf.shape == PsfShape::Gaussian;
    const double size = std::max(psf.sizePx, 0.0);
    // How far the PSF reaches: a Gaussian's mass beyond 7σ is below 1e-12.
    const double reach = gaussian ? 7.0 * size : 0.5 * size;
    const double spread = psf.sigmaPx();
    const int n = std::max(2, std::min(imaging.supersample,
                                       static_cast<int>(std::ceil(12.0 / std::max(spread, 0.1)))));
    const double contrast = square.inside - square.outside;
    const double r = 0.5 * size;
    // The square's share of the PSF centred at (u, v), the square's own coordinates.
    const auto share = [&](double u, double v) {
        if (size <= 0.0) return std::abs(u) < h && std::abs(v) < h ? 1.0 : 0.0;
        if (gaussian) {
            const auto box = [&](double t) {
                return normalCdf((h - t) / size) - normalCdf((-h - t) / size);
            };
            return box(u) * box(v);
        }
        // Corners relative to the disc's centre, counter-clockwise.
        const Vec q[4] = {{-h - u, -h - v}, {h - u, -h - v}, {h - u, h - v}, {-h - u, h - v}};
        double area = 0.0;
        for (int k = 0; k < 4; ++k)
            area += discTriangleArea(q[k], q[(k + 1) % 4], r);
        return std::clamp(area / (kPi * r * r), 0.0, 1.0);
    };
    // Half the pixel's diagonal: a pixel whose centre lies farther than reach + this from the
    // square's outline is the same everywhere.
    const double pixelReach = reach + 0.5 * std::numbers::sqrt2;
    for (int y = 0; y < height; ++y) {
        float* row = out.pixels.row(y);
        for (int x = 0; x < width; ++x) {
            const double dx = x + 0.5 - square.cx, dy = y + 0.5 - square.cy;
            const double u = c * dx + s * dy, v = -s * dx + c * dy;
            const double m = std::max(std::abs(u), std::abs(v));
            const double outsideDist =
                std::hypot(std::max(std::abs(u) - h, 0.0), std::max(std::abs(v) - h, 0.0));
            double value;
            if (m < h && h - m > pixelReach) {
                value = 1.0;
            } else if (outsideDist > pixelReach) {
                value = 0.0;
            } else {
                double sum = 0.0;
                for (int j = 0; j < n; ++j) {
                    const double py = dy + (j + 0.5) / n - 0.5;
                    for (int i = 0; i < n; ++i) {
                        const double px = dx + (i + 0.5) / n - 0.5;
                        sum += share(c * px + s * py, -s * px + c * py);
                    }
                }
                value = sum / (n * n);
            }
            row[x] = static_cast<float>(square.outside + contrast * value);
        }
    }
    if (imaging.noiseSigma > 0.0) addNoise(out.pixels, imaging.noiseSigma, imaging.seed);
    return out;
}

}  // namespace infocus::synth
