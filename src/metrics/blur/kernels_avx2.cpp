// SPDX-License-Identifier: MIT
// AVX2 pixel kernels of the blur-width engine: the same arithmetic as the generic versions in
// kernels_generic.cpp, 8 or 16 pixels at a time. This file alone is compiled with -mavx2;
// chooseKernels hands it out only after a run-time CPU check.
#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "kernels.h"

namespace infocus::detail {

namespace {

inline __m256i widen16(const uint8_t* p) {
    return _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
}

inline __m256 widen8f(const uint8_t* p) {
    return _mm256_cvtepi32_ps(
        _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))));
}

// For each set of non-empty lanes (4 bits), the 32-bit lanes of a permutation that moves those
// doubles, in order, to the front of a vector.
struct PackOrder {
    alignas(32) int32_t lanes[16][8];
};
constexpr PackOrder makePackOrder() {
    PackOrder p{};
    for (int m = 0; m < 16; ++m) {
        int j = 0;
        for (int lane = 0; lane < 4; ++lane)
            if (m >> lane & 1)
                p.lanes[m][2 * j] = 2 * lane, p.lanes[m][2 * j + 1] = 2 * lane + 1, ++j;
        for (; j < 4; ++j)
            p.lanes[m][2 * j] = 0, p.lanes[m][2 * j + 1] = 1;
    }
    return p;
}
constexpr PackOrder kPackOrder = makePackOrder();

}  // namespace

int32_t sobelGridRowAvx2(const uint8_t* a, const uint8_t* m, const uint8_t* c, int x0, int count,
                         int step, int width, int16_t* gx, int16_t* gy, int32_t* mag2) {
    if (step != 2) return sobelGridRowGeneric(a, m, c, x0, count, step, width, gx, gy, mag2);
    const __m256i low = _mm256_set1_epi16(0xff);
    __m256i peak = _mm256_setzero_si256();
    int i = 0;
    // 16 points (32 pixels) per step. Read as 16-bit words from x − 1, a word holds the pixels
    // left of and at a point; from x + 1, its low byte is the pixel right of it. The loads reach
    // x0 + 2i + 32, which must be inside the row. The block of points j.. reads the rows from
    // @p pa, @p pm and @p pc on (their pixel x − 1 of the first point).
    auto block = [&](const uint8_t* pa, const uint8_t* pm, const uint8_t* pc, int j) {
        const auto at = [](const uint8_t* p) {
            return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
        };
        const __m256i aw = at(pa), ar = _mm256_and_si256(at(pa + 2), low);
        const __m256i mw = at(pm), mr = _mm256_and_si256(at(pm + 2), low);
        const __m256i cw = at(pc), cr = _mm256_and_si256(at(pc + 2), low);
        const __m256i al = _mm256_and_si256(aw, low), ac = _mm256_srli_epi16(aw, 8);
        const __m256i ml = _mm256_and_si256(mw, low);
        const __m256i cl = _mm256_and_si256(cw, low), cc = _mm256_srli_epi16(cw, 8);
        const __m256i dx =
            _mm256_add_epi16(_mm256_add_epi16(_mm256_sub_epi16(ar, al), _mm256_sub_epi16(cr, cl)),
                             _mm256_slli_epi16(_mm256_sub_epi16(mr, ml), 1));
        const __m256i dy =
            _mm256_add_epi16(_mm256_add_epi16(_mm256_sub_epi16(cl, al), _mm256_sub_epi16(cr, ar)),
                             _mm256_slli_epi16(_mm256_sub_epi16(cc, ac), 1));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(gx + j), dx);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(gy + j), dy);
        // gx² + gy² in 32 bits: pairs (gx, gy) multiplied and added; the unpacks work within
        // 128-bit halves, so the halves are put back in order.
        const __m256i lo =
            _mm256_madd_epi16(_mm256_unpacklo_epi16(dx, dy), _mm256_unpacklo_epi16(dx, dy));
        const __m256i hi =
            _mm256_madd_epi16(_mm256_unpackhi_epi16(dx, dy), _mm256_unpackhi_epi16(dx, dy));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(mag2 + j),
                            _mm256_permute2x128_si256(lo, hi, 0x20));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(mag2 + j + 8),
                            _mm256_permute2x128_si256(lo, hi, 0x31));
        peak = _mm256_max_epi32(peak, _mm256_max_epi32(lo, hi));
    };
    const auto inPlace = [&](int j) {
        const int x = x0 + 2 * j - 1;
        block(a + x, m + x, c + x, j);
    };
    for (; i + 16 <= count && x0 + 2 * i + 33 <= width; i += 16)
        inPlace(i);
    // The last points: one more vector ending at the last point, overlapping the previous one
    // (the same values again). Where its loads would pass the row's end (the image's last
    // columns), from a copy of the 33 bytes it uses (the byte after them only fills high bytes
    // that are masked off).
    if (i < count && count >= 16) {
        const int x = x0 + 2 * (count - 16) - 1;
        if (x + 34 <= width) {
            inPlace(count - 16);
        } else {
            alignas(32) uint8_t rows[3][64] = {};
            std::memcpy(rows[0], a + x, 33);
            std::memcpy(rows[1], m + x, 33);
            std::memcpy(rows[2], c + x, 33);
            block(rows[0], rows[1], rows[2], count - 16);
        }
        i = count;
    }
    // The lanes' largest by three halvings (a store and a scalar scan cost 24 instructions a row).
    __m128i q = _mm_max_epi32(_mm256_castsi256_si128(peak), _mm256_extracti128_si256(peak, 1));
    q = _mm_max_epi32(q, _mm_shuffle_epi32(q, _MM_SHUFFLE(1, 0, 3, 2)));
    q = _mm_max_epi32(q, _mm_shuffle_epi32(q, _MM_SHUFFLE(2, 3, 0, 1)));
    int32_t best = _mm_cvtsi128_si32(q);
    if (i < count)
        best = std::max(best, sobelGridRowGeneric(a, m, c, x0 + 2 * i, count - i, 2, width, gx + i,
                                                  gy + i, mag2 + i));
    return best;
}

