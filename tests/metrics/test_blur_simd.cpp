// SPDX-License-Identifier: MIT
// The AVX2 kernels of the blur engine against the generic reference, kernel by kernel and through
// the whole engine; also the level and noise sums behind a region's status. Without AVX2 on this
// CPU there is nothing to compare: the executable exits 77, which meson reports as skipped.
#define CATCH_CONFIG_RUNNER
#include <algorithm>
#include <catch2/catch.hpp>
#include <climits>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "blur_test_edges.h"
#include "infocus/blur.h"
#include "infocus/synth.h"
#include "src/metrics/blur/kernels.h"
#include "src/metrics/cpu.h"
#include "src/metrics/sharpness/kernels.h"

using namespace infocus;
using namespace infocus::blur_test;

int main(int argc, char* argv[]) {
    if (!detail::haveAvx2()) {
        std::printf("no AVX2 on this CPU: nothing to compare the generic kernels with; skipped\n");
        return 77;
    }
    return Catch::Session().run(argc, argv);
}

TEST_CASE("the AVX2 blur kernels equal the reference implementation", "[blur][simd]") {
    // Uniform random bytes: every difference and every threshold crossing occurs.
    const int w = 203, h = 9;
    Image<float> f(w, h, 0.0f);
    synth::addNoise(f, 90.0, 11);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            f.row(y)[x] += 128.0f;
    const Image<uint8_t> img = synth::toLuma8(f);
    const Luma8 v = img.view();
    std::vector<int16_t> gx0(w), gy0(w), gx1(w), gy1(w);
    std::vector<float> acc0, acc1;
    int mostBins = 0;  // the most non-empty ESF bins of a case
    for (int y = 1; y < h - 1; ++y)
        for (int x0 : {1, 2, 7, 40})
            for (int n : {1, 5, 15, 16, 17, 33, w - 1 - x0}) {
                // Integer arithmetic on both sides: equal to the bit, for every grid step (the
                // vector kernel has step 2, the others hand over to the generic one).
                for (int step : {1, 2, 3}) {
                    const int count = (n - 1) / step + 1;
                    if (x0 + (count - 1) * step > w - 2) continue;
                    std::vector<int32_t> m0(count), m1(count);
                    const int32_t p0 =
                        detail::sobelGridRowGeneric(v.row(y - 1), v.row(y), v.row(y + 1), x0, count,
                                                    step, w, gx0.data(), gy0.data(), m0.data());
                    const int32_t p1 =
                        detail::sobelGridRowAvx2(v.row(y - 1), v.row(y), v.row(y + 1), x0, count,
                                                 step, w, gx1.data(), gy1.data(), m1.data());
                    CHECK(p0 == p1);
                    CHECK(p0 == *std::max_element(m0.begin(), m0.end()));
                    CHECK(std::equal(gx0.begin(), gx0.begin() + count, gx1.begin()));
                    CHECK(std::equal(gy0.begin(), gy0.begin() + count, gy1.begin()));
                    CHECK(m0 == m1);
                    // The generic kernel is the Sobel operator: spot-check one point by hand.
                    const int x = x0 + (count - 1) * step;
                    const uint8_t *a = v.row(y - 1), *c = v.row(y + 1), *mm = v.row(y);
                    CHECK(gx0[count - 1] == (a[x + 1] - a[x - 1]) + 2 * (mm[x + 1] - mm[x - 1]) +
                                                (c[x + 1] - c[x - 1]));
                    CHECK(gy0[count - 1] ==
                          (c[x - 1] - a[x - 1]) + 2 * (c[x] - a[x]) + (c[x + 1] - a[x + 1]));
                }
                // The same float operations in the same order and lanes (no FMA): the same slice
                // sums to the bit, including the last columns, where the vector loop hands over
                // to the scalar one, and slices clamped at both ends.
                const int x1 = x0 + n - 1;
                // 1.6 and 4.6 rad: rows within 14° of the edge (a second copy of the bins).
                for (double a : {0.0, 0.3, 1.6, 1.9, 3.7, 4.6}) {
                    const auto nx = static_cast<float>(std::cos(a)),
                               ny = static_cast<float>(std::sin(a));
                    for (float thr : {-5.0f, 0.0f, 12.5f, 40.0f}) {
                        // Two rows: this one and, shifted, the one above it.
                        const detail::GeometryPatch g{nx, ny, thr, 9.0f, 5, 5.0f / 18.0f};
                        const detail::GeometrySpan spans[2] = {
                            {v.row(y), x0, x1, -3.3f, 7.1f},
                            {v.row(y - 1) + 1, x0, x1 - 1, 2.4f, -8.2f}};
                        const int rows = y > 1 ? 2 : 1;
                        acc0.assign(detail::kGeometryMoments * detail::kGeometryLanes * g.slices,
                                    0.0f);
                        acc1 = acc0;
                        detail::geometryRowsGeneric(spans, rows, v.stride, w, g, acc0.data());
                        detail::geometryRowsAvx2(spans, rows, v.stride, w, g, acc1.data());
                        CHECK(acc0 == acc1);
                        // The slices' partial sums added up in double, in the same order.
                        std::vector<double> r0(4 * g.slices), r1(4 * g.slices);
                        detail::geometryReduceGeneric(acc1.data(), g.slices, r0.data());
                        detail::geometryReduceAvx2(acc1.data(), g.slices, r1.data());
                        CHECK(r0 == r1);
                    }
                    // The ESF kernels: integer sums, equal whatever the order; bins of 1/4 and
                    // 1/16 px, pixels left and right of the binned width (to the spare bins).
                    for (float bp : {0.25f, 0.0625f}) {
                        const detail::EsfPatch e{
                            nx, 7.0f, 1.0f / bp, bp, static_cast<int>(14.0f / bp), 2048.0f / bp};
                        const detail::GeometrySpan spans[2] = {{v.row(y), x0, x1, -9.3f, 0.0f},
                                                               {v.row(y - 1), x0, x1, 2.4f, 0.0f}};
                        const size_t words = 4 * static_cast<size_t>(e.bins);
                        std::vector<uint32_t> e0(words + 4 * detail::kEsfSpareBins, 0u);
                        std::vector<uint32_t> e1 = e0;
                        detail::esfRowsGeneric(spans, 2, w, e, e0.data());
                        detail::esfRowsAvx2(spans, 2, w, e, e1.data());
                        CHECK(std::equal(e0.begin(), e0.begin() + words, e1.begin()));
                        // Every pixel is counted once: in a bin or in a spare one.
                        for (const auto* acc : {&e0, &e1}) {
                            uint32_t counted = 0;
                            for (int k = 0; k < e.bins + detail::kEsfSpareBins; ++k)
                                counted += (*acc)[4 * k] >> detail::kEsfCountShift;
                            CHECK(counted == static_cast<uint32_t>(2 * n));
                        }
                        // The bins in double: the same values, empty bins skipped; then the
                        // terms of their neighbouring pairs.
                        const size_t room = e.bins + detail::kEsfBinSlack;
                        std::vector<double> f0(5 * room), f1(5 * room);
                        auto arrays = [room](std::vector<double>& f) {
                            return detail::EsfBins{f.data(), f.data() + room, f.data() + 2 * room,
                                                   f.data() + 3 * room, f.data() + 4 * room};
                        };
                        const detail::EsfBins b0 = arrays(f0), b1 = arrays(f1);
                        const int n0 = detail::esfBinsGeneric(e1.data(), 0, e.bins, bp, 7.0, b0);
                        const int n1 = detail::esfBinsAvx2(e1.data(), 0, e.bins, bp, 7.0, b1);
                        REQUIRE(n0 == n1);
                        mostBins = std::max(mostBins, n0);
                        int pixels = 0;
                        for (int i = 0; i < n0; ++i) {
                            CHECK(b0.pos[i] == b1.pos[i]);
                            CHECK(b0.value[i] == b1.value[i]);
                            CHECK(b0.withinVar[i] == b1.withinVar[i]);
                            CHECK(b0.pixelVar[i] == b1.pixelVar[i]);
                            CHECK(b0.count[i] == b1.count[i]);
                            // A bin's mean position lies inside it, in ascending order.
                            CHECK(std::abs(b0.pos[i]) <= 7.0 + 1e-9);
                            if (i > 0) CHECK(b0.pos[i] > b0.pos[i - 1]);
                            pixels += static_cast<int>(b0.count[i]);
                        }
                        // Every bin count from 1 (the generic tail alone) to n0 (the vector
                        // loop and its tail), so that each of the AVX2 loop's ends is reached.
                        for (int n : {1, 2, 5, 6, 9, n0 - 1, n0}) {
                            if (n < 1 || n > n0) continue;
                            const detail::PairInputs in{b0.pos, b0.value, b0.withinVar};
                            std::vector<double> x0(room), c0(room), s0(4 * room, -1.0);
                            std::vector<double> x1(room), c1(room), s1(4 * room, -1.0);
                            detail::pairTermsGeneric(in, 0, n, x0.data(), c0.data(), s0.data());
                            detail::pairTermsAvx2(in, 0, n, x1.data(), c1.data(), s1.data());
                            CHECK(std::equal(x0.begin(), x0.begin() + n - 1, x1.begin()));
                            CHECK(std::equal(c0.begin(), c0.begin() + n - 1, c1.begin()));
                            CHECK(std::equal(s0.begin(), s0.begin() + 4 * n, s1.begin()));
                            // The running sum of the steps telescopes to the last bin's value
                            // less the first's (to rounding: 1e-9 of a grey level).
                            CHECK(std::abs(s0[4 * (n - 1)] - (b0.value[n - 1] - b0.value[0])) <
                                  1e-9);
                        }
                        uint32_t inBins = 0;
                        for (int k = 0; k < e.bins; ++k)
                            inBins += e1[4 * k] >> detail::kEsfCountShift;
                        CHECK(pixels == static_cast<int>(inBins));
                    }
                }
            }
    // The pair terms' vector loop (four pairs from five bins on) ran on long ESFs too.
    CHECK(mostBins >= 64);
}

