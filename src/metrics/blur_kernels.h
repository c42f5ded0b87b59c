// SPDX-License-Identifier: MIT
// Internal: the pixel kernels of the blur-width engine (blur.cpp), a generic reference and an
// AVX2 version of each with the same results, chosen in blur.cpp after a run-time CPU check.
#pragma once

#include <cstddef>
#include <cstdint>

namespace infocus::detail {

/// 3×3 Sobel gradient (×8 grey levels per pixel) of the @p n pixels x0..x0+n−1 of the row whose
/// rows above, at and below are @p above, @p mid, @p below; x0 ≥ 1 and x0+n ≤ width − 1.
void sobelRowGeneric(const uint8_t* above, const uint8_t* mid, const uint8_t* below, int x0, int n,
                     int16_t* gx, int16_t* gy);
/// sobelRowGeneric with AVX2 (check haveAvx2() first): the same numbers.
void sobelRowAvx2(const uint8_t* above, const uint8_t* mid, const uint8_t* below, int x0, int n,
                  int16_t* gx, int16_t* gy);

/// An oriented patch for the edge-geometry fit: the normal (nx, ny), the derivative threshold, the
/// half-length hl and the number of 4 px slices along the edge.
struct GeometryPatch {
    float nx, ny, thr, hl;
    int slices;
};

/// One row of the patch: pixels x0..x1 of image row @p r; (u0, t0) are the patch coordinates of
/// pixel x0 (u grows by nx and t by −ny per pixel).
struct GeometrySpan {
    const uint8_t* r;
    int x0, x1;
    float u0, t0;
};

/// Number of partial sums per slice kept by the geometry kernels: lane i of a row adds into
/// partial (i − x0) mod 8, so that the vector and the generic kernel add in the same order.
constexpr int kGeometryLanes = 8;

/// Adds the pixels of the @p count rows @p spans (image stride @p stride, @p width pixels) whose
/// directional derivative d = 0.5 (Δx·nx + Δy·ny) (central differences) exceeds thr to the slice
/// sums @p acc: for slice s = ⌊(t + hl)/4⌋ (clamped), acc[(3s + j)·8 + lane] += w, w·u, w·t for
/// j = 0, 1, 2, with w = d − thr; all in float.
void geometryRowsGeneric(const GeometrySpan* spans, int count, ptrdiff_t stride, int width,
                         const GeometryPatch& g, float* acc);
/// The scalar arithmetic of both geometry kernels for the pixels from..x1 of a row that starts at
/// x0 (lanes and coordinates counted from x0).
inline void geometryPixels(const uint8_t* r, ptrdiff_t stride, int x0, int from, int x1, float u0,
                           float t0, const GeometryPatch& g, float* acc) {
    for (int x = from; x <= x1; ++x) {
        const float d = 0.5f * (static_cast<float>(r[x + 1] - r[x - 1]) * g.nx +
                                static_cast<float>(r[x + stride] - r[x - stride]) * g.ny);
        if (!(d > g.thr)) continue;
        const int i = x - x0;
        const float w = d - g.thr, fi = static_cast<float>(i);
        const float u = u0 + g.nx * fi, t = t0 - g.ny * fi;
        int s = static_cast<int>((t + g.hl) * 0.25f);
        s = s < 0 ? 0 : (s > g.slices - 1 ? g.slices - 1 : s);
        float* a = acc + 3 * kGeometryLanes * s + (i & (kGeometryLanes - 1));
        a[0] += w;
        a[kGeometryLanes] += w * u;
        a[2 * kGeometryLanes] += w * t;
    }
}

/// geometryRowsGeneric with AVX2 (check haveAvx2() first): the same sums to the bit.
void geometryRowsAvx2(const GeometrySpan* spans, int count, ptrdiff_t stride, int width,
                      const GeometryPatch& g, float* acc);

}  // namespace infocus::detail