void geometryRowsAvx2(const GeometrySpan* spans, int count, ptrdiff_t stride, int width,
                      const GeometryPatch& g, float* acc) {
    constexpr int L = kGeometryLanes, M = kGeometryMoments;
    const __m256 vnx = _mm256_set1_ps(g.nx), vny = _mm256_set1_ps(g.ny);
    const __m256 half = _mm256_set1_ps(0.5f), vinv = _mm256_set1_ps(g.sliceInv);
    const __m256 vthr = _mm256_set1_ps(g.thr), vhl = _mm256_set1_ps(g.hl);
    const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i top = _mm256_set1_epi32(g.slices - 1);
    const __m256i eight = _mm256_set1_epi32(8), sixteen = _mm256_set1_epi32(16);
    // A test in integers first that never drops a pixel the float test passes: with N = the
    // normal times 16384, rounded (int16), dx·Nx + dy·Ny is within (|dx| + |dy|)/2 ≤ 255 of
    // 16384 (dx·nx + dy·ny), and the float d within 3.1e-5 of half of dx·nx + dy·ny; so where
    // the integer sum is at most T = ⌊16384 (2 thr − 0.02)⌋, d ≤ thr − 0.002 and the pixel fails
    // d > thr. Two thirds of the 8-pixel halves of the bench frame's patches hold none: they
    // skip the conversion to float and the float test. The same sums.
    const auto nxq = static_cast<int16_t>(std::lround(g.nx * 16384.0f));
    const auto nyq = static_cast<int16_t>(std::lround(g.ny * 16384.0f));
    const __m256i vN = _mm256_set1_epi32(static_cast<int32_t>(
        (static_cast<uint32_t>(static_cast<uint16_t>(nyq)) << 16) | static_cast<uint16_t>(nxq)));
    const double tq = std::floor(16384.0 * (2.0 * static_cast<double>(g.thr) - 0.02));
    const __m256i vT = _mm256_set1_epi32(static_cast<int32_t>(std::clamp(tq, -2.0e9, 2.0e9)));
    for (int k = 0; k < count; ++k) {
        const GeometrySpan& sp = spans[k];
        const uint8_t* r = sp.r;
        const int x0 = sp.x0, x1 = sp.x1;
        const __m256 vu0 = _mm256_set1_ps(sp.u0), vt0 = _mm256_set1_ps(sp.t0);
        const __m256i end = _mm256_set1_epi32(x1 - x0 + 1);
        // The 8 pixels whose lanes' x − x0 are idx, of central differences dx and dy (exact
        // integers in float): the generic kernel's operations in the same order, so the same
        // rounding (no FMA); lanes past x1 add zeros.
        const auto eightPixels = [&](__m256 dx, __m256 dy, __m256i idx) {
            const __m256 d =
                _mm256_mul_ps(half, _mm256_add_ps(_mm256_mul_ps(dx, vnx), _mm256_mul_ps(dy, vny)));
            const __m256 pass = _mm256_and_ps(_mm256_cmp_ps(d, vthr, _CMP_GT_OQ),
                                              _mm256_castsi256_ps(_mm256_cmpgt_epi32(end, idx)));
            if (_mm256_testz_ps(pass, pass)) return;
            const __m256 fi = _mm256_cvtepi32_ps(idx);
            const __m256 w = _mm256_and_ps(pass, _mm256_sub_ps(d, vthr));
            const __m256 u = _mm256_add_ps(vu0, _mm256_mul_ps(vnx, fi));
            const __m256 t = _mm256_sub_ps(vt0, _mm256_mul_ps(vny, fi));
            const __m256 wu = _mm256_mul_ps(w, u), wt = _mm256_mul_ps(w, t);
            const __m256 wuu = _mm256_mul_ps(wu, u);
            __m256i s = _mm256_cvttps_epi32(_mm256_mul_ps(_mm256_add_ps(t, vhl), vinv));
            s = _mm256_max_epi32(_mm256_setzero_si256(), _mm256_min_epi32(s, top));
            // t is linear along the row, so the lanes' slices run from the first lane's to the
            // last's: one to three of them.
            const int sa = _mm256_extract_epi32(s, 0), sb = _mm256_extract_epi32(s, 7);
            if (sa == sb) {
                // All lanes in one slice (most rows of a patch nearly along y): no lane masks.
                float* a = acc + M * L * sa;
                _mm256_storeu_ps(a, _mm256_add_ps(_mm256_loadu_ps(a), w));
                _mm256_storeu_ps(a + L, _mm256_add_ps(_mm256_loadu_ps(a + L), wu));
                _mm256_storeu_ps(a + 2 * L, _mm256_add_ps(_mm256_loadu_ps(a + 2 * L), wt));
                _mm256_storeu_ps(a + 3 * L, _mm256_add_ps(_mm256_loadu_ps(a + 3 * L), wuu));
                return;
            }
            for (int q = std::min(sa, sb); q <= std::max(sa, sb); ++q) {
                const __m256 m = _mm256_castsi256_ps(_mm256_cmpeq_epi32(s, _mm256_set1_epi32(q)));
                float* a = acc + M * L * q;
                _mm256_storeu_ps(a, _mm256_add_ps(_mm256_loadu_ps(a), _mm256_and_ps(m, w)));
                _mm256_storeu_ps(a + L,
                                 _mm256_add_ps(_mm256_loadu_ps(a + L), _mm256_and_ps(m, wu)));
                _mm256_storeu_ps(a + 2 * L,
                                 _mm256_add_ps(_mm256_loadu_ps(a + 2 * L), _mm256_and_ps(m, wt)));
                _mm256_storeu_ps(a + 3 * L,
                                 _mm256_add_ps(_mm256_loadu_ps(a + 3 * L), _mm256_and_ps(m, wuu)));
            }
        };
        int x = x0;
        __m256i idx = iota;
        // 16 pixels per step while the loads (up to x + 16 in this row and the next) stay inside
        // the image's rows: the differences in 16 bits, then two steps of 8 in float
        // (lane i still adds into partial i mod 8, in the same order). idx holds the lanes' x − x0.
        const int last16 = std::min(x1, width - 17);
        for (; x <= last16; x += 16, idx = _mm256_add_epi32(idx, sixteen)) {
            const __m256i dx = _mm256_sub_epi16(widen16(r + x + 1), widen16(r + x - 1));
            const __m256i dy = _mm256_sub_epi16(widen16(r + x + stride), widen16(r + x - stride));
            const auto lo = [](__m256i v) {
                return _mm256_cvtepi32_ps(_mm256_cvtepi16_epi32(_mm256_castsi256_si128(v)));
            };
            const auto hi = [](__m256i v) {
                return _mm256_cvtepi32_ps(_mm256_cvtepi16_epi32(_mm256_extracti128_si256(v, 1)));
            };
            // Lanes of pl: pixels 0–3 and 8–11; of ph: 4–7 and 12–15.
            const __m256i pl = _mm256_madd_epi16(_mm256_unpacklo_epi16(dx, dy), vN);
            const __m256i ph = _mm256_madd_epi16(_mm256_unpackhi_epi16(dx, dy), vN);
            const int maybe = _mm256_movemask_ps(_mm256_castsi256_ps(
                _mm256_or_si256(_mm256_cmpgt_epi32(pl, vT), _mm256_cmpgt_epi32(ph, vT))));
            if (maybe & 0x0f) eightPixels(lo(dx), lo(dy), idx);
            // (A row's last step often has no pixel of its own in its second half; the pixels
            // read there are past the row's end.)
            if ((maybe & 0xf0) && x + 8 <= x1)
                eightPixels(hi(dx), hi(dy), _mm256_add_epi32(idx, eight));
        }
        // Then 8 pixels per step while the loads (up to x + 8) stay inside the rows.
        const int last = std::min(x1, width - 9);
        for (; x <= last; x += 8, idx = _mm256_add_epi32(idx, eight))
            eightPixels(_mm256_sub_ps(widen8f(r + x + 1), widen8f(r + x - 1)),
                        _mm256_sub_ps(widen8f(r + x + stride), widen8f(r + x - stride)), idx);
        // The last pixels of the image's last columns: the generic arithmetic, in the same lanes.
        if (x <= x1) geometryPixels(r, stride, x0, x, x1, sp.u0, sp.t0, g, acc);
    }
}