TEST_CASE("the candidate counting and listing kernels agree with a plain count", "[blur][simd]") {
    // Squared gradients as the candidate grid holds them, lengths with and without a tail.
    std::vector<int32_t> m(203);
    uint64_t state = 7;
    for (int32_t& v : m) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        v = static_cast<int32_t>((state >> 33) % 2000000);
    }
    m[5] = m[6] = 1234567;  // ties
    for (size_t n : {size_t{0}, size_t{7}, size_t{8}, size_t{64}, size_t{203}})
        for (int32_t v : {0, 1, 1234567, 1234568, 1000000, 1999999, 2000000}) {
            size_t plain = 0;
            for (size_t i = 0; i < n; ++i)
                plain += m[i] >= v;
            CHECK(detail::countAtLeastGeneric(m.data(), n, v) == plain);
            CHECK(detail::countAtLeastAvx2(m.data(), n, v) == plain);
            std::vector<uint64_t> k0(n + 1), k1(n + 1);
            const size_t l0 = detail::listAtLeastGeneric(m.data(), n, v, k0.data());
            const size_t l1 = detail::listAtLeastAvx2(m.data(), n, v, k1.data());
            CHECK(l0 == plain);
            CHECK(l1 == plain);
            CHECK(std::equal(k0.begin(), k0.begin() + l0, k1.begin()));
            // A key holds the value above the complemented index.
            for (size_t i = 0; i < l0; ++i) {
                const size_t at = 0xffffffffu - static_cast<uint32_t>(k0[i]);
                CHECK(static_cast<int32_t>(k0[i] >> 32) == m[at]);
                CHECK(m[at] >= v);
            }
        }
}

