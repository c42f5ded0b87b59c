// SPDX-License-Identifier: MIT
// Internal: the pixel kernels of the blur-width engine, a generic reference (kernels_generic.cpp)
// and an AVX2 version of each with the same results (kernels_avx2.cpp), chosen in one place
// (chooseKernels) after a run-time CPU check.
#pragma once

#include <cstddef>
#include <cstdint>

namespace infocus {

struct BlurOptions;

namespace detail {

/// The 3×3 Sobel gradient (×8 grey levels per pixel) of the @p count pixels x0, x0 + step, … of
/// the row whose rows above, at and below are @p above, @p mid, @p below (x0 ≥ 1), and its square
/// magnitude gx² + gy²; returns the largest magnitude (0 if none). The last pixel
/// must satisfy x ≤ width − 2.
int32_t sobelGridRowGeneric(const uint8_t* above, const uint8_t* mid, const uint8_t* below, int x0,
                            int count, int step, int width, int16_t* gx, int16_t* gy,
                            int32_t* mag2);
/// sobelGridRowGeneric with AVX2 (check haveAvx2() first) for step 2 (others: the generic one),
/// reading up to 32 bytes past x0 + 2·16k while the row has them: the same numbers.
int32_t sobelGridRowAvx2(const uint8_t* above, const uint8_t* mid, const uint8_t* below, int x0,
                         int count, int step, int width, int16_t* gx, int16_t* gy, int32_t* mag2);

/// A candidate's 64-bit key: its |g|² @p mag2 above its complemented grid index @p i, so that
/// the larger key is the stronger point and equal gradients come in scan order.
inline uint64_t candidateKey(int32_t mag2, size_t i) {
    return (static_cast<uint64_t>(mag2) << 32) | (0xffffffffu - static_cast<uint32_t>(i));
}
/// The grid index of a candidateKey.
inline size_t candidateIndex(uint64_t key) {
    return 0xffffffffu - static_cast<uint32_t>(key);
}

/// Number of the @p n values @p m[i] that are at least @p v (v ≥ 0).
size_t countAtLeastGeneric(const int32_t* m, size_t n, int32_t v);
/// countAtLeastGeneric with AVX2 (check haveAvx2() first).
size_t countAtLeastAvx2(const int32_t* m, size_t n, int32_t v);
/// Writes m[i] >> @p shift to @p levels for the @p n values @p m (0 ≤ m[i] < 256 << shift), so
/// that counting the points at or above a multiple of 2^shift reads a byte a point.
void levelsGeneric(const int32_t* m, size_t n, int shift, uint8_t* levels);
/// levelsGeneric with AVX2 (check haveAvx2() first).
void levelsAvx2(const int32_t* m, size_t n, int shift, uint8_t* levels);
/// Number of the @p n bytes @p levels[i] that are at least @p v.
size_t countLevelsAtLeastGeneric(const uint8_t* levels, size_t n, uint8_t v);
/// countLevelsAtLeastGeneric with AVX2 (check haveAvx2() first).
size_t countLevelsAtLeastAvx2(const uint8_t* levels, size_t n, uint8_t v);
/// listAtLeastGeneric for v ≥ 0 with the levels of m (levelsGeneric with @p shift): only the
/// points whose level is at least v >> shift are read in @p m; the same keys.
size_t listLevelsAtLeastGeneric(const uint8_t* levels, int shift, const int32_t* m, size_t n,
                                int32_t v, uint64_t* keys);
/// listLevelsAtLeastGeneric with AVX2 (check haveAvx2() first), 32 levels a compare.
size_t listLevelsAtLeastAvx2(const uint8_t* levels, int shift, const int32_t* m, size_t n,
                             int32_t v, uint64_t* keys);
/// Writes the candidateKey of every i with m[i] ≥ @p v (v ≥ 0) to @p keys, in order of i, and
/// returns how many it wrote.
size_t listAtLeastGeneric(const int32_t* m, size_t n, int32_t v, uint64_t* keys);
/// listAtLeastGeneric with AVX2 (check haveAvx2() first).
size_t listAtLeastAvx2(const int32_t* m, size_t n, int32_t v, uint64_t* keys);

/// Most keys orderKeys takes: it compares every key with every other.
constexpr size_t kMaxOrderKeys = 128;
/// Writes the @p m largest of the @p n distinct keys @p keys (candidateKeys, n ≤ kMaxOrderKeys,
/// m ≤ n), largest first, to @p out.
void orderKeysGeneric(const uint64_t* keys, size_t n, size_t m, uint64_t* out);
/// orderKeysGeneric with AVX2 (check haveAvx2() first): each key's place is the number of keys
/// above it, counted four keys against four at a compare, with no branch on the data; the same
/// keys in the same order.
void orderKeysAvx2(const uint64_t* keys, size_t n, size_t m, uint64_t* out);

/// Adds, over @p rows rows of @p width grid points from @p gx / @p gy (rows @p stride points
/// apart), d = gx·nx + gy·ny to @p along and |d| to @p magnitude (|gx|, |gy|, |nx|, |ny| ≤ 1020).
void oneSidedSumsGeneric(const int16_t* gx, const int16_t* gy, ptrdiff_t stride, int width,
                         int rows, int32_t nx, int32_t ny, int64_t* along, int64_t* magnitude);
/// oneSidedSumsGeneric with AVX2 (check haveAvx2() first), a row at a time when width ≤ 16
/// (others: the generic one); reads 16 points from each row's start, which must be readable.
void oneSidedSumsAvx2(const int16_t* gx, const int16_t* gy, ptrdiff_t stride, int width, int rows,
                      int32_t nx, int32_t ny, int64_t* along, int64_t* magnitude);

/// An oriented patch for the edge-geometry fit: the normal (nx, ny), the derivative threshold, the
/// half-length hl, the number of slices along the edge and their inverse width (slices / 2hl).
struct GeometryPatch {
    float nx, ny, thr, hl;
    int slices;
    float sliceInv;
};

/// One row of a patch: pixels x0..x1 of image row @p r; (u0, t0) are the patch coordinates of
/// pixel x0 (u grows by nx and t by −ny per pixel).
struct GeometrySpan {
    const uint8_t* r;
    int x0, x1;
    float u0, t0;
};

/// An oriented patch solved for x, row by row (patchSpans in geometry.cpp): each of the two slabs
/// |(x − cx)·a + dy·coef| ≤ h bounds x to cx + slope·dy ± half, or, when a = 0 (open), bounds
/// the rows instead: |c·dy| ≤ h.
struct PatchSlab {
    bool open;
    double slope, half, h, c;
};

/// Everything the row walk of a patch needs: image, centre and normal, the two slabs, the
/// widest x range, the sampling bounds in x and the rows.
struct PatchRows {
    const uint8_t* data;
    ptrdiff_t stride;
    double cx, cy, nx, ny, left, right;
    PatchSlab s1, s2;
    int bx0, bx1;  ///< x in [bx0, bx1)
    int y0, y1;    ///< rows y0..y1
};

/// Writes the span of every row of @p rows that holds pixel centres inside the patch to
/// @p out: pixels x0..x1 and the patch coordinates (u, t) of pixel x0 in float, computed in
/// double as ((x0 + ½) − cx)·nx + ((y + ½) − cy)·ny and −((x0 + ½) − cx)·ny + ((y + ½) − cy)·nx.
/// Returns the number of spans.
int patchRowsGeneric(const PatchRows& rows, GeometrySpan* out);
/// patchRowsGeneric with AVX2 (check haveAvx2() first), four rows at a time: the same spans.
int patchRowsAvx2(const PatchRows& rows, GeometrySpan* out);

/// Number of partial sums per slice and moment kept by the geometry kernels: lane i of a row adds
/// into partial (i − x0) mod 8, so that the vector and the generic kernel add in the same order.
constexpr int kGeometryLanes = 8;
/// Moments per slice: w, w·u, w·t, w·u².
constexpr int kGeometryMoments = 4;

/// Adds the pixels of the @p count rows @p spans (image stride @p stride, @p width pixels) whose
/// directional derivative d = 0.5 (Δx·nx + Δy·ny) (central differences) exceeds thr to the slice
/// sums @p acc: for slice s = ⌊(t + hl)·sliceInv⌋ (clamped), acc[(4s + j)·8 + lane] += w, w·u,
/// w·t, w·u·u for j = 0..3, with w = d − thr; all in float.
void geometryRowsGeneric(const GeometrySpan* spans, int count, ptrdiff_t stride, int width,
                         const GeometryPatch& g, float* acc);
/// The scalar arithmetic of both geometry kernels for the pixels from..x1 of a row that starts at
/// x0 (lanes and coordinates counted from x0).
inline void geometryPixels(const uint8_t* r, ptrdiff_t stride, int x0, int from, int x1, float u0,
                           float t0, const GeometryPatch& g, float* acc) {
    constexpr int L = kGeometryLanes;
    for (int x = from; x <= x1; ++x) {
        const float d = 0.5f * (static_cast<float>(r[x + 1] - r[x - 1]) * g.nx +
                                static_cast<float>(r[x + stride] - r[x - stride]) * g.ny);
        if (!(d > g.thr)) continue;
        const int i = x - x0;
        const float w = d - g.thr, fi = static_cast<float>(i);
        const float u = u0 + g.nx * fi, t = t0 - g.ny * fi;
        int s = static_cast<int>((t + g.hl) * g.sliceInv);
        s = s < 0 ? 0 : (s > g.slices - 1 ? g.slices - 1 : s);
        float* a = acc + kGeometryMoments * L * s + (i & (L - 1));
        const float wu = w * u;
        a[0] += w;
        a[L] += wu;
        a[2 * L] += w * t;
        a[3 * L] += wu * u;
    }
}

/// geometryRowsGeneric with AVX2 (check haveAvx2() first): the same sums to the bit.
void geometryRowsAvx2(const GeometrySpan* spans, int count, ptrdiff_t stride, int width,
                      const GeometryPatch& g, float* acc);

/// Adds up each slice's partial sums in double, lane by lane in order: out[4s + j] =
/// Σ_l acc[(4s + j)·8 + l] for the @p slices slices and the four moments j.
void geometryReduceGeneric(const float* acc, int slices, double* out);
/// geometryReduceGeneric with AVX2 (check haveAvx2() first): the same sums to the bit.
void geometryReduceAvx2(const float* acc, int slices, double* out);

/// How the ESF kernels bin a patch: the pixel at distance u across the edge goes to bin
/// k = ⌊(u + hw)·inv⌋ when 0 ≤ (u + hw)·inv < bins, with its offset from the bin's centre
/// δ = ((u + hw) − (k + ½)·binPx)·offsetScale, truncated to an integer.
struct EsfPatch {
    float nx, hw, inv, binPx;
    int bins;
    float offsetScale;  ///< 2048 / binPx: |δ| ≤ 1024 units, δ² sums of 2047 pixels fit 32 bits
};

/// Bit at which the pixel count is packed above the grey-level sum in a bin's first word: sums
/// of up to 4112 pixels of 255 fit below it.
constexpr int kEsfCountShift = 20;
/// Most pixels one bin may receive (the packed count and the δ² sum stay in 32 bits).
constexpr int kEsfMaxBinPixels = 2047;
/// Spare bins after an ESF's own (indices bins..bins + 7), for the pixels outside it: the generic
/// kernel uses the first, the vector kernel one per lane, so that the lanes past a row's end do
/// not queue on one bin's memory.
constexpr int kEsfSpareBins = 8;

/// The bin and offset of the pixel at lane offset @p fi of a row starting at u0 (shared by both
/// ESF kernels so that their float arithmetic is the same); the spare bin for pixels outside.
inline int esfBin(float u0, float fi, const EsfPatch& e, int32_t* offset) {
    const float uh = (u0 + e.nx * fi) + e.hw;
    const float q = uh * e.inv;
    if (!(q >= 0.0f && q < static_cast<float>(e.bins))) {
        *offset = 0;
        return e.bins;
    }
    const int k = static_cast<int>(q);
    *offset = static_cast<int32_t>((uh - (static_cast<float>(k) + 0.5f) * e.binPx) * e.offsetScale);
    return k;
}

/// The scalar ESF binning of pixels from..x1 of a row starting at x0 (see esfRowsGeneric).
inline void esfPixels(const uint8_t* r, int x0, int from, int x1, float u0, const EsfPatch& e,
                      uint32_t* acc) {
    for (int x = from; x <= x1; ++x) {
        int32_t off;
        const int k = esfBin(u0, static_cast<float>(x - x0), e, &off);
        const uint32_t v = r[x], o = static_cast<uint32_t>(off);
        uint32_t* a = acc + 4 * k;
        a[0] += v + (1u << kEsfCountShift);
        a[1] += v * v;
        a[2] += o;
        a[3] += o * o;
    }
}

/// An ESF's non-empty bins, one array per field: bin i's mean position across the edge (px from
/// the patch centre), mean grey level, the variance of its pixels' positions and of their grey
/// levels, and its pixel count (a whole number, in double: the fit weighs by it). Arrays of one
/// field let the AVX2 kernels load four neighbouring bins at once.
struct EsfBins {
    double *pos, *value, *withinVar, *pixelVar, *count;
    /// The same arrays from bin @p k on.
    EsfBins from(int k) const {
        return {pos + k, value + k, withinVar + k, pixelVar + k, count + k};
    }
};
/// Entries past the last bin that the AVX2 kernels may write into: each array of an EsfBins
/// needs this many beyond the bins it holds.
constexpr int kEsfBinSlack = 4;

/// Turns bins @p from..n−1 of the integer sums @p acc (as the ESF kernels leave them; bins of
/// @p binPx across a patch of half-width @p hw) into @p out, skipping empty bins; returns how
/// many:
/// with inv = 1/count and unit = binPx/2048, d = Σδ·unit·inv, pos = ((k + ½)·binPx − hw) + d,
/// value = Σv·inv, withinVar = max(0, Σδ²·unit·unit·inv − d²), pixelVar = max(0, Σv²·inv −
/// value²), in that order of double operations.
int esfBinsGeneric(const uint32_t* acc, int from, int n, double binPx, double hw,
                   const EsfBins& out);
/// esfBinsGeneric with AVX2 (check haveAvx2() first), four bins at a time, the non-empty ones
/// packed by a permutation: the same bins.
int esfBinsAvx2(const uint32_t* acc, int from, int n, double binPx, double hw, const EsfBins& out);

/// The fields of an ESF's bins (as in EsfBins) that the pair terms read.
struct PairInputs {
    const double *pos, *value, *withinVar;
};

/// The terms of the pairs of neighbouring bins (i, i + 1) of the @p n bins @p b that the line
/// spread's moments add up: the midpoint x[i] = ½(pos[i] + pos[i+1]), the bins' own spread
/// c[i] = gap²/12 + ½(withinVar[i] + withinVar[i+1]) (gap = pos[i+1] − pos[i]), and, with
/// step = value[i+1] − value[i], the running sums over the pairs before k as four doubles
/// sums[4k..4k+3] = Σ step, Σ step·x, Σ (step·x)·x, Σ step·c, added pair by pair from pair
/// @p from on (sums[4·from..] hold the sums before it; from = 0 starts them at 0). In that order
/// of double operations.
void pairTermsGeneric(const PairInputs& b, int from, int n, double* x, double* c, double* sums);
/// pairTermsGeneric with AVX2 (check haveAvx2() first), four pairs at a time: the same terms.
void pairTermsAvx2(const PairInputs& b, int from, int n, double* x, double* c, double* sums);

/// Bins the pixels of the @p count rows @p spans (of an image @p width pixels wide) into @p acc,
/// four unsigned words per bin plus kEsfSpareBins spare ones for the pixels outside (their sums
/// mean nothing): [Σv + count·2²⁰, Σv², Σδ, Σδ²]. Integer (wrapping) additions: any order of the
/// pixels gives the same sums. At most kEsfMaxBinPixels pixels may fall in one bin.
void esfRowsGeneric(const GeometrySpan* spans, int count, int width, const EsfPatch& e,
                    uint32_t* acc);
/// esfRowsGeneric with AVX2 (check haveAvx2() first): the same sums in bins 0..bins − 1.
void esfRowsAvx2(const GeometrySpan* spans, int count, int width, const EsfPatch& e, uint32_t* acc);

/// The pixel kernels the engine calls: AVX2 when the CPU has it and the options allow, else the
/// generic reference.
struct Kernels {
    decltype(&sobelGridRowGeneric) sobelGridRow;
    decltype(&geometryRowsGeneric) geometryRows;
    decltype(&esfRowsGeneric) esfRows;
    decltype(&geometryReduceGeneric) geometryReduce;
    decltype(&countAtLeastGeneric) countAtLeast;
    decltype(&listAtLeastGeneric) listAtLeast;
    decltype(&listLevelsAtLeastGeneric) listLevelsAtLeast;
    decltype(&levelsGeneric) levels;
    decltype(&countLevelsAtLeastGeneric) countLevelsAtLeast;
    decltype(&oneSidedSumsGeneric) oneSidedSums;
    decltype(&patchRowsGeneric) patchRows;
    decltype(&esfBinsGeneric) esfBins;
    decltype(&pairTermsGeneric) pairTerms;
    decltype(&orderKeysGeneric) orderKeys;
};

/// The kernels for options @p o (BlurOptions::simd) on this CPU: the one place that chooses
/// between the AVX2 and the generic kernels.
Kernels chooseKernels(const BlurOptions& o);

}  // namespace detail

}  // namespace infocus