void orderKeysAvx2(const uint64_t* keys, size_t n, size_t m, uint64_t* out) {
    // Keys are below 2⁶³ (|g|² < 2³¹ above the index), so signed compares order them; the
    // padding (0) is below every key and is never counted above one.
    alignas(32) uint64_t pad[kMaxOrderKeys + 4];
    std::memcpy(pad, keys, n * sizeof(uint64_t));
    const size_t n4 = (n + 3) & ~size_t{3};
    std::fill(pad + n, pad + n4, uint64_t{0});
    const __m256i* v = reinterpret_cast<const __m256i*>(pad);
    alignas(32) int64_t rank[4];
    for (size_t i = 0; i < n4; i += 4) {
        const __m256i k0 = _mm256_set1_epi64x(static_cast<int64_t>(pad[i]));
        const __m256i k1 = _mm256_set1_epi64x(static_cast<int64_t>(pad[i + 1]));
        const __m256i k2 = _mm256_set1_epi64x(static_cast<int64_t>(pad[i + 2]));
        const __m256i k3 = _mm256_set1_epi64x(static_cast<int64_t>(pad[i + 3]));
        __m256i a0 = _mm256_setzero_si256(), a1 = a0, a2 = a0, a3 = a0;
        // A true compare is −1: subtracting it counts the keys above.
        for (size_t j = 0; j < n4 / 4; ++j) {
            const __m256i x = _mm256_load_si256(v + j);
            a0 = _mm256_sub_epi64(a0, _mm256_cmpgt_epi64(x, k0));
            a1 = _mm256_sub_epi64(a1, _mm256_cmpgt_epi64(x, k1));
            a2 = _mm256_sub_epi64(a2, _mm256_cmpgt_epi64(x, k2));
            a3 = _mm256_sub_epi64(a3, _mm256_cmpgt_epi64(x, k3));
        }
        // The four counts' lanes added up: [a0, a1, a2, a3] in one vector.
        const __m256i s01 =
            _mm256_add_epi64(_mm256_unpacklo_epi64(a0, a1), _mm256_unpackhi_epi64(a0, a1));
        const __m256i s23 =
            _mm256_add_epi64(_mm256_unpacklo_epi64(a2, a3), _mm256_unpackhi_epi64(a2, a3));
        const __m256i r = _mm256_add_epi64(_mm256_permute2x128_si256(s01, s23, 0x20),
                                           _mm256_permute2x128_si256(s01, s23, 0x31));
        _mm256_store_si256(reinterpret_cast<__m256i*>(rank), r);
        for (size_t q = 0; q < 4 && i + q < n; ++q)
            if (static_cast<size_t>(rank[q]) < m) out[rank[q]] = pad[i + q];
    }
}