TEST_CASE("the candidate ordering kernels give the strongest keys in order", "[blur][simd]") {
    // Distinct candidate keys with many equal gradients (keys then differ in their index only)
    // and the largest gradient a grid can hold.
    uint64_t state = 99;
    std::vector<uint64_t> keys(detail::kMaxOrderKeys);
    for (size_t i = 0; i < keys.size(); ++i) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        const auto mag2 = static_cast<int32_t>(i % 5 == 0 ? 777 : (state >> 33) % 2000000);
        keys[i] = detail::candidateKey(i == 3 ? INT32_MAX : mag2, 10 * i + (state >> 60));
    }
    for (size_t n : {size_t{1}, size_t{3}, size_t{4}, size_t{5}, size_t{63}, size_t{64}, size_t{97},
                     detail::kMaxOrderKeys})
        for (size_t m : {size_t{1}, size_t{16}, size_t{64}, n}) {
            if (m > n) continue;
            std::vector<uint64_t> sorted(keys.begin(), keys.begin() + n);
            std::sort(sorted.begin(), sorted.end(), std::greater<>());
            std::vector<uint64_t> o0(m, 0), o1(m, 0);
            detail::orderKeysGeneric(keys.data(), n, m, o0.data());
            detail::orderKeysAvx2(keys.data(), n, m, o1.data());
            CHECK(std::equal(o0.begin(), o0.end(), sorted.begin()));
            CHECK(o1 == o0);
        }
}

