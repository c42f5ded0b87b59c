// SPDX-License-Identifier: MIT
// An edge's geometry: the rows of an oriented patch, the derivative's slices along the edge, the
// line fitted through their centroids and the patch moved onto it (docs/blur.md, "Edge geometry").
#include "internal.h"

namespace infocus::blur_detail {

std::span<const detail::GeometrySpan> patchSpans(const Luma8& img, const Bounds& b, const Patch& p,
                                                 const Kernels& k) {
    const double r = std::abs(p.hw * p.nx) + std::abs(p.hl * p.ny);
    const double rv = std::abs(p.hw * p.ny) + std::abs(p.hl * p.nx);
    const int y0 = std::max(b.y0, static_cast<int>(std::floor(p.cy - rv - 0.5)));
    const int y1 = std::min(b.y1 - 1, static_cast<int>(std::ceil(p.cy + rv - 0.5)));
    thread_local std::vector<detail::GeometrySpan> spans;
    if (y1 < y0) return {};
    if (spans.size() < static_cast<size_t>(y1 - y0 + 1)) spans.resize(y1 - y0 + 1);
    // |dx·nx + dy·ny| ≤ hw and |−dx·ny + dy·nx| ≤ hl, solved for dx: each slab bounds dx to
    // centre(dy) ± half, with centre linear in dy, so a 45° patch costs its area, not its
    // bounding box, and a row costs a few multiplications. A slab whose normal has no x part
    // (an axis-aligned patch) bounds the rows instead: |c·dy| ≤ h.
    auto makeSlab = [](double a, double coef, double h) {
        if (std::abs(a) < 1e-12) return detail::PatchSlab{true, 0.0, 0.0, h, coef};
        const double inv = 1.0 / a;
        return detail::PatchSlab{false, -coef * inv, std::abs(h * inv), h, coef};
    };
    const detail::PatchRows rows{img.data,
                                 img.stride,
                                 p.cx,
                                 p.cy,
                                 p.nx,
                                 p.ny,
                                 p.cx - r - 1.0,
                                 p.cx + r + 1.0,
                                 makeSlab(p.nx, p.ny, p.hw),
                                 makeSlab(-p.ny, p.nx, p.hl),
                                 b.x0,
                                 b.x1,
                                 y0,
                                 y1};
    return {spans.data(), static_cast<size_t>(k.patchRows(rows, spans.data()))};
}

void geometrySlices(const Luma8& img, const Bounds& b, const Kernels& k, const Patch& p,
                    double threshold, int slices, Slice* out) {
    // The kernel sums in float partial sums (8 per slice and moment, see blur_kernels.h); they are
    // added up here in double. Scratch reused across calls: no allocation per edge.
    constexpr int L = detail::kGeometryLanes, M = detail::kGeometryMoments;
    thread_local std::vector<float> partial;
    partial.assign(static_cast<size_t>(M) * L * slices, 0.0f);
    const detail::GeometryPatch g{static_cast<float>(p.nx),
                                  static_cast<float>(p.ny),
                                  static_cast<float>(threshold),
                                  static_cast<float>(p.hl),
                                  slices,
                                  static_cast<float>(slices / (2.0 * p.hl))};
    const auto& spans = patchSpans(img, b, p, k);
    k.geometryRows(spans.data(), static_cast<int>(spans.size()), img.stride, img.width, g,
                   partial.data());
    thread_local std::vector<double> sums;
    sums.resize(static_cast<size_t>(M) * slices);
    k.geometryReduce(partial.data(), slices, sums.data());
    for (int s = 0; s < slices; ++s)
        out[s] = {sums[M * s], sums[M * s + 1], sums[M * s + 2], sums[M * s + 3]};
}

LineFit fitLine(const Slice* s, int n) {
    LineFit f;
    double W = 0, St = 0, Se = 0, Stt = 0, Ste = 0, spread = 0;
    int used = 0;
    for (int i = 0; i < n; ++i) {
        if (s[i].w <= 0.0) continue;
        const double t = s[i].wt / s[i].w, e = s[i].wu / s[i].w, w = s[i].w;
        W += w, St += w * t, Se += w * e, Stt += w * t * t, Ste += w * t * e;
        spread += s[i].wuu - e * s[i].wu;
        ++used;
    }
    if (used < 3) return f;
    const double den = W * Stt - St * St;
    if (den <= 1e-9) return f;
    f.slope = (W * Ste - St * Se) / den;
    f.a = (Se - f.slope * St) / W;
    double res = 0.0;
    for (int i = 0; i < n; ++i) {
        if (s[i].w <= 0.0) continue;
        const double t = s[i].wt / s[i].w, e = s[i].wu / s[i].w;
        res += s[i].w * (e - f.a - f.slope * t) * (e - f.a - f.slope * t);
    }
    f.straight = std::sqrt(res / W);
    f.spread2 = std::max(0.0, spread / W);
    f.ok = true;
    return f;
}

void moveOnto(Patch& p, const LineFit& f) {
    p.cx += f.a * p.nx;
    p.cy += f.a * p.ny;
    const double nx = p.nx + f.slope * p.ny, ny = p.ny - f.slope * p.nx;
    const double len = std::hypot(nx, ny);
    p.nx = nx / len;
    p.ny = ny / len;
}

Trim trimToEdge(Patch& p, const Slice* s, int n, double probeHalfLength, double marginPx,
                double minHalfLengthPx) {
    if (n < 4) return Trim::Whole;
    double strongest = 0.0;
    for (int i = 0; i < n; ++i)
        strongest = std::max(strongest, s[i].w);
    const double half = 0.5 * strongest;
    // The seed lies between slices n/2 − 1 and n/2; the edge runs on from there each way while
    // its slices keep at least half the strongest derivative.
    int lo = n / 2, hi = n / 2 - 1;
    while (lo > 0 && s[lo - 1].w >= half)
        --lo;
    while (hi < n - 1 && s[hi + 1].w >= half)
        ++hi;
    if (hi < lo) return Trim::Whole;
    // An end counts where the edge stops for good (a corner): beyond it the derivative falls
    // under a tenth of the strongest and stays there to the probe's end. A contrast that merely
    // dips along the edge (texture, shading) leaves the segment whole.
    const auto stops = [&](int from, int to, int dir) {
        bool faded = false;
        for (int i = from; i != to; i += dir) {
            if (s[i].w < 0.1 * strongest)
                faded = true;
            else if (faded)
                return false;
        }
        return faded;
    };
    if (lo > 0 && !stops(lo - 1, -1, -1)) lo = 0;
    if (hi < n - 1 && !stops(hi + 1, n, 1)) hi = n - 1;
    const double step = 2.0 * probeHalfLength / n;
    double t0 = -p.hl, t1 = p.hl;
    if (lo > 0) t0 = std::max(t0, -probeHalfLength + lo * step + marginPx);
    if (hi < n - 1) t1 = std::min(t1, -probeHalfLength + (hi + 1) * step - marginPx);
    if (t0 <= -p.hl && t1 >= p.hl) return Trim::Whole;
    if (t1 - t0 < 2.0 * minHalfLengthPx) return Trim::TooShort;
    const double mid = 0.5 * (t0 + t1);
    p.cx -= mid * p.ny;
    p.cy += mid * p.nx;
    p.hl = 0.5 * (t1 - t0);
    return Trim::Trimmed;
}

namespace {

// measureSegment on @p patch as trimToEdge left it (@p how). The probe's line was fitted over the
// whole length, the edge's end included, where the corner's blur pulls the slices' centroids off
// the edge and spreads them: on a trimmed patch that line may be tilted (a tilted line widens the
// ESF) and its guess of σ too wide. The line is fitted again in the trimmed patch's own slab, as
// wide as the probe's, and taken where its derivative spreads less than the probe's; where it
// spreads more, the trimmed part holds texture or clutter that the longer probe averaged, and
// the probe's line stands.
std::optional<EdgeMeasurement> measureTrimmed(const Luma8& img, const Bounds& b,
                                              const BlurOptions& o, const Kernels& k, Patch& patch,
                                              Trim how, double threshold, const LineFit& line,
                                              int slices, EdgeTrack& track) {
    LineFit fit = line;
    if (how == Trim::Trimmed) {
        thread_local std::vector<Slice> sl;
        sl.resize(slices);
        Patch slab = patch;
        slab.hw = kProbeHalfWidthPx;
        geometrySlices(img, b, k, slab, threshold, slices, sl.data());
        const LineFit refit = fitLine(sl.data(), slices);
        if (refit.ok && refit.spread2 <= line.spread2) {
            moveOnto(patch, refit);
            fit = refit;
        }
    }
    return measureSegment(img, b, o, k, patch, threshold, fit, slices, track);
}

}  // namespace

std::optional<EdgeMeasurement> measureClearOfEnds(const Luma8& img, const Bounds& b,
                                                  const BlurOptions& o, const Kernels& k,
                                                  Patch& patch, double threshold,
                                                  const LineFit& line, int slices, EdgeTrack& track,
                                                  const Slice* probe, int probeSlices,
                                                  double probeHalfLength, double minHalfLengthPx) {
    const Patch whole = patch;
    const Trim first = trimToEdge(patch, probe, probeSlices, probeHalfLength,
                                  3.0 * guessSigma(line) + 1.0, minHalfLengthPx);
    const double firstHalfLength = patch.hl;
    const auto m = measureTrimmed(img, b, o, k, patch, first, threshold, line, slices, track);
    if (!m) return m;
    // The probe's slab (±6 px) cuts a wide blur's derivative, and its guess of σ with it: the
    // measured σ says how far the corner's blur reaches.
    Patch again = whole;
    const Trim t = trimToEdge(again, probe, probeSlices, probeHalfLength, 3.0 * m->sigmaPx + 1.0,
                              minHalfLengthPx);
    if (t != Trim::Trimmed || again.hl >= firstHalfLength - 0.5) return m;
    patch = again;
    return measureTrimmed(img, b, o, k, patch, t, threshold, line, slices, track);
}

}  // namespace infocus::blur_detail