void oneSidedSumsAvx2(const int16_t* gx, const int16_t* gy, ptrdiff_t stride, int width, int rows,
                      int32_t nx, int32_t ny, int64_t* along, int64_t* magnitude) {
    if (width > 16)
        return oneSidedSumsGeneric(gx, gy, stride, width, rows, nx, ny, along, magnitude);
    // (gx, gy) pairs times (nx, ny) by madd: 32-bit d, |d| ≤ 2·1020², and sums of at most
    // 16 × 16 of them below 2³¹ per lane. The unpacks take points 0–3 and 8–11 (lo), 4–7 and
    // 12–15 (hi); points past the width are masked.
    const __m256i n = _mm256_set1_epi32(
        static_cast<int32_t>((static_cast<uint32_t>(ny) << 16) | static_cast<uint16_t>(nx)));
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 8, 9, 10, 11);
    const __m256i w = _mm256_set1_epi32(width);
    const __m256i inLo = _mm256_cmpgt_epi32(w, lane);
    const __m256i inHi = _mm256_cmpgt_epi32(w, _mm256_add_epi32(lane, _mm256_set1_epi32(4)));
    __m256i sum = _mm256_setzero_si256(), abs = _mm256_setzero_si256();
    for (int y = 0; y < rows; ++y) {
        const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(gx + y * stride));
        const __m256i z = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(gy + y * stride));
        const __m256i lo =
            _mm256_and_si256(inLo, _mm256_madd_epi16(_mm256_unpacklo_epi16(x, z), n));
        const __m256i hi =
            _mm256_and_si256(inHi, _mm256_madd_epi16(_mm256_unpackhi_epi16(x, z), n));
        sum = _mm256_add_epi32(sum, _mm256_add_epi32(lo, hi));
        abs = _mm256_add_epi32(abs, _mm256_add_epi32(_mm256_abs_epi32(lo), _mm256_abs_epi32(hi)));
    }
    alignas(32) int32_t s[8], a[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(s), sum);
    _mm256_store_si256(reinterpret_cast<__m256i*>(a), abs);
    for (int i = 0; i < 8; ++i)
        *along += s[i], *magnitude += a[i];
}

int patchRowsAvx2(const PatchRows& s, GeometrySpan* out) {
    // An axis-aligned slab bounds rows, not x: the generic walk handles those patches.
    if (s.s1.open || s.s2.open) return patchRowsGeneric(s, out);
    GeometrySpan* const first = out;
    const __m256d cx = _mm256_set1_pd(s.cx), cy = _mm256_set1_pd(s.cy);
    const __m256d nx = _mm256_set1_pd(s.nx), ny = _mm256_set1_pd(s.ny);
    const __m256d slope1 = _mm256_set1_pd(s.s1.slope), half1 = _mm256_set1_pd(s.s1.half);
    const __m256d slope2 = _mm256_set1_pd(s.s2.slope), half2 = _mm256_set1_pd(s.s2.half);
    const __m256d left = _mm256_set1_pd(s.left), right = _mm256_set1_pd(s.right);
    const __m256d leftEnd = _mm256_set1_pd(s.left - 1.0), rightEnd = _mm256_set1_pd(s.right + 1.0);
    const __m256d half = _mm256_set1_pd(0.5);
    const __m256d bx0 = _mm256_set1_pd(s.bx0), bx1 = _mm256_set1_pd(s.bx1 - 1);
    const __m256d sign = _mm256_set1_pd(-0.0);
    const __m256i rowStep = _mm256_setr_epi64x(0, s.stride, 2 * s.stride, 3 * s.stride);
    alignas(32) int32_t x0s[4], x1s[4];
    alignas(16) float us[4], ts[4];
    // Four rows at a time, the generic walk's double operations in the same order: max and min
    // of numbers are exact, and ceil and floor of the row ends are whole numbers.
    for (int y = s.y0; y <= s.y1; y += 4) {
        const __m256d vy = _mm256_setr_pd(y, y + 1.0, y + 2.0, y + 3.0);
        const __m256d dy = _mm256_sub_pd(_mm256_add_pd(vy, half), cy);
        const __m256d c1 = _mm256_add_pd(cx, _mm256_mul_pd(slope1, dy));
        const __m256d c2 = _mm256_add_pd(cx, _mm256_mul_pd(slope2, dy));
        // Clamped to the patch's x range like the generic walk's ends (a slab nearly along y).
        const __m256d lo = _mm256_min_pd(
            _mm256_max_pd(_mm256_max_pd(left, _mm256_sub_pd(c1, half1)), _mm256_sub_pd(c2, half2)),
            rightEnd);
        const __m256d hi = _mm256_max_pd(
            _mm256_min_pd(_mm256_min_pd(right, _mm256_add_pd(c1, half1)), _mm256_add_pd(c2, half2)),
            leftEnd);
        const __m256d x0 = _mm256_max_pd(bx0, _mm256_ceil_pd(_mm256_sub_pd(lo, half)));
        const __m256d x1 = _mm256_min_pd(bx1, _mm256_floor_pd(_mm256_sub_pd(hi, half)));
        const __m256d dx = _mm256_sub_pd(_mm256_add_pd(x0, half), cx);
        const __m256d u = _mm256_add_pd(_mm256_mul_pd(dx, nx), _mm256_mul_pd(dy, ny));
        const __m256d t =
            _mm256_add_pd(_mm256_mul_pd(_mm256_xor_pd(dx, sign), ny), _mm256_mul_pd(dy, nx));
        const __m128i ix0 = _mm256_cvttpd_epi32(x0), ix1 = _mm256_cvttpd_epi32(x1);
        const __m128 fu = _mm256_cvtpd_ps(u), ft = _mm256_cvtpd_ps(t);
        if (y + 3 <= s.y1 && _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpgt_epi32(ix0, ix1))) == 0) {
            // Four rows, none empty (the rows inside a patch): the four 24-byte spans, three
            // 8-byte fields each (row pointer; x0, x1; u0, t0), put in place by permutes and
            // written by three stores.
            static_assert(sizeof(GeometrySpan) == 24);
            const __m256i rp = _mm256_add_epi64(
                _mm256_set1_epi64x(reinterpret_cast<intptr_t>(s.data + y * s.stride)), rowStep);
            const __m256i xs =
                _mm256_setr_m128i(_mm_unpacklo_epi32(ix0, ix1), _mm_unpackhi_epi32(ix0, ix1));
            const __m256i ut = _mm256_castps_si256(
                _mm256_setr_m128(_mm_unpacklo_ps(fu, ft), _mm_unpackhi_ps(fu, ft)));
            const auto pick = [](__m256i r, __m256i x, __m256i v) {
                return _mm256_blend_epi32(_mm256_blend_epi32(r, x, 0x0c), v, 0x30);
            };
            auto* o = reinterpret_cast<__m256i*>(out);
            _mm256_storeu_si256(
                o, pick(_mm256_permute4x64_epi64(rp, 0x40), _mm256_permute4x64_epi64(xs, 0x00),
                        _mm256_permute4x64_epi64(ut, 0x00)));
            _mm256_storeu_si256(
                o + 1, pick(_mm256_permute4x64_epi64(xs, 0x81), _mm256_permute4x64_epi64(ut, 0x04),
                            _mm256_permute4x64_epi64(rp, 0x20)));
            _mm256_storeu_si256(
                o + 2, pick(_mm256_permute4x64_epi64(ut, 0xc2), _mm256_permute4x64_epi64(rp, 0x0c),
                            _mm256_permute4x64_epi64(xs, 0x30)));
            out += 4;
            continue;
        }
        _mm_store_si128(reinterpret_cast<__m128i*>(x0s), ix0);
        _mm_store_si128(reinterpret_cast<__m128i*>(x1s), ix1);
        _mm_store_ps(us, fu);
        _mm_store_ps(ts, ft);
        for (int j = 0; j < 4 && y + j <= s.y1; ++j)
            if (x0s[j] <= x1s[j])
                *out++ = {s.data + static_cast<ptrdiff_t>(y + j) * s.stride, x0s[j], x1s[j], us[j],
                          ts[j]};
    }
    return static_cast<int>(out - first);
}