TEST_CASE("the candidate level kernels agree with a plain shift and count", "[blur][simd]") {
    // Squared gradients below 256 << shift, lengths with and without a 32-point tail.
    for (int shift : {0, 5, 13}) {
        std::vector<int32_t> m(203);
        uint64_t state = 11 + shift;
        for (int32_t& v : m) {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            v = static_cast<int32_t>((state >> 33) % (256u << shift));
        }
        m[0] = (256 << shift) - 1;  // the largest level, 255
        m[1] = 0;
        for (size_t n : {size_t{0}, size_t{31}, size_t{32}, size_t{64}, size_t{203}}) {
            std::vector<uint8_t> l0(n + 1, 0xee), l1(n + 1, 0xee);
            detail::levelsGeneric(m.data(), n, shift, l0.data());
            detail::levelsAvx2(m.data(), n, shift, l1.data());
            for (size_t i = 0; i < n; ++i)
                CHECK(l0[i] == m[i] >> shift);
            CHECK(l1 == l0);  // the same bytes, and none written past n
            for (int v : {0, 1, 7, 128, 200, 255}) {
                size_t plain = 0;
                for (size_t i = 0; i < n; ++i)
                    plain += (m[i] >> shift) >= v;
                const auto level = static_cast<uint8_t>(v);
                CHECK(detail::countLevelsAtLeastGeneric(l0.data(), n, level) == plain);
                CHECK(detail::countLevelsAtLeastAvx2(l0.data(), n, level) == plain);
            }
            // Listing through the levels gives listAtLeast's keys, also for a v between levels.
            for (int32_t v : {0, 1, m[0], m[0] + 1, (7 << shift) + 3, 200 << shift}) {
                std::vector<uint64_t> k0(n + 1), k1(n + 1), k2(n + 1);
                const size_t plain = detail::listAtLeastGeneric(m.data(), n, v, k0.data());
                const size_t g =
                    detail::listLevelsAtLeastGeneric(l0.data(), shift, m.data(), n, v, k1.data());
                const size_t a =
                    detail::listLevelsAtLeastAvx2(l0.data(), shift, m.data(), n, v, k2.data());
                CHECK(g == plain);
                CHECK(a == plain);
                CHECK(std::equal(k0.begin(), k0.begin() + plain, k1.begin()));
                CHECK(std::equal(k0.begin(), k0.begin() + plain, k2.begin()));
            }
        }
    }
}

