// SPDX-License-Identifier: MIT
// The generic pixel kernels of the blur-width engine (the reference the AVX2 versions in
// kernels_avx2.cpp match to the bit), and the one place that chooses between them.
#include <algorithm>
#include <cmath>

#include "../cpu.h"
#include "infocus/blur.h"
#include "kernels.h"

namespace infocus::detail {

void geometryRowsGeneric(const GeometrySpan* spans, int count, ptrdiff_t stride, int,
                         const GeometryPatch& g, float* acc) {
    for (int k = 0; k < count; ++k) {
        const GeometrySpan& sp = spans[k];
        geometryPixels(sp.r, stride, sp.x0, sp.x0, sp.x1, sp.u0, sp.t0, g, acc);
    }
}

void esfRowsGeneric(const GeometrySpan* spans, int count, int, const EsfPatch& e, uint32_t* acc) {
    for (int k = 0; k < count; ++k)
        esfPixels(spans[k].r, spans[k].x0, spans[k].x0, spans[k].x1, spans[k].u0, e, acc);
}

int32_t sobelGridRowGeneric(const uint8_t* a, const uint8_t* m, const uint8_t* c, int x0, int count,
                            int step, int, int16_t* gx, int16_t* gy, int32_t* mag2) {
    int32_t peak = 0;
    for (int i = 0; i < count; ++i) {
        const int x = x0 + i * step;
        const int dx = (a[x + 1] - a[x - 1]) + 2 * (m[x + 1] - m[x - 1]) + (c[x + 1] - c[x - 1]);
        const int dy = (c[x - 1] - a[x - 1]) + 2 * (c[x] - a[x]) + (c[x + 1] - a[x + 1]);
        gx[i] = static_cast<int16_t>(dx);
        gy[i] = static_cast<int16_t>(dy);
        mag2[i] = dx * dx + dy * dy;
        peak = std::max(peak, mag2[i]);
    }
    return peak;
}

void geometryReduceGeneric(const float* acc, int slices, double* out) {
    for (int k = 0; k < kGeometryMoments * slices; ++k) {
        double sum = 0.0;
        for (int l = 0; l < kGeometryLanes; ++l)
            sum += acc[k * kGeometryLanes + l];
        out[k] = sum;
    }
}

size_t countAtLeastGeneric(const int32_t* m, size_t n, int32_t v) {
    size_t count = 0;
    for (size_t i = 0; i < n; ++i)
        count += m[i] >= v;
    return count;
}

void levelsGeneric(const int32_t* m, size_t n, int shift, uint8_t* levels) {
    for (size_t i = 0; i < n; ++i)
        levels[i] = static_cast<uint8_t>(m[i] >> shift);
}

size_t countLevelsAtLeastGeneric(const uint8_t* levels, size_t n, uint8_t v) {
    size_t count = 0;
    for (size_t i = 0; i < n; ++i)
        count += levels[i] >= v;
    return count;
}

size_t listLevelsAtLeastGeneric(const uint8_t* levels, int shift, const int32_t* m, size_t n,
                                int32_t v, uint64_t* keys) {
    // m[i] ≥ v implies levels[i] = m[i] >> shift ≥ v >> shift: the byte test only skips points.
    const int level = v >> shift;
    size_t listed = 0;
    for (size_t i = 0; i < n; ++i)
        if (levels[i] >= level && m[i] >= v) keys[listed++] = candidateKey(m[i], i);
    return listed;
}

size_t listAtLeastGeneric(const int32_t* m, size_t n, int32_t v, uint64_t* keys) {
    size_t listed = 0;
    for (size_t i = 0; i < n; ++i)
        if (m[i] >= v) keys[listed++] = candidateKey(m[i], i);
    return listed;
}

void orderKeysGeneric(const uint64_t* keys, size_t n, size_t m, uint64_t* out) {
    std::partial_sort_copy(keys, keys + n, out, out + m, std::greater<>());
}

void oneSidedSumsGeneric(const int16_t* gx, const int16_t* gy, ptrdiff_t stride, int width,
                         int rows, int32_t nx, int32_t ny, int64_t* along, int64_t* magnitude) {
    for (int y = 0; y < rows; ++y)
        for (int x = 0; x < width; ++x) {
            const int64_t d = int64_t{gx[y * stride + x]} * nx + int64_t{gy[y * stride + x]} * ny;
            *along += d;
            *magnitude += d < 0 ? -d : d;
        }
}

int patchRowsGeneric(const PatchRows& s, GeometrySpan* out) {
    GeometrySpan* const first = out;
    for (int y = s.y0; y <= s.y1; ++y) {
        const double dy = y + 0.5 - s.cy;
        double lo = s.left, hi = s.right;
        // Narrows [lo, hi] to the slab; false when an open slab excludes the row.
        const auto inside = [&](const PatchSlab& slab) {
            if (slab.open) return std::abs(slab.c * dy) <= slab.h;
            const double centre = s.cx + slab.slope * dy;
            lo = std::max(lo, centre - slab.half);
            hi = std::min(hi, centre + slab.half);
            return true;
        };
        if (!inside(s.s1) || !inside(s.s2)) continue;
        // A slab nearly along y has a huge slope: clamped to the patch's x range, a row outside
        // it stays empty and its ends stay small numbers.
        lo = std::min(lo, s.right + 1.0);
        hi = std::max(hi, s.left - 1.0);
        const int x0 = std::max(s.bx0, static_cast<int>(std::ceil(lo - 0.5)));
        const int x1 = std::min(s.bx1 - 1, static_cast<int>(std::floor(hi - 0.5)));
        if (x0 > x1) continue;
        const double dx = x0 + 0.5 - s.cx;
        *out++ = {s.data + static_cast<ptrdiff_t>(y) * s.stride, x0, x1,
                  static_cast<float>(dx * s.nx + dy * s.ny),
                  static_cast<float>(-dx * s.ny + dy * s.nx)};
    }
    return static_cast<int>(out - first);
}

int esfBinsGeneric(const uint32_t* acc, int from, int n, double binPx, double hw,
                   const EsfBins& out) {
    int k = 0;
    const double unit = binPx / 2048.0;
    for (int i = from; i < n; ++i) {
        const uint32_t* a = acc + 4 * i;
        const auto cnt = static_cast<int>(a[0] >> kEsfCountShift);
        if (cnt == 0) continue;
        const double inv = 1.0 / cnt;
        const double sv = a[0] & ((1u << kEsfCountShift) - 1u);
        const double v = sv * inv, d = static_cast<int32_t>(a[2]) * unit * inv;
        const double centre = (i + 0.5) * binPx - hw;
        out.pos[k] = centre + d;
        out.value[k] = v;
        out.withinVar[k] = std::max(0.0, a[3] * unit * unit * inv - d * d);
        out.pixelVar[k] = std::max(0.0, static_cast<double>(a[1]) * inv - v * v);
        out.count[k] = cnt;
        ++k;
    }
    return k;
}

void pairTermsGeneric(const PairInputs& b, int from, int n, double* x, double* c, double* sums) {
    if (from == 0) sums[0] = sums[1] = sums[2] = sums[3] = 0.0;
    double s0 = sums[4 * from], s1 = sums[4 * from + 1], s2 = sums[4 * from + 2],
           s3 = sums[4 * from + 3];
    for (int i = from; i + 1 < n; ++i) {
        const double step = b.value[i + 1] - b.value[i];
        const double mid = 0.5 * (b.pos[i] + b.pos[i + 1]);
        const double gap = b.pos[i + 1] - b.pos[i];
        const double spread = gap * gap / 12.0 + 0.5 * (b.withinVar[i] + b.withinVar[i + 1]);
        x[i] = mid, c[i] = spread;
        s0 += step, s1 += step * mid, s2 += step * mid * mid, s3 += step * spread;
        double* s = sums + 4 * (i + 1);
        s[0] = s0, s[1] = s1, s[2] = s2, s[3] = s3;
    }
}

Kernels chooseKernels(const BlurOptions& o) {
    if (o.simd && haveAvx2())
        return {sobelGridRowAvx2,       geometryRowsAvx2, esfRowsAvx2,           geometryReduceAvx2,
                countAtLeastAvx2,       listAtLeastAvx2,  listLevelsAtLeastAvx2, levelsAvx2,
                countLevelsAtLeastAvx2, oneSidedSumsAvx2, patchRowsAvx2,         esfBinsAvx2,
                pairTermsAvx2,          orderKeysAvx2};
    return {sobelGridRowGeneric,      geometryRowsGeneric, esfRowsGeneric,
            geometryReduceGeneric,    countAtLeastGeneric, listAtLeastGeneric,
            listLevelsAtLeastGeneric, levelsGeneric,       countLevelsAtLeastGeneric,
            oneSidedSumsGeneric,      patchRowsGeneric,    esfBinsGeneric,
            pairTermsGeneric,         orderKeysGeneric};
}

}  // namespace infocus::detail