int esfBinsAvx2(const uint32_t* acc, int from, int n, double binPx, double hw, const EsfBins& out) {
    const double unit = binPx / 2048.0;
    const __m256d vunit = _mm256_set1_pd(unit), vbin = _mm256_set1_pd(binPx);
    const __m256d vhw = _mm256_set1_pd(hw), one = _mm256_set1_pd(1.0), half = _mm256_set1_pd(0.5);
    const __m256d zero = _mm256_setzero_pd();
    const __m128i mask = _mm_set1_epi32((1 << kEsfCountShift) - 1);
    int i = from, k = 0;
    for (; i + 4 <= n; i += 4) {
        // Four bins' four words, transposed into one vector per word.
        const __m128i b0 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(acc + 4 * i));
        const __m128i b1 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(acc + 4 * i + 4));
        const __m128i b2 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(acc + 4 * i + 8));
        const __m128i b3 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(acc + 4 * i + 12));
        const __m128i t0 = _mm_unpacklo_epi32(b0, b1), t1 = _mm_unpackhi_epi32(b0, b1);
        const __m128i t2 = _mm_unpacklo_epi32(b2, b3), t3 = _mm_unpackhi_epi32(b2, b3);
        const __m128i w0 = _mm_unpacklo_epi64(t0, t2), w1 = _mm_unpackhi_epi64(t0, t2);
        const __m128i w2 = _mm_unpacklo_epi64(t1, t3), w3 = _mm_unpackhi_epi64(t1, t3);
        const __m128i cnt = _mm_srli_epi32(w0, kEsfCountShift);
        const int full =
            _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpgt_epi32(cnt, _mm_setzero_si128())));
        if (full == 0) continue;
        // esfBinsGeneric's operations, in the same order (an empty lane divides by zero and is
        // dropped by the packing).
        const __m256d count = _mm256_cvtepi32_pd(cnt);
        const __m256d inv = _mm256_div_pd(one, count);
        const __m256d v = _mm256_mul_pd(_mm256_cvtepi32_pd(_mm_and_si128(w0, mask)), inv);
        const __m256d d = _mm256_mul_pd(_mm256_mul_pd(_mm256_cvtepi32_pd(w2), vunit), inv);
        const __m256d ki = _mm256_setr_pd(i, i + 1.0, i + 2.0, i + 3.0);
        const __m256d centre = _mm256_sub_pd(_mm256_mul_pd(_mm256_add_pd(ki, half), vbin), vhw);
        const __m256d wv = _mm256_sub_pd(
            _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(_mm256_cvtepi32_pd(w3), vunit), vunit), inv),
            _mm256_mul_pd(d, d));
        const __m256d pv =
            _mm256_sub_pd(_mm256_mul_pd(_mm256_cvtepi32_pd(w1), inv), _mm256_mul_pd(v, v));
        // The non-empty lanes moved to the front of each vector and stored at the next free
        // entry; the lanes behind them land in the arrays' slack or are overwritten next.
        const __m256i order =
            _mm256_load_si256(reinterpret_cast<const __m256i*>(kPackOrder.lanes[full]));
        auto put = [&](double* a, __m256d x) {
            _mm256_storeu_pd(
                a + k, _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(x), order)));
        };
        put(out.pos, _mm256_add_pd(centre, d));
        put(out.value, v);
        // max(x, 0) keeps std::max(0.0, x)'s result for −0 and NaN: +0.
        put(out.withinVar, _mm256_max_pd(wv, zero));
        put(out.pixelVar, _mm256_max_pd(pv, zero));
        put(out.count, count);
        k += __builtin_popcount(static_cast<unsigned>(full));
    }
    return k + esfBinsGeneric(acc, i, n, binPx, hw, out.from(k));
}

