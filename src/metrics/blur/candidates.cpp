// SPDX-License-Identifier: MIT
// Edge candidates of a region: the Sobel grid, its strongest and next weaker points, and the
// one-sided test of a seed's neighbourhood (docs/blur.md, "Candidates").
#include <climits>

#include "internal.h"

namespace infocus::blur_detail {

namespace {

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

// Radius (px, a whole number) of the square about a seed in which oneSided weighs the gradients,
// and the least value a seed needs to be measured.
constexpr int kOneSidedRadiusPx = 8;
constexpr double kMinOneSided = 0.5;

}  // namespace

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

}  // namespace infocus::blur_detail