TEST_CASE("the one-sided sums kernels agree with a plain sum", "[blur][simd]") {
    // Sobel gradients up to the largest (±1020), a grid of 20 × 12 points plus the 16 points of
    // padding the AVX2 kernel may read past a row's start.
    const int stride = 20, rowsInGrid = 12;
    std::vector<int16_t> gx(stride * rowsInGrid + 16), gy(gx.size());
    uint64_t state = 3;
    for (size_t i = 0; i < gx.size(); ++i) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        gx[i] = static_cast<int16_t>(static_cast<int>((state >> 33) % 2041) - 1020);
        gy[i] = static_cast<int16_t>(static_cast<int>((state >> 45) % 2041) - 1020);
    }
    gx[0] = gy[0] = -1020;  // the extremes: d = 2·1020² at n = (−1020, −1020)
    for (int width : {1, 8, 9, 16, 17})
        for (int rows : {1, 9, 12})
            for (auto [nx, ny] : {std::pair{-1020, -1020}, std::pair{1020, -3}, std::pair{0, 7}}) {
                int64_t along = 0, magnitude = 0;
                for (int y = 0; y < rows; ++y)
                    for (int x = 0; x < width && x < stride; ++x) {
                        const int64_t d =
                            int64_t{gx[y * stride + x]} * nx + int64_t{gy[y * stride + x]} * ny;
                        along += d;
                        magnitude += std::abs(d);
                    }
                const int w = std::min(width, stride);
                int64_t a0 = 5, m0 = 6, a1 = 5, m1 = 6;  // added to, not overwritten
                detail::oneSidedSumsGeneric(gx.data(), gy.data(), stride, w, rows, nx, ny, &a0,
                                            &m0);
                detail::oneSidedSumsAvx2(gx.data(), gy.data(), stride, w, rows, nx, ny, &a1, &m1);
                INFO("width " << w << ", rows " << rows << ", n (" << nx << ", " << ny << ")");
                CHECK(a0 == along + 5);
                CHECK(m0 == magnitude + 6);
                CHECK(a1 == a0);
                CHECK(m1 == m0);
            }
}

TEST_CASE("the AVX2 patch row walk gives the generic kernel's spans", "[blur][simd]") {
    static const uint8_t pixels[4] = {};
    int spans = 0;
    // Every 0.37 rad, and normals a hair off the axes: a slab nearly along y has a huge slope,
    // and its rows outside the patch must stay empty (they once became spans from x = −2³¹).
    std::vector<double> angles;
    for (double angle = 0.0; angle < 6.3; angle += 0.37)
        angles.push_back(angle);
    for (double tiny : {1e-11, 1e-9, 1e-6})
        for (double axis : {0.0, 1.5707963267948966, 3.141592653589793})
            angles.push_back(axis + tiny);
    for (double angle : angles)
        for (double hw : {6.0, 9.3})
            for (int bx0 : {0, 37}) {
                // The generic walk's slabs (see patchSpans): |(x − cx)·a + dy·coef| ≤ h.
                const double nx = std::cos(angle), ny = std::sin(angle), hl = 30.0;
                auto slab = [](double a, double coef, double h) {
                    if (std::abs(a) < 1e-12) return detail::PatchSlab{true, 0.0, 0.0, h, coef};
                    return detail::PatchSlab{false, -coef / a, std::abs(h / a), h, coef};
                };
                const double cx = 50.3, cy = 41.7;
                const double r = std::abs(hw * nx) + std::abs(hl * ny);
                const detail::PatchRows rows{pixels,
                                             640,
                                             cx,
                                             cy,
                                             nx,
                                             ny,
                                             cx - r - 1.0,
                                             cx + r + 1.0,
                                             slab(nx, ny, hw),
                                             slab(-ny, nx, hl),
                                             bx0,
                                             90,
                                             3,
                                             80};
                std::vector<detail::GeometrySpan> a(80), b(80);
                const int na = detail::patchRowsGeneric(rows, a.data());
                const int nb = detail::patchRowsAvx2(rows, b.data());
                REQUIRE(na == nb);
                for (int i = 0; i < na; ++i) {
                    CHECK(a[i].r == b[i].r);
                    CHECK(a[i].x0 == b[i].x0);
                    CHECK(a[i].x1 == b[i].x1);
                    CHECK(a[i].u0 == b[i].u0);
                    CHECK(a[i].t0 == b[i].t0);
                    // Pixel x0 lies inside the patch: |u| ≤ hw, |t| ≤ hl (float rounding aside).
                    CHECK(std::abs(a[i].u0) <= hw + 1e-4);
                    CHECK(std::abs(a[i].t0) <= hl + 1e-4);
                    CHECK(a[i].x0 >= bx0);
                    CHECK(a[i].x1 <= 89);
                }
                spans += na;
            }
    CHECK(spans > 1000);  // the walks were not empty
}