void pairTermsAvx2(const PairInputs& b, int from, int n, double* x, double* c, double* sums) {
    if (from == 0) _mm256_storeu_pd(sums, _mm256_setzero_pd());
    const __m256d half = _mm256_set1_pd(0.5), twelve = _mm256_set1_pd(12.0);
    __m256d run = _mm256_loadu_pd(sums + 4 * from);
    int i = from;
    // Pairs i..i + 3 read bins up to i + 4.
    for (; i + 5 <= n; i += 4) {
        const __m256d p0 = _mm256_loadu_pd(b.pos + i), p1 = _mm256_loadu_pd(b.pos + i + 1);
        const __m256d step =
            _mm256_sub_pd(_mm256_loadu_pd(b.value + i + 1), _mm256_loadu_pd(b.value + i));
        const __m256d mid = _mm256_mul_pd(half, _mm256_add_pd(p0, p1));
        const __m256d gap = _mm256_sub_pd(p1, p0);
        const __m256d spread =
            _mm256_add_pd(_mm256_div_pd(_mm256_mul_pd(gap, gap), twelve),
                          _mm256_mul_pd(half, _mm256_add_pd(_mm256_loadu_pd(b.withinVar + i),
                                                            _mm256_loadu_pd(b.withinVar + i + 1))));
        _mm256_storeu_pd(x + i, mid);
        _mm256_storeu_pd(c + i, spread);
        const __m256d sx = _mm256_mul_pd(step, mid);
        const __m256d sxx = _mm256_mul_pd(sx, mid);
        const __m256d sc = _mm256_mul_pd(step, spread);
        // One vector of the four terms per pair (a 4 × 4 transpose), added to the running sums
        // in pair order: each sum takes the generic version's additions.
        const __m256d lo01 = _mm256_unpacklo_pd(step, sx), hi01 = _mm256_unpackhi_pd(step, sx);
        const __m256d lo23 = _mm256_unpacklo_pd(sxx, sc), hi23 = _mm256_unpackhi_pd(sxx, sc);
        const __m256d pair[4] = {
            _mm256_permute2f128_pd(lo01, lo23, 0x20), _mm256_permute2f128_pd(hi01, hi23, 0x20),
            _mm256_permute2f128_pd(lo01, lo23, 0x31), _mm256_permute2f128_pd(hi01, hi23, 0x31)};
        for (int j = 0; j < 4; ++j) {
            run = _mm256_add_pd(run, pair[j]);
            _mm256_storeu_pd(sums + 4 * (i + j + 1), run);
        }
    }
    pairTermsGeneric(b, i, n, x, c, sums);
}

size_t countAtLeastAvx2(const int32_t* m, size_t n, int32_t v) {
    const __m256i below = _mm256_set1_epi32(v - 1);
    size_t count = 0, i = 0;
    // 32 points a step, each compare's −1 lanes subtracted from a count per lane (at most n/8):
    // a region's grid is a few thousand points, and a movemask and popcount per 8 of them cost
    // more than the compares.
    __m256i lanes = _mm256_setzero_si256();
    for (; i + 32 <= n; i += 32) {
        const auto at = [&](size_t j) {
            return _mm256_cmpgt_epi32(
                _mm256_loadu_si256(reinterpret_cast<const __m256i*>(m + i + j)), below);
        };
        lanes = _mm256_sub_epi32(lanes, _mm256_add_epi32(_mm256_add_epi32(at(0), at(8)),
                                                         _mm256_add_epi32(at(16), at(24))));
    }
    alignas(32) uint32_t perLane[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(perLane), lanes);
    for (const uint32_t c : perLane)
        count += c;
    for (; i + 8 <= n; i += 8) {
        const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(m + i));
        count += static_cast<size_t>(__builtin_popcount(
            _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(x, below)))));
    }
    return count + countAtLeastGeneric(m + i, n - i, v);
}

void levelsAvx2(const int32_t* m, size_t n, int shift, uint8_t* levels) {
    const __m128i count = _mm_cvtsi32_si128(shift);
    // The packs interleave 32-bit groups of the four vectors within 128-bit halves; the
    // permutation puts the 32 bytes back in order.
    const __m256i order = _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7);
    size_t i = 0;
    for (; i + 32 <= n; i += 32) {
        const auto at = [&](size_t j) {
            return _mm256_srl_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(m + i + j)),
                                    count);
        };
        const __m256i ab = _mm256_packus_epi32(at(0), at(8));
        const __m256i cd = _mm256_packus_epi32(at(16), at(24));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(levels + i),
                            _mm256_permutevar8x32_epi32(_mm256_packus_epi16(ab, cd), order));
    }
    levelsGeneric(m + i, n - i, shift, levels + i);
}

