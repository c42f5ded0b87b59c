// SPDX-License-Identifier: MIT
// Blur width at straight edges: slanted-edge ESF sampling and the second moment of the line
// spread. Method and error budget: docs/blur.md.
#include "infocus/blur.h"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <span>

#include "blur_kernels.h"
#include "cpu.h"

namespace infocus {

namespace detail {

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

}  // namespace detail

namespace {

// Variance of a 1 px box (the pixel's own area), px². Its projection on any edge normal is a
// trapezoid of variance (cos²θ + sin²θ)/12 = 1/12, whatever the edge angle.
constexpr double kPixelVariance = 1.0 / 12.0;
// 10–90 % rise of a Gaussian edge per unit σ (DESIGN.md).
constexpr double kGaussianRisePerSigma = 2.5631;
// Plateau levels (grey) at which an edge counts as clipped by the sensor or the encoder.
constexpr double kClipLow = 3.0, kClipHigh = 252.0;
// Light (0..1) of the encoded value @p v (0..1) under @p tf.
double decodeLight(TransferFunction tf, double v) {
    switch (tf) {
        case TransferFunction::Srgb:  // IEC 61966-2-1
            return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
        case TransferFunction::Rec709:  // ITU-R BT.709, the inverse of its camera curve
            return v < 0.081 ? v / 4.5 : std::pow((v + 0.099) / 1.099, 1.0 / 0.45);
        case TransferFunction::Linear:
            break;
    }
    return v;
}

// The encoded value (0..1) of light @p l (0..1) under @p tf: the inverse of decodeLight.
double encodeLight(TransferFunction tf, double l) {
    l = std::clamp(l, 0.0, 1.0);
    switch (tf) {
        case TransferFunction::Srgb:
            return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
        case TransferFunction::Rec709:
            return l < 0.018 ? 4.5 * l : 1.099 * std::pow(l, 0.45) - 0.099;
        case TransferFunction::Linear:
            break;
    }
    return l;
}

constexpr int kDecodeSteps = 16;  // table entries per grey level

// Grey levels decoded to linear light (BlurOptions::transfer). Blur spreads light, so the ESF's
// profile (its line spread's moments, rise and overshoot) is taken in light: each bin's mean
// grey level goes through the inverse transfer function, tabulated every 1/16 grey level and
// interpolated (a bin's pixels lie at one place of the profile and differ by noise, over which
// the curve is nearly straight). What judges an edge stays in the frame's grey levels, where
// its thresholds were set: the plateaus' levels and contrast (encoded again), their pixels'
// spread and the clip levels; so do the candidates and the one-sided test.
struct Decoding {
    TransferFunction tf = TransferFunction::Linear;
    const std::vector<double>* table = nullptr;  // 255 × light at grey i/16; null: linear
    // The grey level of light @p level (both 0..255).
    double encode(double level) const { return 255.0 * encodeLight(tf, level / 255.0); }
};

Decoding decodingFor(TransferFunction tf) {
    if (tf == TransferFunction::Linear) return {};
    const auto make = [](TransferFunction t) {
        std::vector<double> table(255 * kDecodeSteps + 1);
        for (size_t i = 0; i < table.size(); ++i)
            table[i] = 255.0 * decodeLight(t, i / (255.0 * kDecodeSteps));
        return table;
    };
    static const std::vector<double> srgb = make(TransferFunction::Srgb);
    static const std::vector<double> rec709 = make(TransferFunction::Rec709);
    return {tf, tf == TransferFunction::Srgb ? &srgb : &rec709};
}

// Segment lengths tried per seed (halved from the longest down to 6 px: 48 → 6 is 4).
constexpr int kMaxLengths = 8;
// The straightness share e^(−bend²) of the quality (relativeBend) above which a segment
// length counts as straight: a longer length is measured only while its bend costs it less than
// half its quality. The bend widens the ESF (the edge's wander across the segment adds to its
// spread), and a longer segment of a curved edge spends more pixels to measure it wider.
constexpr double kStraightShare = 0.5;
// Half-width of the window in which the reported line-spread variance is taken, in its σ, and the
// contrast-to-spread ratio above which the spread beside an edge counts as noise (fitEsf).
constexpr double kMomentSigmas = 3.0, kCleanCnr = 20.0;
// What an edge needs to set the region's blur (measureBlur): a share of the region's best edge
// quality, and a contrast of this many times the grey-level spread beside it.
constexpr double kTrustedQuality = 0.3, kTrustedCnr = 5.0;
// The widest σ (px) at which an edge's halo is counted (BlurEstimate::haloFraction).
constexpr double kHaloSigmaPx = 2.0;
// Quality above which an edge counts towards a region's blur at all.
constexpr double kUsableQuality = 0.05;

struct Bounds {
    int x0, y0, x1, y1;  // half-open [x0, x1) × [y0, y1)
};

struct Candidate {
    int x, y;
    float gx, gy, mag2;
    size_t gridIndex;  // in CandidateGrid
};

// A region's candidate Sobel grid (the scratch of the last candidateGrid call on this thread):
// gradients and |g|² per point, row by row from (x0, y0) at step px; the region's peak |g|² and
// the least |g|² a candidate needs.
struct CandidateGrid {
    const int16_t* gx = nullptr;
    const int16_t* gy = nullptr;
    const int32_t* m = nullptr;
    size_t size = 0;
    int perRow = 0, rows = 0, step = 1, x0 = 0, y0 = 0;
    int32_t peak = 0, least = 0;
};

// An oriented rectangle on the image: centre c, unit normal n (dark → bright), tangent
// t = (−ny, nx); half-extent hw across the edge, hl along it.
struct Patch {
    double cx, cy, nx, ny, hw, hl;
    double u(double x, double y) const { return (x - cx) * nx + (y - cy) * ny; }
    double t(double x, double y) const { return -(x - cx) * ny + (y - cy) * nx; }
};

// Where an edge was measured, kept from frame to frame by BlurTracker: the patch its ESF was
// sampled in (on its fitted line), the line's straightness, the window the ESF fit's second
// start began with (0: none; measureSegment), and the derivative threshold and slice count of
// its geometry fit.
struct EdgeTrack {
    Patch patch;
    double straight = 0.0, narrowStart = 0.0, threshold = 0.0;
    int slices = 0;
};

// The pixel kernels: AVX2 when the CPU has it and the options allow, else the generic reference.
struct Kernels {
    decltype(&detail::sobelGridRowGeneric) sobelGridRow;
    decltype(&detail::geometryRowsGeneric) geometryRows;
    decltype(&detail::esfRowsGeneric) esfRows;
    decltype(&detail::geometryReduceGeneric) geometryReduce;
    decltype(&detail::countAtLeastGeneric) countAtLeast;
    decltype(&detail::listAtLeastGeneric) listAtLeast;
    decltype(&detail::listLevelsAtLeastGeneric) listLevelsAtLeast;
    decltype(&detail::levelsGeneric) levels;
    decltype(&detail::countLevelsAtLeastGeneric) countLevelsAtLeast;
    decltype(&detail::oneSidedSumsGeneric) oneSidedSums;
    decltype(&detail::patchRowsGeneric) patchRows;
    decltype(&detail::esfBinsGeneric) esfBins;
    decltype(&detail::pairTermsGeneric) pairTerms;
    decltype(&detail::orderKeysGeneric) orderKeys;
};

Kernels chooseKernels(const BlurOptions& o) {
    if (o.simd && detail::haveAvx2())
        return {
            detail::sobelGridRowAvx2,      detail::geometryRowsAvx2, detail::esfRowsAvx2,
            detail::geometryReduceAvx2,    detail::countAtLeastAvx2, detail::listAtLeastAvx2,
            detail::listLevelsAtLeastAvx2, detail::levelsAvx2,       detail::countLevelsAtLeastAvx2,
            detail::oneSidedSumsAvx2,      detail::patchRowsAvx2,    detail::esfBinsAvx2,
            detail::pairTermsAvx2,         detail::orderKeysAvx2};
    return {detail::sobelGridRowGeneric,
            detail::geometryRowsGeneric,
            detail::esfRowsGeneric,
            detail::geometryReduceGeneric,
            detail::countAtLeastGeneric,
            detail::listAtLeastGeneric,
            detail::listLevelsAtLeastGeneric,
            detail::levelsGeneric,
            detail::countLevelsAtLeastGeneric,
            detail::oneSidedSumsGeneric,
            detail::patchRowsGeneric,
            detail::esfBinsGeneric,
            detail::pairTermsGeneric,
            detail::orderKeysGeneric};
}

// The candidate grid of region @p roi: a Sobel gradient (grey levels per pixel) on a sparse grid,
// in one pass that stores the grid's gradients and magnitudes (the kernel computes only the
// grid's points) and the region's peak; the threshold relative to it then sets the least |g|².
// Scratch is reused across regions.
CandidateGrid candidateGrid(const Luma8& img, const Bounds& roi, const BlurOptions& o,
                            const Kernels& k) {
    CandidateGrid grid;
    const int step = o.candidateStep;  // ≥ 1 (sanitized)
    const int y0 = std::max(roi.y0, 1), y1 = std::min(roi.y1, img.height - 1);
    const int x0 = std::max(roi.x0, 1), x1 = std::min(roi.x1, img.width - 1);
    if (x0 >= x1 || y0 >= y1) return grid;
    const int n = x1 - x0;
    const int perRow = (n + step - 1) / step;
    const int rows = (y1 - y0 + step - 1) / step;
    const size_t gridSize = static_cast<size_t>(perRow) * rows;
    thread_local std::vector<int16_t> gridX, gridY;
    thread_local std::vector<int32_t> gridM;
    // The gradients are padded by 16 points: oneSidedSumsAvx2 reads 16 from a row's start.
    if (gridX.size() < gridSize + 16)
        gridX.resize(gridSize + 16), gridY.resize(gridSize + 16), gridM.resize(gridSize);
    int peak2 = 0;
    size_t g = 0;
    for (int y = y0; y < y1; y += step, g += perRow)
        peak2 = std::max(
            peak2, k.sobelGridRow(img.row(y - 1), img.row(y), img.row(y + 1), x0, perRow, step,
                                  img.width, gridX.data() + g, gridY.data() + g, gridM.data() + g));
    const float peak = static_cast<float>(peak2) * (1.0f / 64.0f);
    const auto thr = std::max(static_cast<float>(o.relativeGradient * o.relativeGradient * peak),
                              static_cast<float>(o.minGradient * o.minGradient));
    // A point passes when |g|²/64 ≥ thr, i.e. (|g|² an integer, the scaling by 64 exact in float)
    // when |g|² ≥ ⌈64·thr⌉.
    const auto minMag2 = static_cast<int64_t>(std::ceil(static_cast<double>(thr * 64.0f)));
    // (No point is above 2³¹: a larger threshold passes none either way.)
    const auto minM = static_cast<int32_t>(std::min<int64_t>(minMag2, INT32_MAX));
    return {gridX.data(), gridY.data(), gridM.data(), gridSize, perRow, rows,
            step,         x0,           y0,           peak2,    minM};
}

// Points of a candidate grid, handed out strongest first (CandidateList::at): the strongest
// `strongest()` of the grid's passing points, or, after a region has looked at those, the next
// weaker ones that oneSided does not pass over (weakerCandidates). A list of up to kMaxOrderKeys
// keys comes in order; the keys of a longer one are put in order a block at a time as they are
// asked for (a region looks at about 20 of its 64), each block as long as all the blocks before
// it, so that a list walked to its end is ordered in O(n log n).
class CandidateList {
public:
    CandidateList() = default;
    // The @p size keys @p keys (of @p listed, the first @p ordered of them already in order) of
    // @p grid's @p strongest strongest points, the least of which is @p lowest; @p judged when
    // oneSided has passed them.
    CandidateList(const CandidateGrid& grid, uint64_t* keys, size_t listed, size_t size,
                  size_t ordered, size_t strongest, uint64_t lowest, bool judged)
        : grid_(&grid),
          keys_(keys),
          listed_(listed),
          size_(size),
          ordered_(ordered),
          strongest_(strongest),
          lowest_(lowest),
          judged_(judged) {}
    size_t size() const { return size_; }
    // How many of the grid's strongest points the list was drawn from, and the least of them.
    size_t strongest() const { return strongest_; }
    uint64_t lowest() const { return lowest_; }
    // True when every point handed out has passed oneSided already.
    bool judged() const { return judged_; }
    // The @p i-th strongest (i < size()).
    Candidate at(size_t i) {
        while (i >= ordered_) {
            // Keys are unique (they hold the grid index), so the block after ordered_ is the
            // same whichever way the rest was left: the order is exact.
            const size_t next = std::min(size_, ordered_ + std::max(kBlock, ordered_));
            std::nth_element(keys_ + ordered_, keys_ + next, keys_ + listed_, std::greater<>());
            std::sort(keys_ + ordered_, keys_ + next, std::greater<>());
            ordered_ = next;
        }
        const size_t q = detail::candidateIndex(keys_[i]);
        return {grid_->x0 + static_cast<int>(q % grid_->perRow) * grid_->step,
                grid_->y0 + static_cast<int>(q / grid_->perRow) * grid_->step,
                grid_->gx[q] / 8.0f,
                grid_->gy[q] / 8.0f,
                static_cast<float>(grid_->m[q]) * (1.0f / 64.0f),
                q};
    }

private:
    static constexpr size_t kBlock = 16;
    const CandidateGrid* grid_ = nullptr;
    uint64_t* keys_ = nullptr;
    size_t listed_ = 0, size_ = 0, ordered_ = 0, strongest_ = 0;
    uint64_t lowest_ = 0;
    bool judged_ = false;
};

// Keys of a candidate grid's strongest points, in no order: at least the m = min(cap, passing)
// strongest, and those the only ones above the least of them.
struct ListedKeys {
    uint64_t* keys = nullptr;
    size_t listed = 0, m = 0;
    // Puts the m strongest first (in no order) and returns the least of them (m > 0). When all
    // listed keys are the m, a scan finds it: a selection over a region's whole grid (a walk on
    // noise lists every point) costs a tenth of such a frame.
    uint64_t selectStrongest() const {
        if (listed == m) return *std::min_element(keys, keys + m);
        std::nth_element(keys, keys + (m - 1), keys + listed, std::greater<>());
        return keys[m - 1];
    }
};

// The keys of the @p cap strongest passing points of @p grid (they live until the next call on
// this thread). A point is a 64-bit key, |g|² above its complemented grid index: the larger key
// is the stronger point, equal gradients in scan order, so a longer list starts with a shorter
// one. Counting the points above a level (8 at a time) finds, by bisection over 256 levels up to
// the peak, the highest level with at least cap points above it; only those points (a few dozen
// of thousands) are then listed.
ListedKeys listStrongest(const CandidateGrid& grid, const Kernels& k, size_t cap) {
    thread_local std::vector<uint64_t> keys;
    if (keys.size() < grid.size) keys.resize(grid.size);
    int shift = 0;
    while ((grid.peak >> shift) >= 256)
        ++shift;
    thread_local std::vector<uint8_t> levels;
    if (levels.size() < grid.size) levels.resize(grid.size);
    const size_t count = k.countAtLeast(grid.m, grid.size, grid.least);
    const size_t m = std::min(cap, count);
    int32_t lowest = grid.least;
    if (count > m) {
        // A level mid·2^shift above the least |g|² counts the points whose |g|² >> shift is at
        // least mid: a byte a point. At or below it, the level is the least, and count ≥ m.
        k.levels(grid.m, grid.size, shift, levels.data());
        int lo = 0, hi = 255;
        while (lo < hi) {
            const int mid = (lo + hi + 1) / 2;
            if ((mid << shift) <= grid.least ||
                k.countLevelsAtLeast(levels.data(), grid.size, static_cast<uint8_t>(mid)) >= m)
                lo = mid;
            else
                hi = mid - 1;
        }
        lowest = std::max(grid.least, lo << shift);
    }
    const size_t listed = count > m ? k.listLevelsAtLeast(levels.data(), shift, grid.m, grid.size,
                                                          lowest, keys.data())
                                    : k.listAtLeast(grid.m, grid.size, lowest, keys.data());
    return {keys.data(), listed, m};
}

// The @p cap strongest passing points of @p grid, strongest first (the list lives until the next
// call on this thread).
CandidateList strongestCandidates(const CandidateGrid& grid, const Kernels& k, size_t cap) {
    if (grid.size == 0) return {};
    const ListedKeys l = listStrongest(grid, k, cap);
    if (l.m == 0) return {};
    // The usual list (64 of some 60–100 listed) is put in order at once, without the branches
    // of a selection and a sort: those took 5 % of a frame's time.
    if (l.listed <= detail::kMaxOrderKeys) {
        thread_local std::vector<uint64_t> ordered(detail::kMaxOrderKeys);
        k.orderKeys(l.keys, l.listed, l.m, ordered.data());
        return CandidateList(grid, ordered.data(), l.m, l.m, l.m, l.m, ordered[l.m - 1], false);
    }
    // The m strongest first; their order comes as they are asked for.
    const uint64_t lowest = l.selectStrongest();
    return CandidateList(grid, l.keys, l.listed, l.m, 0, l.m, lowest, false);
}

// Radius (px, a whole number) of the square about a seed in which oneSided weighs the gradients,
// and the least value a seed needs to be measured.
constexpr int kOneSidedRadiusPx = 8;
constexpr double kMinOneSided = 0.5;

// Whether the gradient about the grid point @p q is one-sided: Σ g·n / Σ |g·n| ≥ kMinOneSided
// over the grid points within kOneSidedRadiusPx, n the point's gradient. A lone edge gives about
// 1. A bar, a thin line or crowded texture, whose two sides lie within a few pixels, gives
// gradients of both signs; its ESF has no two plateaus and the fit would lose its contrast after
// all the pixel work.
bool oneSided(const CandidateGrid& g, size_t q, const Kernels& k) {
    // The radius in grid steps, rounded half away from zero (integers: no lround a seed).
    const int r = std::max(1, (2 * kOneSidedRadiusPx + g.step) / (2 * g.step));
    const int qx = static_cast<int>(q % g.perRow);
    const int qy = static_cast<int>(q / g.perRow);
    const int32_t nx = g.gx[q], ny = g.gy[q];
    const int x0 = std::max(0, qx - r), y0 = std::max(0, qy - r);
    const size_t first = static_cast<size_t>(y0) * g.perRow + x0;
    int64_t along = 0, magnitude = 0;
    k.oneSidedSums(g.gx + first, g.gy + first, g.perRow, std::min(g.perRow - 1, qx + r) - x0 + 1,
                   std::min(g.rows - 1, qy + r) - y0 + 1, nx, ny, &along, &magnitude);
    // The sums are integers (64-bit, far from overflow), so the ratio is compared without a
    // division: along / magnitude ≥ ½ exactly when 2·along ≥ magnitude.
    static_assert(kMinOneSided == 0.5);
    return magnitude > 0 && 2 * along >= magnitude;
}

// The points among the @p cap strongest of @p grid that are weaker than @p below (the least of the
// list a region has looked at) and that oneSided does not pass over, strongest first. A region
// that asks for them has passed over all its stronger seeds (traces, text, a fine chart's bars),
// and may pass over most of these too: judging them before they are put in order spares it the
// ordering of seeds it would skip (on a chart of fine bars, every one). oneSided depends on the
// grid alone, so the region measures the seeds it would have measured, in the same order.
CandidateList weakerCandidates(const CandidateGrid& grid, const Kernels& k, size_t cap,
                               uint64_t below) {
    const ListedKeys l = listStrongest(grid, k, cap);
    if (l.m == 0) return {};
    const uint64_t lowest = l.selectStrongest();
    size_t kept = 0;
    for (size_t j = 0; j < l.m; ++j)
        if (l.keys[j] < below && oneSided(grid, detail::candidateIndex(l.keys[j]), k))
            l.keys[kept++] = l.keys[j];
    return CandidateList(grid, l.keys, kept, kept, 0, l.m, lowest, true);
}

// The rows of @p p inside @p b as kernel spans (scratch reused across calls): for every row
// holding pixel centres inside the patch, its pixels x0..x1 and the patch coordinates (u0, t0)
// of pixel x0; along the row u grows by nx and t by −ny per pixel, so the kernels step them
// instead of projecting every pixel.
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

// The directional derivative's moments in one slice along the edge: Σw, Σw·u, Σw·t, Σw·u².
struct Slice {
    double w, wu, wt, wuu;
};

// Fills @p out with the @p slices slices of @p p (equal widths along the edge) of the pixels whose
// derivative along the normal exceeds @p threshold, weighted by the excess.
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

// The edge as the line u = a + slope·t in a patch's coordinates, from slice centroids.
struct LineFit {
    bool ok = false;
    double a = 0, slope = 0;
    double straight = 0;  // RMS scatter of the centroids about the line, px
    double spread2 = 0;   // the derivative's variance across the edge within a slice, px²
};

// Weighted least squares e = a + b·t through the centroids (t_k, e_k) of the @p n slices @p s,
// weights Σw; needs three slices with an edge.
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

// Moves @p p onto the line @p f: the centre onto it, the normal turned by atan(slope)
// (n' ∝ n − slope·t̂).
void moveOnto(Patch& p, const LineFit& f) {
    p.cx += f.a * p.nx;
    p.cy += f.a * p.ny;
    const double nx = p.nx + f.slope * p.ny, ny = p.ny - f.slope * p.nx;
    const double len = std::hypot(nx, ny);
    p.nx = nx / len;
    p.ny = ny / len;
}

// An ESF's non-empty bins (see detail::EsfBins), in ascending position; scratch reused.
struct BinList {
    std::vector<double> pos, value, withinVar, pixelVar, count;
    size_t size = 0;
    // Room for @p n bins and the kernels' slack; the arrays to fill.
    detail::EsfBins reserve(size_t n) {
        for (auto* v : {&pos, &value, &withinVar, &pixelVar, &count})
            if (v->size() < n + detail::kEsfBinSlack) v->resize(n + detail::kEsfBinSlack);
        return {pos.data(), value.data(), withinVar.data(), pixelVar.data(), count.data()};
    }
};

struct EsfFit {
    bool ok = false;
    bool needWider = false;  // the edge's spread does not fit in the sampled width
    double mean = 0, varLsf = 0, lo = 0, contrast = 0, noise = 0, rise = 0, binVar = 0;
    double varCore = 0;        // line-spread variance in the narrow window: the width reported
    double overshoot = 0;      // largest excursion past a plateau, fraction of the contrast
    double plateauPixels = 0;  // pixels beside the window that set the plateau levels
    // lo and contrast of the profile itself: in light where the frame is decoded (Decoding),
    // else lo and contrast.
    double profileLo = 0, profileContrast = 0;
};

// Centroid and variance of the line spread between bins @p il and @p ir, the ESF taken as @p lo
// at il and @p hi at ir (the plateau levels), and the mean variance of the bins' own spread
// (spacing²/12 + within-bin variance of the positions) that each difference of two bins adds.
struct Moments {
    double mean, var, binVar;
};

// Fewest non-empty bins an ESF needs to be fitted.
constexpr size_t kMinEsfBins = 8;

// The terms of each pair of neighbouring bins (i, i + 1) that lineSpreadMoments adds up, computed
// once per ESF (detail::pairTermsGeneric): the running sums of the step and its products (so that
// the fit's every window costs the same whatever its width), and the midpoint x and the bins' own
// spread c for the window's end pairs, whose step runs from or to a plateau level instead.
struct PairTerms {
    std::vector<double> x, c, sums;
    /// Makes the terms of @p bins due: they are computed when a fit first asks for them (get).
    /// A fit that ends at its first window (the ESF's two ends within minContrast, or too few
    /// bins) asks for none: on the 12 px bench frame a fifth of the ESFs' pixels go to such fits.
    void defer(const BinList& bins, const Kernels& k) { src = &bins, kernels = &k, ready = false; }
    /// The terms of the bins last deferred (whose BinList must still hold them), computed on the
    /// first call.
    const PairTerms& get() {
        if (!ready) set(*src, *kernels), ready = true;
        return *this;
    }

private:
    const BinList* src = nullptr;
    const Kernels* kernels = nullptr;
    bool ready = false;
    void set(const BinList& bins, const Kernels& k) {
        const size_t n = bins.size;
        if (x.size() < n + detail::kEsfBinSlack)
            x.resize(n + detail::kEsfBinSlack), c.resize(n + detail::kEsfBinSlack);
        if (sums.size() < 4 * (n + 1)) sums.resize(4 * (n + 1));
        k.pairTerms({bins.pos.data(), bins.value.data(), bins.withinVar.data()}, 0,
                    static_cast<int>(n), x.data(), c.data(), sums.data());
    }
};

// The moments of the line spread (see Moments) from the pair terms @p t of @p bins.
Moments lineSpreadMoments(const PairTerms& t, size_t il, size_t ir, double lo, double hi,
                          const BinList& bins) {
    double m0 = 0, m1 = 0, m2 = 0, corr = 0;
    auto add = [&](size_t i, double l) {
        m0 += l;
        m1 += l * t.x[i];
        m2 += l * t.x[i] * t.x[i];
        corr += l * t.c[i];
    };
    // The first pair steps up from the low plateau, the last to the high one; the pairs between
    // them from the running sums.
    add(il, (il + 1 == ir ? hi : bins.value[il + 1]) - lo);
    if (ir > il + 2) {
        const double* a = t.sums.data() + 4 * (il + 1);
        const double* b = t.sums.data() + 4 * (ir - 1);
        m0 += b[0] - a[0];
        m1 += b[1] - a[1];
        m2 += b[2] - a[2];
        corr += b[3] - a[3];
    }
    if (ir > il + 1) add(ir - 1, hi - bins.value[ir - 1]);
    const double mean = m1 / m0;
    return {mean, m2 / m0 - mean * mean, corr / m0};
}

// The number of leading @p bins (in ascending position) for which @p before holds of its position
// (it holds for a prefix of them), by a bisection whose steps are conditional moves: the fit asks
// for a window's ends many times an ESF, and the branches of a plain bisection over 50–100 bins
// mispredict.
template <class Before>
size_t countBefore(const BinList& bins, Before before) {
    if (bins.size == 0) return 0;
    const double* base = bins.pos.data();
    for (size_t len = bins.size; len > 1;) {
        const size_t half = len / 2;
        base = before(base[half]) ? base + half : base;
        len -= half;
    }
    return static_cast<size_t>(base - bins.pos.data()) + (before(*base) ? 1 : 0);
}
// Index of the first of @p bins whose position exceeds @p x, and of the first at or right of it.
size_t firstAfter(const BinList& bins, double x) {
    return countBefore(bins, [x](double pos) { return pos <= x; });
}
size_t firstAtOrAfter(const BinList& bins, double x) {
    return countBefore(bins, [x](double pos) { return pos < x; });
}

// Calls @p fn(centre, mean) for each bin from the first at or after @p from while its position
// is at most @p to: mean is the ESF averaged over 1 px there (the bin and those less than 1 px
// after it, by a running sum), centre the middle of those bins' positions.
template <class Fn>
void forEachPixelMean(const BinList& bins, double from, double to, Fn&& fn) {
    const double* pos = bins.pos.data();
    const double* value = bins.value.data();
    const double* count = bins.count.data();
    const size_t size = bins.size;
    size_t i = firstAtOrAfter(bins, from), j = i;
    double sum = 0.0;
    double n = 0.0;  // a whole number of pixels
    for (; i < size && pos[i] <= to; ++i) {
        for (; j < size && pos[j] < pos[i] + 1.0; ++j)
            sum += value[j] * count[j], n += count[j];
        fn(0.5 * (pos[i] + pos[j - 1]), sum / n);
        sum -= value[i] * count[i], n -= count[i];
    }
}

// Sharpening halos of the ESF @p bins about an edge at @p mu whose line spread has the standard
// deviation @p sd (px): the lesser of the two sides' excursions past their far plateaus (the
// outermost 2 px of each side), on the ESF averaged over 1 px, within 2.5 sd + 2.5 px of the
// edge, as a fraction of the far plateaus' contrast. Blur by any PSF keeps an edge's profile
// between its plateaus, so a clean edge gives about 0; an unsharp mask raises a bright halo on
// one side and a dark one on the other. Clutter (another edge in one side) mostly gives one.
double esfHalo(const BinList& bins, double mu, double sd) {
    const double* pos = bins.pos.data();
    const double* value = bins.value.data();
    const double* count = bins.count.data();
    const size_t size = bins.size;
    if (size < 2) return 0.0;
    double sumLo = 0, nLo = 0, sumHi = 0, nHi = 0;
    for (size_t k = 0; k < size && pos[k] < pos[0] + 2.0; ++k)
        sumLo += value[k] * count[k], nLo += count[k];
    for (size_t k = size; k-- > 0 && pos[k] > pos[size - 1] - 2.0;)
        sumHi += value[k] * count[k], nHi += count[k];
    const double lo = sumLo / nLo, hi = sumHi / nHi;
    if (!(hi > lo)) return 0.0;
    const double reach = 2.5 * sd + 2.5;
    double above = 0.0, below = 0.0;
    // From 1 px before the reach, so that every 1 px mean centred within it is seen.
    forEachPixelMean(bins, mu - reach - 1.0, mu + reach, [&](double centre, double v) {
        if (std::abs(centre - mu) > reach) return;
        if (centre > mu)
            above = std::max(above, v - hi);
        else
            below = std::max(below, lo - v);
    });
    return std::min(above, below) / (hi - lo);
}

// Second moment of the line spread from the binned ESF. The edge's extent is found in a window
// grown or shrunk to 4 σ + 1 px about the centroid (holds 99.99 % of a Gaussian and all of a
// disc), with the plateau levels just outside it; that window's variance (varLsf) rates and
// screens the edge. Noise in a bin weighs on the moment with the square of its distance from the
// centroid, so its share grows as the window's cube: for a sharp edge the wide window is mostly
// noise (a 0.7 px Gaussian scattered 4–6 % per edge at 2 % noise). The width reported (varCore) is
// therefore taken in a ±3 σ window about the centroid, the ESF beyond it set to the same plateau
// levels, so the tail mass between 3 σ and the plateaus (0.27 % of a Gaussian, none of a disc)
// is kept, placed at the window's edge. That misses (x² − 9σ²) over a Gaussian's tails, 0.5 % of
// its variance (σ 0.25 % low), and nothing of a disc from d = 2 px up (its projection ends at
// 2 σ, the pixel's at 0.71 px). The bins' own spread is removed here, the pixel's 1/12 by the
// caller. The window starts over the whole patch (@p halfWidth about its middle), or, with
// @p startRadius > 0, over ±startRadius about the patch's line (u = 0).
EsfFit fitEsf(const BinList& bins, PairTerms& terms, double halfWidth, double minContrast,
              const Decoding& dec, double startRadius = 0.0) {
    EsfFit f;
    const size_t size = bins.size;
    if (size < kMinEsfBins) return f;
    const double* pos = bins.pos.data();
    const double* value = bins.value.data();
    const double* count = bins.count.data();
    const double* pixelVar = bins.pixelVar.data();
    const double first = pos[0], last = pos[size - 1];
    double mu = 0.5 * (first + last), radius = halfWidth;
    if (startRadius > 0.0) mu = 0.0, radius = std::min(startRadius, halfWidth);
    constexpr double kPlateauPx = 2.0;
    for (int iter = 0; iter < 6; ++iter) {
        const double wl = mu - radius, wr = mu + radius;
        // Plateau levels: mean over up to 2 px just outside the window (or the outermost bin).
        // The bins are in ascending position: the window's ends by bisection, then only the
        // plateau bins are visited (left before right, as a full scan would add them).
        double sl = 0, nl = 0, sr = 0, nr = 0, pv = 0, npv = 0;
        // First bin right of wl (pos > wl), first bin at or right of wr.
        const size_t afterL = firstAfter(bins, wl);
        const size_t atR = firstAtOrAfter(bins, wr);
        size_t il = afterL > 0 ? afterL - 1 : 0;
        size_t ir = std::min(atR, size - 1);
        {
            size_t i = afterL;
            while (i > 0 && pos[i - 1] > wl - kPlateauPx)
                --i;
            for (; i < afterL; ++i) {
                sl += value[i] * count[i], nl += count[i];
                pv += pixelVar[i] * count[i], npv += count[i];
            }
        }
        for (size_t i = atR; i < size && pos[i] < wr + kPlateauPx; ++i) {
            sr += value[i] * count[i], nr += count[i];
            pv += pixelVar[i] * count[i], npv += count[i];
        }
        if (wl < first) il = 0;
        if (wr > last) ir = size - 1;
        const double lo = nl > 0 ? sl / nl : value[il];
        const double hi = nr > 0 ? sr / nr : value[ir];
        // The edge is judged in the frame's grey levels (Decoding), its profile taken in light.
        const double judgedLo = dec.table ? dec.encode(lo) : lo;
        const double contrast = dec.table ? dec.encode(hi) - judgedLo : hi - lo;
        if (contrast < minContrast || ir <= il + 2) return f;
        const Moments m = lineSpreadMoments(terms.get(), il, ir, lo, hi, bins);
        mu = m.mean;
        const double var = m.var;
        f.binVar = m.binVar;
        f.varLsf = var - f.binVar;
        f.contrast = contrast;
        f.lo = judgedLo;
        f.profileLo = lo;
        f.profileContrast = hi - lo;
        f.mean = mu;
        f.noise = npv > 0 ? std::sqrt(pv / npv) : 0.0;
        f.plateauPixels = npv;
        const double newRadius = 4.0 * std::sqrt(std::max(var, 0.05)) + 1.0;
        const bool converged = std::abs(newRadius - radius) < 0.05;
        radius = newRadius;
        if (converged) break;
    }
    // The window and a plateau beside it must lie inside what was sampled.
    if (mu - radius - 1.0 < first || mu + radius + 1.0 > last) {
        f.needWider = true;
        return f;
    }
    // The variance in the narrow window, sized by the σ of the wide one (not iterated: a window
    // sized by its own σ can settle on a step of clutter). Only where the spread beside the edge
    // is small against the contrast: the scatter it removes is that of white noise, while a
    // plateau spread of clutter (other edges, texture along the edge) means the ESF outside 3 σ
    // is no tail of this edge's PSF either way, and the wide window's value is kept.
    {
        const double half = kMomentSigmas * std::sqrt(std::max(f.varLsf + f.binVar, 0.05));
        const double wl = f.mean - half, wr = f.mean + half;
        // The last bin at or left of wl (or the first), the first at or right of wr (or the last).
        const size_t afterL = firstAfter(bins, wl);
        const size_t il = afterL > 0 ? afterL - 1 : 0;
        const size_t ir = std::min(firstAtOrAfter(bins, wr), size - 1);
        f.varCore = f.varLsf;
        if (ir > il + 2 && f.contrast >= kCleanCnr * std::max(f.noise, 0.5)) {
            const Moments m = lineSpreadMoments(terms.get(), il, ir, f.profileLo,
                                                f.profileLo + f.profileContrast, bins);
            f.varCore = m.var - m.binVar;
        }
    }
    // 10–90 % rise of the sampled ESF, searched outwards from the centroid.
    double x10 = mu, x90 = mu;
    // The last bin left of the centroid (or the first).
    const size_t beforeMu = firstAtOrAfter(bins, mu);
    const size_t c = beforeMu > 0 ? beforeMu - 1 : 0;
    auto level = [&](size_t i) { return (value[i] - f.profileLo) / f.profileContrast; };
    for (size_t i = c; i > 0; --i) {
        const double a = level(i - 1), b = level(i);
        if (a <= 0.1 && b > 0.1) {
            x10 = pos[i - 1] + (0.1 - a) / (b - a) * (pos[i] - pos[i - 1]);
            break;
        }
    }
    for (size_t i = c; i + 1 < size; ++i) {
        const double a = level(i), b = level(i + 1);
        if (a < 0.9 && b >= 0.9) {
            x90 = pos[i] + (0.9 - a) / (b - a) * (pos[i + 1] - pos[i]);
            break;
        }
    }
    f.rise = x90 - x10;
    // A clean edge rises monotonically from one plateau to the other. A second edge inside the
    // window (a thin line, a small blob, crowded texture) overshoots a plateau: measure by how
    // much, on the ESF averaged over 1 px so that noise does not count.
    double overshoot = 0.0;
    forEachPixelMean(bins, mu - radius, mu + radius, [&](double, double v) {
        overshoot = std::max({overshoot, v - (f.profileLo + f.profileContrast), f.profileLo - v});
    });
    f.overshoot = overshoot / f.profileContrast;
    f.ok = true;
    return f;
}

// Bins the pixels of @p p by their distance across the edge (the slanted-edge ESF) into @p bins,
// their mean grey levels decoded to light by @p dec.
void sampleEsf(const Luma8& img, const Bounds& b, const Kernels& k, const Patch& p, double binPx,
               const Decoding& dec, BinList& bins) {
    const int n = static_cast<int>(std::ceil(2.0 * p.hw / binPx));
    const auto bp = static_cast<float>(binPx);
    const detail::EsfPatch e{
        static_cast<float>(p.nx), static_cast<float>(p.hw), 1.0f / bp, bp, n, 2048.0f / bp};
    // Four integer sums per bin and the spare ones (see blur_kernels.h); scratch reused.
    thread_local std::vector<uint32_t> acc;
    acc.assign(4 * static_cast<size_t>(n + detail::kEsfSpareBins), 0u);
    const auto& spans = patchSpans(img, b, p, k);
    k.esfRows(spans.data(), static_cast<int>(spans.size()), img.width, e, acc.data());
    // Written in place, one division per bin: this runs for every bin of every ESF, a hundred
    // thousand times a frame.
    bins.size = static_cast<size_t>(k.esfBins(acc.data(), 0, n, binPx, p.hw, bins.reserve(n)));
    if (!dec.table) return;
    const std::vector<double>& t = *dec.table;
    for (size_t i = 0; i < bins.size; ++i) {
        const double x = bins.value[i] * kDecodeSteps;
        const auto j = std::min(static_cast<size_t>(x), t.size() - 2);
        bins.value[i] = t[j] + (x - static_cast<double>(j)) * (t[j + 1] - t[j]);
    }
}

// Half-width (px) of the slab across the edge in which the geometry is first fitted.
constexpr double kProbeHalfWidthPx = 6.0;
// Ranges of the options (BlurOptions, sanitized): the shortest segment measured (its half-length,
// px), the widest ESF half-width (px; a blur of some 800 px), the most edges a region and the
// coarsest candidate grid.
constexpr double kShortestHalfLengthPx = 6.0, kMaxHalfWidthPx = 1024.0;
constexpr int kMaxEdgesPerRegion = 256, kMaxCandidateStep = 64;

// An edge's bend in units of what its blur tolerates: its straightness (RMS scatter of the slice
// centroids, px) over 0.3 px + a quarter of its σ (px). The quality's straightness share is
// e^(−bend²), both for a measured edge and for judging a probe's segment lengths.
double relativeBend(double straightPx, double sigmaPx) {
    return straightPx / (0.3 + 0.25 * sigmaPx);
}

// The measurement of the edge on @p patch from its ESF fit @p f of @p bins.
EdgeMeasurement makeMeasurement(const Patch& patch, const EsfFit& f, const BinList& bins,
                                double straight, const BlurOptions& o) {
    EdgeMeasurement m;
    m.cx = patch.cx + f.mean * patch.nx;
    m.cy = patch.cy + f.mean * patch.ny;
    m.angleDeg = std::atan2(patch.ny, patch.nx) * 180.0 / std::numbers::pi;
    m.contrast = f.contrast;
    m.noise = f.noise;
    m.sigmaPx = std::sqrt(std::max(0.0, f.varCore - kPixelVariance));
    m.riseRawPx = f.rise;
    // The sampled rise includes the pixel area and the bins' own spread; remove them as Gaussian
    // shares in quadrature (exact for a Gaussian PSF, close for a disc, whose rise per σ is 2.7482
    // rather than 2.5631). Near 0° and 45° the ESF is sampled at whole-pixel spacing, too coarse
    // to interpolate a crossing: there the Gaussian model's rise of the measured σ stands in.
    const double floorRise2 =
        kGaussianRisePerSigma * kGaussianRisePerSigma * (kPixelVariance + f.binVar);
    const bool dense = f.binVar <= 2.0 * o.binPx * o.binPx / 6.0;
    m.edgeWidthPx = dense ? std::sqrt(std::max(0.0, f.rise * f.rise - floorRise2))
                          : kGaussianRisePerSigma * m.sigmaPx;
    m.straightnessPx = straight;
    // Halos only where a region may count them (blurFromEdges): a clean, sharp edge.
    if (m.sigmaPx <= kHaloSigmaPx && f.contrast >= kCleanCnr * std::max(f.noise, 0.5))
        m.haloFraction = esfHalo(bins, f.mean, std::sqrt(std::max(f.varLsf, 0.0)));
    const double sd = std::sqrt(std::max(f.varLsf, kPixelVariance));
    const double cnr = f.contrast / std::max(f.noise, 0.5);
    const double bend = relativeBend(straight, sd);
    const double over = f.overshoot / 0.25;
    m.quality = (1.0 - std::exp(-cnr / 5.0)) * std::exp(-bend * bend - over * over);
    return m;
}

// σ (px) of the line spread guessed from the spread of the thresholded derivative across the
// edge (spread2, px²): a Gaussian's derivative above 0.2 of its peak has 0.72 σ, a disc's 0.95 σ.
double guessSigma(const LineFit& f) {
    return 1.2 * std::sqrt(f.spread2);
}
// The largest σ a guessed σ @p sd allows: a Gaussian's, whose thresholded derivative is the
// narrowest for its σ (the guess is 1.2 × 0.72 σ for it, 1.2 × 0.95 σ for a disc).
double largestSigma(double sd) {
    return sd / (1.2 * 0.72);
}

// Whether the fit @p f measures an edge: fitted, and neither clipped nor collapsed. A clipped
// edge (a plateau at black or white) has lost the part of its spread beyond the clip, so its
// moment says nothing about the blur; an LSF narrower than half the pixel's own spread is no
// imaged edge (JPEG block seams, a window collapsed on clutter), and a fit without plateau
// pixels has nothing to trust.
bool usable(const EsfFit& f) {
    return f.ok && f.lo > kClipLow && f.lo + f.contrast < kClipHigh &&
           f.varLsf >= 0.5 * kPixelVariance && f.plateauPixels > 0;
}

// The line of the edge in @p patch fitted again in the patch's own slab (@p slices slices along
// it, derivative above @p threshold), and the patch moved onto it; empty when too few slices
// hold an edge.
std::optional<LineFit> refitOnto(const Luma8& img, const Bounds& b, const Kernels& k, Patch& patch,
                                 double threshold, int slices) {
    thread_local std::vector<Slice> sl;
    sl.resize(slices);
    geometrySlices(img, b, k, patch, threshold, slices, sl.data());
    const LineFit line = fitLine(sl.data(), slices);
    if (!line.ok) return std::nullopt;
    moveOnto(patch, line);
    return line;
}

// The ESF fit of @p bins over the whole patch and, when that gives no usable edge and
// @p narrowStart is above 0, the fit of the same bins from a window of ±narrowStart about the
// line (measureSegment says why), kept only where it gives one.
EsfFit fitWithSecondStart(const BinList& bins, PairTerms& terms, double halfWidth,
                          double minContrast, double narrowStart, const Decoding& dec) {
    const EsfFit f = fitEsf(bins, terms, halfWidth, minContrast, dec);
    if (usable(f) || narrowStart <= 0.0) return f;
    const EsfFit g = fitEsf(bins, terms, halfWidth, minContrast, dec, narrowStart);
    return usable(g) ? g : f;
}

// The half-width a patch of half-width @p hw is widened to when the line spread of fit @p f does
// not fit in it: 1.6 × as wide, and at least 4 σ + 4 px of that spread, up to maxHalfWidthPx.
double widerHalfWidth(const EsfFit& f, double hw, const BlurOptions& o) {
    const double sd = std::sqrt(std::max(f.varLsf, 0.1));
    return std::min(o.maxHalfWidthPx, std::max(1.6 * hw, 4.0 * sd + 4.0));
}

// Measures the edge along @p patch (on the edge's line, half-length set, @p slices slices along
// it) from the line @p line found in the probe. The ESF is sampled as wide as the guessed blur
// needs; where the probe's slab may have cut the derivative, the geometry is refitted in the
// patch's own slab and the ESF widened while its line spread does not fit. On return @p patch is
// where the edge was sampled.
std::optional<EdgeMeasurement> measureSegment(const Luma8& img, const Bounds& b,
                                              const BlurOptions& o, const Kernels& k, Patch& patch,
                                              double threshold, LineFit line, int slices,
                                              EdgeTrack& track) {
    const double sd0 = guessSigma(line);
    patch.hw = std::clamp(4.5 * sd0 + 3.5, kProbeHalfWidthPx, o.maxHalfWidthPx);
    // The probe's slab (±kProbeHalfWidthPx about the seed) cut the derivative where the line,
    // at its furthest from the seed along the segment, plus 3 σ of the guessed spread reaches
    // the slab's side: then the line is fitted again in the patch's own slab. Otherwise every
    // slice held its derivative and the probe's centroids stand.
    const bool cut =
        std::abs(line.a) + std::abs(line.slope) * patch.hl + 3.0 * sd0 > kProbeHalfWidthPx;
    bool refit = cut;
    const Decoding dec = decodingFor(o.transfer);
    thread_local BinList bins;
    for (int pass = 0; pass < 6; ++pass) {
        if (refit) {
            const auto fitted = refitOnto(img, b, k, patch, threshold, slices);
            if (!fitted) return std::nullopt;
            line = *fitted;
        }
        sampleEsf(img, b, k, patch, o.binPx, dec, bins);
        // The bin-pair terms at most once per ESF: every fit of these bins that gets past its
        // first window reads them.
        thread_local PairTerms terms;
        terms.defer(bins, k);
        // The window started over the whole patch takes in, on crowded texture, the edges beside
        // this one, and may wander off it or lose its contrast. Where the probe's slab held the
        // derivative, the σ guessed from it bounds the edge's own line spread: the same bins are
        // fitted again from a window that holds just that, ±(4 σ + 1 px) of the largest σ the
        // guess allows, about the line. Only as a second chance: where the whole patch gives an
        // edge, it stands (near a chequerboard's corner the narrow start misses the corner's
        // clutter and reads the edge narrow). No pixel is read again. On the bench frame more
        // seeds give an edge, and 142 regions of 144 measure instead of 132 (docs/blur.md).
        const double narrowStart = pass == 0 && !cut ? 4.0 * largestSigma(sd0) + 1.0 : 0.0;
        const EsfFit f = fitWithSecondStart(bins, terms, patch.hw, o.minContrast, narrowStart, dec);
        if (usable(f)) {
            track = {patch, line.straight, narrowStart, threshold, slices};
            return makeMeasurement(patch, f, bins, line.straight, o);
        }
        if (f.ok) return std::nullopt;  // fitted, but clipped or collapsed: no wider patch helps
        if (!f.needWider || patch.hw >= o.maxHalfWidthPx) return std::nullopt;
        // A derivative held well inside the probe's slab, with a line spread that does not fit
        // in 4.5 σ + 3.5 px of it: the extra spread is another edge, shading or texture beside
        // this one, not its blur (on the bench frame, 91 of 112 such segments ended without a
        // usable edge once widened). Only an edge whose derivative the slab may have cut, a wide
        // blur, is widened.
        if (!cut) return std::nullopt;
        patch.hw = widerHalfWidth(f, patch.hw, o);
        refit = true;
    }
    return std::nullopt;
}

// The part of @p r inside a @p w × @p h image (intersect: a rectangle near INT_MAX clips).
Bounds clipRect(const Rect& r, int w, int h) {
    const Rect c = intersect(r, {0, 0, w, h});
    return {c.x, c.y, c.x + c.w, c.y + c.h};
}

// Asks the cache for the pixels the candidate pass of the next region will read, a few rows at
// a time while the current region is measured. A 1080p frame (2 MB) does not stay in a core's
// L2 cache (1 MB here) from one pass over the regions to the next, and the Sobel pass reads each
// region row by row, a stride apart, with nothing else to do while a row comes from memory: on
// the bench frame it took 1.8 M cycles a frame when its rows were cold and 0.6 M when warm.
// Fetched during the seeds' pixel work, which reads only what the Sobel pass already brought in,
// the rows arrive in time. Empty (no region) does nothing.
class RowPrefetcher {
public:
    RowPrefetcher() = default;
    RowPrefetcher(const Luma8& img, const Rect& roi) : img_(&img) {
        const Bounds b = clipRect(roi, img.width, img.height);
        // The rows and columns the candidate Sobel reads (its vector loads reach 32 px on).
        y_ = std::max(b.y0 - 1, 0), y1_ = std::min(b.y1 + 1, img.height);
        xa_ = std::max(b.x0 - 1, 0), xb_ = std::min(b.x1 + 32, img.width - 1);
        if (b.x0 >= b.x1 || b.y0 >= b.y1) y_ = y1_;  // an empty region: nothing to fetch
    }
    // Asks for the next @p rows rows.
    void fetch(int rows) {
        constexpr int kLine = 64;
        for (const int end = std::min(y_ + rows, y1_); y_ < end; ++y_) {
            const uint8_t* row = img_->row(y_);
            for (int x = xa_; x < xb_; x += kLine)
                __builtin_prefetch(row + x);
            __builtin_prefetch(row + xb_);
        }
    }
    // Asks for every row not asked for yet.
    void finish() { fetch(y1_ - y_); }

private:
    const Luma8* img_ = nullptr;
    int y_ = 0, y1_ = 0, xa_ = 0, xb_ = 0;
};

// Rows of the next region asked for per seed tried: about a region's worth over the 16 or so
// seeds a region of the bench's grid looks at (most are passed over cheaply).
constexpr int kPrefetchRowsPerSeed = 8;

// @p given with every knob in its range (blur.h): a value outside it taken as the nearest one
// inside, one that is not a number as the default. The engine's sizes follow from these (the
// bins of a patch, the slices of a probe, the candidate grid), so an unchecked value would cost
// memory or read past the scratch rather than only give a poor measurement.
BlurOptions sanitized(const BlurOptions& given) {
    const BlurOptions defaults;
    const auto in = [](double v, double fallback, double lo, double hi) {
        return std::isnan(v) ? fallback : std::clamp(v, lo, hi);
    };
    // The ESF kernels' integer sums hold kEsfMaxBinPixels pixels a bin: bins of at most 1 px
    // along segments of at most 2 × 500 px (a bin of an axis-aligned edge takes one column of
    // the patch, one pixel a row).
    constexpr double kMaxHalfLengthPx = 500.0;
    static_assert(2 * kMaxHalfLengthPx + 1 <= detail::kEsfMaxBinPixels);
    BlurOptions o = given;
    o.maxEdges = std::clamp(given.maxEdges, 1, kMaxEdgesPerRegion);
    o.candidateStep = std::clamp(given.candidateStep, 1, kMaxCandidateStep);
    // 0 (or less, or not a number) picks the length from the region; a length is at least the
    // shortest segment measured.
    o.edgeHalfLengthPx =
        given.edgeHalfLengthPx > 0.0
            ? std::clamp(given.edgeHalfLengthPx, kShortestHalfLengthPx, kMaxHalfLengthPx)
            : 0.0;
    o.maxHalfWidthPx =
        in(given.maxHalfWidthPx, defaults.maxHalfWidthPx, kProbeHalfWidthPx, kMaxHalfWidthPx);
    o.binPx = in(given.binPx, defaults.binPx, 1.0 / 16.0, 1.0);
    o.minContrast = in(given.minContrast, defaults.minContrast, 0.0, 255.0);
    o.minGradient = in(given.minGradient, defaults.minGradient, 0.0, 1020.0);
    o.relativeGradient = in(given.relativeGradient, defaults.relativeGradient, 0.0, 1.0);
    o.opticsFloorSigmaPx = in(given.opticsFloorSigmaPx, 0.0, 0.0, kMaxHalfWidthPx);
    if (given.transfer != TransferFunction::Srgb && given.transfer != TransferFunction::Rec709)
        o.transfer = TransferFunction::Linear;
    return o;
}

// What the seeds of one region share: the region, where sampling may reach, and the segment
// lengths tried (halved from the longest down to 6 px), whose probe slices nest: the central
// 4·2^j of them cover the j-th shortest length.
struct RegionSetup {
    Bounds r, sb;
    double halfLength = 0.0;
    double lengths[kMaxLengths] = {};
    int nLengths = 0, slices = 0;
};

// The setup of region @p roi of @p luma, @p o sanitized; empty when the region or the image is
// too small to hold a 3 × 3 gradient.
std::optional<RegionSetup> regionSetup(const Luma8& luma, const Rect& roi, const BlurOptions& o) {
    if (luma.empty() || luma.width < 3 || luma.height < 3) return std::nullopt;
    RegionSetup s;
    s.r = clipRect(roi, luma.width, luma.height);
    if (s.r.x1 - s.r.x0 < 3 || s.r.y1 - s.r.y0 < 3) return std::nullopt;
    // Sampling stays one pixel inside the image: the derivative needs both neighbours.
    const Bounds sb = o.sampleOutsideRoi ? Bounds{0, 0, luma.width, luma.height} : s.r;
    s.sb = {std::max(sb.x0, 1), std::max(sb.y0, 1), std::min(sb.x1, luma.width - 1),
            std::min(sb.y1, luma.height - 1)};
    // Longer segments average more pixels per ESF bin (less noise) but must stay straight and
    // inside the region's scale: a quarter of the region's smaller side unless told.
    s.halfLength = o.edgeHalfLengthPx > 0
                       ? o.edgeHalfLengthPx
                       : std::clamp(0.25 * std::min(s.r.x1 - s.r.x0, s.r.y1 - s.r.y0), 8.0, 48.0);
    for (double len = s.halfLength; len >= kShortestHalfLengthPx && s.nLengths < kMaxLengths;
         len *= 0.5)
        s.lengths[s.nLengths++] = len;
    s.slices = 4 << (s.nLengths - 1);
    return s;
}

// The edge at seed @p c of a region set up as @p s: the best of its segment lengths, or none.
// @p covered is set to the patch along the seed's edge (over the full length), so that later
// seeds on the same edge are skipped, measured or not, and @p track to where the edge was
// measured.
std::optional<EdgeMeasurement> measureSeed(const Luma8& luma, const RegionSetup& s,
                                           const BlurOptions& o, const Kernels& k,
                                           const Candidate& c, Patch& covered, EdgeTrack& track) {
    thread_local std::vector<Slice> probe;
    probe.resize(s.slices);
    // One probe along the longest segment in a narrow slab about the seed's gradient: the
    // slices' derivative centroids give every length's line and straightness at once.
    const double g = std::sqrt(c.mag2);
    const double threshold = 0.2 * g;
    const Patch seed{c.x + 0.5, c.y + 0.5, c.gx / g, c.gy / g, kProbeHalfWidthPx, s.halfLength};
    geometrySlices(luma, s.sb, k, seed, threshold, s.slices, probe.data());
    // Long segments average more pixels; curved or crowded edges (texture) only stay straight
    // and clean over a short one. Lengths are judged shortest first: a longer one only while
    // the shorter is straight, since an edge that bends over a short segment bends more over
    // a long one (straight: kStraightShare). The longest straight one is measured, then,
    // while none rates above 0.3, the next shorter ones (three tries in all).
    LineFit fits[kMaxLengths];
    double share[kMaxLengths] = {};
    int longest = -1, bestShare = -1;
    for (int j = s.nLengths - 1; j >= 0; --j) {
        const int m = s.slices >> j;
        fits[j] = fitLine(probe.data() + (s.slices - m) / 2, m);
        if (!fits[j].ok) continue;  // too few slices with an edge (a border): try longer
        const double sd = std::max(guessSigma(fits[j]), std::sqrt(kPixelVariance));
        const double bend = relativeBend(fits[j].straight, sd);
        share[j] = std::exp(-bend * bend);
        if (bestShare < 0 || share[j] > share[bestShare]) bestShare = j;
        if (share[j] <= kStraightShare) break;
        longest = j;
    }
    std::optional<EdgeMeasurement> best;
    covered = seed;
    int tries = 0;
    const int from = longest >= 0 ? longest : bestShare;
    for (int j = from; j >= 0 && j < s.nLengths && tries < 3; ++j) {
        if (!fits[j].ok || (longest >= 0 && share[j] <= kStraightShare)) continue;
        ++tries;
        Patch p = seed;
        p.hl = s.lengths[j];
        moveOnto(p, fits[j]);
        EdgeTrack t;
        const auto m = measureSegment(luma, s.sb, o, k, p, threshold, fits[j], s.slices >> j, t);
        if (tries == 1) covered = p;
        if (m && (!best || m->quality > best->quality)) {
            best = m;
            covered = p;
            track = t;
        }
        if (best && best->quality > 0.3) break;
    }
    covered.hl = s.halfLength;
    return best;
}

// measureEdges with @p options already sanitized, asking the cache for the pixels of @p next
// meanwhile. When @p found is given, where each edge was measured is added to it, in the edges'
// order (BlurTracker measures them there again on later frames).
std::vector<EdgeMeasurement> measureEdgesPrefetching(const Luma8& luma, const Rect& roi,
                                                     const BlurOptions& options,
                                                     RowPrefetcher& next,
                                                     std::vector<EdgeTrack>* found = nullptr) {
    std::vector<EdgeMeasurement> out;
    const std::optional<RegionSetup> setup = regionSetup(luma, roi, options);
    if (!setup) return out;
    const RegionSetup& s = *setup;
    const Kernels kernels = chooseKernels(options);
    // The 64 strongest candidates first. A region without an edge yet whose candidates were all
    // passed over or covered (crossed by many lines stronger than its edges: traces, wires, text)
    // lists the next, weaker ones, four times as many each time. Equal gradients keep their scan
    // order, so a longer list starts with the shorter one.
    size_t cap = 64;
    const CandidateGrid grid = candidateGrid(luma, s.r, options, kernels);
    CandidateList cands = strongestCandidates(grid, kernels, cap);
    size_t i = 0;  // the next of cands
    std::vector<Patch> used;
    int attempts = 0;
    // A seed that passes oneSided usually gives an edge: a region gets maxEdges attempts, and one
    // more per 128 × 128 px so that a large region (a coarse grid on a big sensor) is not judged
    // by its first few seeds. The last attempt is kept for a region without a usable edge yet:
    // there it finds the region's first edge, where elsewhere it would only add one more to the
    // average. Since the ESF fit's second start (measureSegment) more seeds give an edge, and the
    // rule takes a sixth of a frame's instructions without losing a region (docs/blur.md).
    const int extra = (s.r.x1 - s.r.x0) * (s.r.y1 - s.r.y0) / (128 * 128);
    bool haveUsable = false;
    for (;;) {
        if (static_cast<int>(out.size()) >= options.maxEdges ||
            attempts >= options.maxEdges + extra - (haveUsable ? 1 : 0))
            break;
        if (i == cands.size()) {
            // Every point listed, or an edge found: the region is done.
            if (cands.strongest() < cap || !out.empty()) break;
            const size_t looked = cands.strongest();
            cap *= 4;
            cands = weakerCandidates(grid, kernels, cap, cands.lowest());
            i = 0;
            if (cands.strongest() == looked) break;
            continue;
        }
        const Candidate c = cands.at(i++);
        next.fetch(kPrefetchRowsPerSeed);
        // Skip seeds on an edge already measured (or already rejected).
        const double px = c.x + 0.5, py = c.y + 0.5;
        const bool covered = std::any_of(used.begin(), used.end(), [&](const Patch& p) {
            return std::abs(p.u(px, py)) <= std::max(p.hw, 3.0) && std::abs(p.t(px, py)) <= p.hl;
        });
        if (covered) continue;
        // Seeds on bars, lines and clutter are passed over (the scan goes on to weaker ones); the
        // test reads 81 grid points where a measurement walks a thousand pixels twice.
        if (!cands.judged() && !oneSided(grid, c.gridIndex, kernels)) continue;
        ++attempts;
        Patch edge{};
        EdgeTrack track;
        const std::optional<EdgeMeasurement> best =
            measureSeed(luma, s, options, kernels, c, edge, track);
        used.push_back(edge);
        if (best) {
            out.push_back(*best);
            if (found) found->push_back(track);
            haveUsable = haveUsable || best->quality > kUsableQuality;
        }
    }
    return out;
}

// The edge of @p track measured again in @p luma (BlurTracker): its ESF sampled in the same
// patch, on the same line, and fitted as measureSegment fitted it there, so that an unchanged
// frame gives the same measurement. The probe and the segment lengths that found the edge are
// not repeated: on photographs they and the failed tries take most of an edge's pixel work.
// Where that fit gives no usable edge, the edge may have moved (focus breathing, a camera that
// shifts): its line is fitted again in the patch's slab, as measureSegment refits it, and the
// edge measured there, widened as measureSegment widens it while its line spread does not fit.
// Empty when it gives no usable edge then either, or at once when @p rescue is false.
std::optional<EdgeMeasurement> remeasureEdge(const Luma8& luma, const Bounds& sb,
                                             const BlurOptions& o, const Kernels& k,
                                             EdgeTrack& track, bool rescue) {
    thread_local BinList bins;
    thread_local PairTerms terms;
    Patch& patch = track.patch;
    bool refit = false, refitted = false;
    const Decoding dec = decodingFor(o.transfer);
    for (int pass = 0; pass < 6; ++pass) {
        if (refit) {
            const auto line = refitOnto(luma, sb, k, patch, track.threshold, track.slices);
            if (!line) return std::nullopt;
            track.straight = line->straight;
            refitted = true;
        }
        sampleEsf(luma, sb, k, patch, o.binPx, dec, bins);
        terms.defer(bins, k);
        const EsfFit f =
            fitWithSecondStart(bins, terms, patch.hw, o.minContrast, track.narrowStart, dec);
        if (usable(f)) return makeMeasurement(patch, f, bins, track.straight, o);
        if (!rescue) return std::nullopt;
        refit = true;
        if (!refitted) continue;
        if (f.ok || !f.needWider || patch.hw >= o.maxHalfWidthPx) return std::nullopt;
        patch.hw = widerHalfWidth(f, patch.hw, o);
        track.narrowStart = 0.0;
    }
    return std::nullopt;
}

// The region's blur from its edges (measureBlur), @p options already sanitized.
BlurEstimate blurFromEdges(const std::vector<EdgeMeasurement>& edges, const BlurOptions& options) {
    BlurEstimate est;
    std::vector<const EdgeMeasurement*> good;
    for (const EdgeMeasurement& e : edges)
        if (e.quality > kUsableQuality) good.push_back(&e);
    if (good.empty()) return est;
    // The sharpest edges set the region's blur. An edge's width is the defocus blur convolved
    // with the edge's own softness (a rounded body, a shadow, a printed gradient), which only
    // widens it: no edge in focus at that depth is sharper than the blur, so the smallest σ
    // bounds it and wider edges are soft objects or edges at another depth. Only trusted edges
    // may set it: at least 0.3 × the region's best quality, and a contrast at least 5 × the
    // grey-level spread beside the edge. A cluttered edge (another edge or a corner in its
    // plateaus) can read narrow, and one such edge must not decide the region.
    // The edges within 25 % of the sharpest, either side, are averaged in variance, weighted by
    // quality, against noise.
    double best = 0.0;
    for (const auto* e : good)
        best = std::max(best, e->quality);
    double sharpest = std::numeric_limits<double>::infinity();
    for (const auto* e : good)
        if (e->quality >= kTrustedQuality * best &&
            e->contrast >= kTrustedCnr * std::max(e->noise, 0.5))
            sharpest = std::min(sharpest, e->sigmaPx);
    // A region of cluttered edges only: the sharpest of them, at their low confidence.
    if (!std::isfinite(sharpest))
        for (const auto* e : good)
            sharpest = std::min(sharpest, e->sigmaPx);
    double sw = 0, sv = 0, sr = 0, sh = 0, shw = 0;
    int agreeing = 0;
    for (const auto* e : good) {
        if (std::abs(e->sigmaPx - sharpest) > 0.25 * sharpest + 0.05) continue;
        sw += e->quality;
        sv += e->quality * e->sigmaPx * e->sigmaPx;
        sr += e->quality * e->edgeWidthPx * e->edgeWidthPx;
        if (e->contrast >= kCleanCnr * std::max(e->noise, 0.5) && e->sigmaPx <= kHaloSigmaPx)
            sh += e->quality * e->haloFraction, shw += e->quality;
        ++agreeing;
    }
    const double sigma = std::sqrt(sv / sw), width = std::sqrt(sr / sw);
    const double floor2 = options.opticsFloorSigmaPx * options.opticsFloorSigmaPx;
    const double s = std::sqrt(std::max(0.0, sigma * sigma - floor2));
    est.sigmaPx = s;
    // A disc's projection is a semicircle of variance d²/16: the disc of equal moment has d = 4σ.
    est.discDiameterPx = 4.0 * s;
    est.edgeWidthPx = std::sqrt(
        std::max(0.0, width * width - kGaussianRisePerSigma * kGaussianRisePerSigma * floor2));
    est.edgeCount = agreeing;
    if (shw > 0) est.haloFraction = sh / shw;
    // Confidence: mean quality of the agreeing edges, more edges better, discounted by the
    // share of edges that disagree with them (mixed widths: soft objects or several depths).
    const double agreement = static_cast<double>(agreeing) / good.size();
    est.confidence =
        std::clamp((sw / agreeing) * (1.0 - std::exp(-agreeing / 1.5)) * agreement, 0.0, 1.0);
    return est;
}

}  // namespace

std::vector<EdgeMeasurement> measureEdges(const Luma8& luma, const Rect& roi,
                                          const BlurOptions& options) {
    RowPrefetcher none;
    return measureEdgesPrefetching(luma, roi, sanitized(options), none);
}

BlurEstimate measureBlur(const Luma8& luma, const Rect& roi, const BlurOptions& options) {
    const BlurOptions o = sanitized(options);
    RowPrefetcher none;
    return blurFromEdges(measureEdgesPrefetching(luma, roi, o, none), o);
}

std::vector<BlurEstimate> measureBlurRegions(const Luma8& luma, std::span<const Rect> rois,
                                             const BlurOptions& options) {
    const BlurOptions o = sanitized(options);
    std::vector<BlurEstimate> out;
    out.reserve(rois.size());
    for (size_t i = 0; i < rois.size(); ++i) {
        RowPrefetcher next =
            i + 1 < rois.size() ? RowPrefetcher(luma, rois[i + 1]) : RowPrefetcher();
        out.push_back(blurFromEdges(measureEdgesPrefetching(luma, rois[i], o, next), o));
        next.finish();
    }
    return out;
}

// What the tracker keeps of one region: where its edges were measured when it was last searched
// (those still found since), and whether it waits for a search.
struct BlurTracker::Impl {
    struct Region {
        std::vector<EdgeTrack> edges;
        bool due = true;        // lost an edge since its last search
        uint64_t searched = 0;  // the frame of its last search
    };
    BlurOptions options;
    int searchesPerFrame = 0;
    double searchBudgetS = 0.0;  // seconds of searching a frame; 0: no limit
    int width = 0, height = 0;
    std::vector<Rect> rois;
    std::vector<Region> regions;
    uint64_t frame = 0;  // frames measured since the last full search
};

BlurTracker::BlurTracker(const BlurOptions& options, int searchesPerFrame, double searchBudgetS)
    : impl_(std::make_unique<Impl>()) {
    impl_->options = sanitized(options);
    impl_->searchesPerFrame = std::max(searchesPerFrame, 1);
    impl_->searchBudgetS = std::isnan(searchBudgetS) ? 0.0 : std::max(searchBudgetS, 0.0);
}

BlurTracker::~BlurTracker() = default;
BlurTracker::BlurTracker(BlurTracker&&) noexcept = default;
BlurTracker& BlurTracker::operator=(BlurTracker&&) noexcept = default;

void BlurTracker::reset() {
    impl_->rois.clear();
    impl_->regions.clear();
}

std::vector<BlurEstimate> BlurTracker::measure(const Luma8& luma, std::span<const Rect> rois) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    const auto elapsedS = [&] {
        return std::chrono::duration<double>(Clock::now() - start).count();
    };
    Impl& t = *impl_;
    const bool same = luma.width == t.width && luma.height == t.height &&
                      std::equal(rois.begin(), rois.end(), t.rois.begin(), t.rois.end());
    const size_t n = rois.size();
    if (!same) {
        t.width = luma.width, t.height = luma.height;
        t.rois.assign(rois.begin(), rois.end());
        t.regions.assign(n, {});
        t.frame = 0;
    }
    std::vector<BlurEstimate> out(n);
    std::vector<char> searched(n, 0);
    // A region searched afresh: its edges and where they were found replace the old ones.
    const auto search = [&](size_t i, size_t next) {
        Impl::Region& r = t.regions[i];
        RowPrefetcher ahead = next < n ? RowPrefetcher(luma, rois[next]) : RowPrefetcher();
        r.edges.clear();
        out[i] = blurFromEdges(measureEdgesPrefetching(luma, rois[i], t.options, ahead, &r.edges),
                               t.options);
        ahead.finish();
        r.due = false;
        r.searched = t.frame;
        searched[i] = 1;
    };
    if (!same) {
        // The first frame: every region, in order.
        for (size_t i = 0; i < n; ++i)
            search(i, i + 1);
    } else {
        // This frame's searches, at most searchesPerFrame: first the regions not searched for
        // 2n / searchesPerFrame frames, then those that lost an edge, then those searched
        // longest ago, oldest first within each. A frame's cost stays bounded while the scene
        // changes, lost edges are looked for again at once, and no region goes unsearched for
        // long (a sharper edge may have come into focus there).
        std::vector<size_t> order(n);
        for (size_t i = 0; i < n; ++i)
            order[i] = i;
        // Oldest search first; equal ages in region order, so that the round is deterministic.
        std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
            return t.regions[a].searched < t.regions[b].searched;
        });
        const auto most = static_cast<size_t>(t.searchesPerFrame);
        const uint64_t overdue = 2 * n / most;
        std::vector<size_t> queue;
        std::vector<char> queued(n, 0);
        const auto take = [&](auto&& wanted) {
            for (const size_t i : order)
                if (queue.size() < most && !queued[i] && wanted(t.regions[i]))
                    queue.push_back(i), queued[i] = 1;
        };
        take([&](const Impl::Region& r) { return t.frame - r.searched >= overdue; });
        take([](const Impl::Region& r) { return r.due; });
        take([](const Impl::Region&) { return true; });
        // With a time budget, the searches stop once it is spent (one at least, so that the
        // round goes on): on frames far out of focus a search costs many times more.
        for (size_t q = 0; q < queue.size(); ++q) {
            if (q > 0 && t.searchBudgetS > 0.0 && elapsedS() >= t.searchBudgetS) break;
            search(queue[q], q + 1 < queue.size() ? queue[q + 1] : n);
        }
    }
    // Every other region: its edges measured again where they were found. With a time budget,
    // an edge that fails there is looked for again (refitted, widened) only while the frame has
    // taken less than twice the budget: after a cut most edges fail, and their rescue, not
    // their one ESF each, is what makes that frame slow. Dropped, they wait for a search.
    const Kernels kernels = chooseKernels(t.options);
    for (size_t i = 0; i < n; ++i) {
        if (searched[i]) continue;
        Impl::Region& r = t.regions[i];
        std::vector<EdgeMeasurement> edges;
        if (const auto setup = regionSetup(luma, rois[i], t.options)) {
            size_t kept = 0;
            for (EdgeTrack& e : r.edges)
                if (const auto m = remeasureEdge(
                        luma, setup->sb, t.options, kernels, e,
                        t.searchBudgetS <= 0.0 || elapsedS() < 2.0 * t.searchBudgetS)) {
                    edges.push_back(*m);
                    r.edges[kept++] = e;
                }
            r.due = kept < r.edges.size();
            r.edges.resize(kept);
        }
        out[i] = blurFromEdges(edges, t.options);
    }
    ++t.frame;
    return out;
}

}  // namespace infocus