TEST_CASE("the AVX2 and the generic engine measure the same edges", "[blur][simd]") {
    // A textured frame (every angle, curved and straight edges): the whole engine gives the same
    // numbers either way. The kernels agree to the bit, so the tolerance (1e-12 relative) only
    // states that nothing else differs.
    synth::SharpCanvas canvas = synth::makeCanvas(480, 270, 2);
    synth::paintDeadLeaves(canvas, 77, 4.0, 60.0);
    const auto img =
        synth::toLuma8(synth::renderSharp(canvas, {synth::Psf::disc(3.0), 2, 1.0, 5}).pixels);
    BlurOptions simd, plain;
    plain.simd = false;
    int edges = 0;
    for (int y = 0; y < 270; y += 90)
        for (int x = 0; x < 480; x += 120) {
            const Rect r{x, y, 120, 90};
            const auto a = measureEdges(img.view(), r, simd);
            const auto b = measureEdges(img.view(), r, plain);
            REQUIRE(a.size() == b.size());
            for (size_t i = 0; i < a.size(); ++i) {
                CHECK(a[i].sigmaPx == Approx(b[i].sigmaPx).epsilon(1e-12));  // same arithmetic
                CHECK(a[i].cx == Approx(b[i].cx).epsilon(1e-12));
                CHECK(a[i].quality == Approx(b[i].quality).epsilon(1e-12));
            }
            edges += static_cast<int>(a.size());
        }
    CHECK(edges >= 12);  // the frame has edges in most regions: the comparison is not empty
}

namespace {

// @p n pseudo-random levels from @p seed, each passed through @p level: a test sets how often
// the ends of the range occur.
template <typename Level>
std::vector<uint8_t> randomLevels(size_t n, uint32_t seed, Level level) {
    std::vector<uint8_t> px(n);
    for (auto& p : px) {
        seed = seed * 1664525u + 1013904223u;
        p = static_cast<uint8_t>(level(seed >> 24));
    }
    return px;
}

}  // namespace

TEST_CASE("the level sums of a region's status equal a plain count", "[status][simd]") {
    // Levels spread over the whole range, with runs at both ends: every byte compare and both
    // sample parities of the last, backed-up window occur.
    const int w = 301, h = 23;
    const std::vector<uint8_t> px = randomLevels(size_t(w) * h, 12345, [](uint32_t r) {
        return r < 16 ? 255u : r < 24 ? 254u : r < 32 ? 0u : r;
    });
    const Luma8 v{px.data(), w, h, w, nullptr};
    int compared = 0;
    for (int x0 : {0, 1, 2, 5})
        for (int rw : {31, 32, 33, 63, 64, 65, 94, 95, 200, w - x0})
            for (int step : {1, 2})
                for (int topFrom : {0, 1, 128, 254, 255, 256}) {
                    if (x0 + rw > w) continue;
                    const Rect r{x0, 1, rw, h - 2};
                    const auto a = detail::levelSumsGeneric(v, r, step, topFrom);
                    const auto b = detail::levelSumsAvx2(v, r, step, topFrom);
                    INFO("x0 " << x0 << " w " << rw << " step " << step << " top " << topFrom);
                    CHECK(a.sum == b.sum);
                    CHECK(a.top == b.top);
                    ++compared;
                }
    CHECK(compared > 400);
}

TEST_CASE("the noise kernel counts the pixels at the ends as a plain count", "[noise][simd]") {
    const int w = 211, h = 41;
    const std::vector<uint8_t> px = randomLevels(size_t(w) * h, 777, [](uint32_t r) {
        return r < 10 ? 255u : r < 14 ? 254u : r < 20 ? 1u : r < 26 ? 0u : r;
    });
    const Luma8 v{px.data(), w, h, w, nullptr};
    for (int x0 : {1, 2, 7})
        for (int rw : {32, 33, 50, 64, 97, w - 1 - x0})
            for (int step : {1, 4}) {
                const Rect a{x0, 1, rw, h - 2};
                int64_t plain = 0;
                for (int y = a.y; y < a.y + a.h; y += step)
                    for (int x = a.x; x < a.x + a.w; ++x)
                        plain += v.row(y)[x] <= kNoiseLowEnd || v.row(y)[x] >= kNoiseHighEnd;
                int64_t counted = -1;
                INFO("x0 " << x0 << " w " << rw << " step " << step);
                CHECK(detail::simdImmerkaerSum(v, a, step, &counted) >= 0);
                CHECK(counted == plain);
                CHECK(plain > 0);
            }
}