size_t countLevelsAtLeastAvx2(const uint8_t* levels, size_t n, uint8_t v) {
    const __m256i vv = _mm256_set1_epi8(static_cast<char>(v));
    size_t count = 0, i = 0;
    // 128 points a step (the bisection counts a region's grid eight times): the loop's own
    // instructions were a third of the count's.
    for (; i + 128 <= n; i += 128) {
        const auto mask = [&](size_t j) {
            const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(levels + i + j));
            return static_cast<uint32_t>(
                _mm256_movemask_epi8(_mm256_cmpeq_epi8(_mm256_max_epu8(x, vv), x)));
        };
        count += static_cast<size_t>(
            __builtin_popcountll(mask(0) | static_cast<uint64_t>(mask(32)) << 32) +
            __builtin_popcountll(mask(64) | static_cast<uint64_t>(mask(96)) << 32));
    }
    for (; i + 32 <= n; i += 32) {
        const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(levels + i));
        // x ≥ v (unsigned) exactly when max(x, v) = x.
        count += static_cast<size_t>(__builtin_popcount(static_cast<uint32_t>(
            _mm256_movemask_epi8(_mm256_cmpeq_epi8(_mm256_max_epu8(x, vv), x)))));
    }
    return count + countLevelsAtLeastGeneric(levels + i, n - i, v);
}

size_t listLevelsAtLeastAvx2(const uint8_t* levels, int shift, const int32_t* m, size_t n,
                             int32_t v, uint64_t* keys) {
    const int level = v >> shift;
    const __m256i vl = _mm256_set1_epi8(static_cast<char>(level));
    size_t listed = 0, i = 0;
    for (; i + 32 <= n; i += 32) {
        const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(levels + i));
        // Few points pass the byte test; only theirs are read in m (x ≥ level: max(x, level) = x).
        auto bits = static_cast<uint32_t>(
            _mm256_movemask_epi8(_mm256_cmpeq_epi8(_mm256_max_epu8(x, vl), x)));
        while (bits) {
            // Written always, kept when m[j] ≥ v: no branch on the points at the level's edge
            // (listed ≤ j, so the write stays inside the n keys).
            const size_t j = i + static_cast<size_t>(__builtin_ctz(bits));
            keys[listed] = candidateKey(m[j], j);
            listed += m[j] >= v;
            bits &= bits - 1;
        }
    }
    for (; i < n; ++i)
        if (levels[i] >= level && m[i] >= v) keys[listed++] = candidateKey(m[i], i);
    return listed;
}

size_t listAtLeastAvx2(const int32_t* m, size_t n, int32_t v, uint64_t* keys) {
    const __m256i below = _mm256_set1_epi32(v - 1);
    size_t listed = 0, i = 0;
    for (; i + 8 <= n; i += 8) {
        const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(m + i));
        // Few points pass: test 8 at once, then visit only the set bits.
        auto bits = static_cast<unsigned>(
            _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(x, below))));
        while (bits) {
            const size_t j = i + static_cast<size_t>(__builtin_ctz(bits));
            keys[listed++] = candidateKey(m[j], j);
            bits &= bits - 1;
        }
    }
    for (; i < n; ++i)
        if (m[i] >= v) keys[listed++] = candidateKey(m[i], i);
    return listed;
}

void geometryReduceAvx2(const float* acc, int slices, double* out) {
    constexpr int L = kGeometryLanes, M = kGeometryMoments;
    static_assert(L == 8 && M == 4, "one slice is a 4 x 8 block");
    for (int s = 0; s < slices; ++s) {
        const float* a = acc + M * L * s;
        // Transpose the 4 moments × 8 lanes so that each vector holds lane l of the 4 moments,
        // then add the lanes in order in double: each moment's sum in the generic order.
        const __m256 r0 = _mm256_loadu_ps(a), r1 = _mm256_loadu_ps(a + L);
        const __m256 r2 = _mm256_loadu_ps(a + 2 * L), r3 = _mm256_loadu_ps(a + 3 * L);
        const __m256 t0 = _mm256_unpacklo_ps(r0, r1), t1 = _mm256_unpackhi_ps(r0, r1);
        const __m256 t2 = _mm256_unpacklo_ps(r2, r3), t3 = _mm256_unpackhi_ps(r2, r3);
        // Lane l of moments 0..3: columns of the 4 × 4 transposes of each 128-bit half.
        const __m256 c0 = _mm256_shuffle_ps(t0, t2, 0x44), c1 = _mm256_shuffle_ps(t0, t2, 0xee);
        const __m256 c2 = _mm256_shuffle_ps(t1, t3, 0x44), c3 = _mm256_shuffle_ps(t1, t3, 0xee);
        __m256d sum = _mm256_setzero_pd();
        for (const __m128 lane : {_mm256_castps256_ps128(c0), _mm256_castps256_ps128(c1),
                                  _mm256_castps256_ps128(c2), _mm256_castps256_ps128(c3),
                                  _mm256_extractf128_ps(c0, 1), _mm256_extractf128_ps(c1, 1),
                                  _mm256_extractf128_ps(c2, 1), _mm256_extractf128_ps(c3, 1)})
            sum = _mm256_add_pd(sum, _mm256_cvtps_pd(lane));
        _mm256_storeu_pd(out + M * s, sum);
    }
}

namespace {

// esfRowsAvx2 into Copies (1 or 2) copies of the bins: lane j adds into copy j mod Copies, copy 0
// being @p acc and copy 1 @p copy1, which the caller adds to it.
template <int Copies>
void esfRowsInto(const GeometrySpan* spans, int count, int width, const EsfPatch& e, uint32_t* acc,
                 uint32_t* copy1) {
    const __m256 vnx = _mm256_set1_ps(e.nx), vhw = _mm256_set1_ps(e.hw);
    const __m256 vinv = _mm256_set1_ps(e.inv), vbin = _mm256_set1_ps(e.binPx);
    const __m256 vhalf = _mm256_set1_ps(0.5f), vscale = _mm256_set1_ps(e.offsetScale);
    const __m256 vbins = _mm256_set1_ps(static_cast<float>(e.bins));
    const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    // A spare bin per lane: the lanes past a row's end (a third of them on a typical row) would
    // otherwise each wait for the last one's add to the same bin.
    const __m256i spare = _mm256_add_epi32(_mm256_set1_epi32(e.bins), iota);
    const __m256i one = _mm256_set1_epi32(1 << kEsfCountShift);
    const __m256i eight = _mm256_set1_epi32(8);
    char* const base0 = reinterpret_cast<char*>(acc);
    char* const base1 = reinterpret_cast<char*>(Copies == 2 ? copy1 : acc);
    alignas(32) uint32_t bin[8];
    for (int k = 0; k < count; ++k) {
        const GeometrySpan& sp = spans[k];
        const uint8_t* r = sp.r;
        const int x0 = sp.x0, x1 = sp.x1;
        const __m256 vu0 = _mm256_set1_ps(sp.u0);
        const __m256i end = _mm256_set1_epi32(x1 - x0 + 1);
        int x = x0;
        // 8 pixels per step while the 8-byte load stays inside the row; idx holds the lanes'
        // x − x0.
        const int last = std::min(x1, width - 8);
        __m256i idx = iota;
        for (; x <= last; x += 8, idx = _mm256_add_epi32(idx, eight)) {
            // esfBin's float operations, in the same order.
            const __m256 uh =
                _mm256_add_ps(_mm256_add_ps(vu0, _mm256_mul_ps(vnx, _mm256_cvtepi32_ps(idx))), vhw);
            const __m256 q = _mm256_mul_ps(uh, vinv);
            const __m256i inSpan = _mm256_cmpgt_epi32(end, idx);
            const __m256 inside =
                _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(q, _mm256_setzero_ps(), _CMP_GE_OQ),
                                            _mm256_cmp_ps(q, vbins, _CMP_LT_OQ)),
                              _mm256_castsi256_ps(inSpan));
            const __m256i kq = _mm256_cvttps_epi32(q);
            const __m256 centre = _mm256_mul_ps(_mm256_add_ps(_mm256_cvtepi32_ps(kq), vhalf), vbin);
            const __m256i off = _mm256_and_si256(
                _mm256_castps_si256(inside),
                _mm256_cvttps_epi32(_mm256_mul_ps(_mm256_sub_ps(uh, centre), vscale)));
            const __m256i kb = _mm256_castps_si256(
                _mm256_blendv_ps(_mm256_castsi256_ps(spare), _mm256_castsi256_ps(kq), inside));
            const __m256i v =
                _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(r + x)));
            // Lanes past the row's end add nothing (the generic kernel never sees them).
            const __m256i a = _mm256_and_si256(inSpan, _mm256_add_epi32(v, one));
            const __m256i b = _mm256_and_si256(inSpan, _mm256_mullo_epi32(v, v));
            const __m256i c = off;
            const __m256i d = _mm256_mullo_epi32(off, off);
            // Four words per pixel: a 4×4 transpose in each 128-bit half.
            const __m256i t0 = _mm256_unpacklo_epi32(a, b), t1 = _mm256_unpackhi_epi32(a, b);
            const __m256i t2 = _mm256_unpacklo_epi32(c, d), t3 = _mm256_unpackhi_epi32(c, d);
            // Pixels 0 and 4, 1 and 5, 2 and 6, 3 and 7, four words each, added from registers.
            const __m256i p04 = _mm256_unpacklo_epi64(t0, t2), p15 = _mm256_unpackhi_epi64(t0, t2);
            const __m256i p26 = _mm256_unpacklo_epi64(t1, t3), p37 = _mm256_unpackhi_epi64(t1, t3);
            // The bins' byte offsets (16 bytes a bin), unsigned: the address needs no shift or
            // sign extension per pixel.
            _mm256_store_si256(reinterpret_cast<__m256i*>(bin), _mm256_slli_epi32(kb, 4));
            const auto add = [&](char* base, int j, __m128i w) {
                auto* dst = reinterpret_cast<__m128i*>(base + bin[j]);
                _mm_storeu_si128(dst, _mm_add_epi32(_mm_loadu_si128(dst), w));
            };
            add(base0, 0, _mm256_castsi256_si128(p04));
            add(base1, 1, _mm256_castsi256_si128(p15));
            add(base0, 2, _mm256_castsi256_si128(p26));
            add(base1, 3, _mm256_castsi256_si128(p37));
            add(base0, 4, _mm256_extracti128_si256(p04, 1));
            add(base1, 5, _mm256_extracti128_si256(p15, 1));
            add(base0, 6, _mm256_extracti128_si256(p26, 1));
            add(base1, 7, _mm256_extracti128_si256(p37, 1));
        }
        // The last pixels of the image's last columns: the generic arithmetic.
        if (x <= x1) esfPixels(r, x0, x, x1, sp.u0, e, acc);
    }
}

}  // namespace

void esfRowsAvx2(const GeometrySpan* spans, int count, int width, const EsfPatch& e,
                 uint32_t* acc) {
    // Where neighbouring pixels of a row fall in one bin (an edge within 14° of the rows, for
    // ¼ px bins), each pixel's add would wait for the one before it; there the odd lanes add into
    // a second copy of the bins, added to the first at the end. Elsewhere that copy costs more
    // than it saves.
    if (std::abs(e.nx) >= e.binPx) return esfRowsInto<1>(spans, count, width, e, acc, nullptr);
    const size_t words = 4 * static_cast<size_t>(e.bins + kEsfSpareBins);
    thread_local std::vector<uint32_t> copy;
    copy.assign(words, 0u);
    esfRowsInto<2>(spans, count, width, e, acc, copy.data());
    for (size_t i = 0; i < words; i += 4) {
        auto* dst = reinterpret_cast<__m128i*>(acc + i);
        _mm_storeu_si128(
            dst, _mm_add_epi32(_mm_loadu_si128(dst),
                               _mm_loadu_si128(reinterpret_cast<const __m128i*>(copy.data() + i))));
    }
}

}  // namespace infocus::detail
