// SPDX-License-Identifier: MIT
// Vectorised LAPV and TENG: one pass over the pixels with AVX2. For LAPV, Σ L comes from the
// region's border alone because the Laplacian's sum telescopes. This file alone is compiled with
// -mavx2; sharpness.cpp calls it only after a run-time CPU check.
#include <immintrin.h>

#include <algorithm>
#include <cstdint>

#include "sharpness_kernels.h"

namespace infocus::detail {

namespace {

inline __m256i load(const uint8_t* p) {
    return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
}

// Byte mask selecting the pixels at or after @p skip in a 32-pixel window.
inline __m256i tailMask(int skip) {
    alignas(32) static const uint8_t ramp[32] = {0,  1,  2,  3,  4,  5,  6,  7,  8,  9,  10,
                                                 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21,
                                                 22, 23, 24, 25, 26, 27, 28, 29, 30, 31};
    // ramp > skip − 1 as signed bytes (all values < 128).
    return _mm256_cmpgt_epi8(load(ramp), _mm256_set1_epi8(static_cast<char>(skip - 1)));
}

// Adds 8 i32 lanes into 4 i64 lanes (before they can overflow).
inline __m256i widenAdd(__m256i acc64, __m256i v32) {
    acc64 = _mm256_add_epi64(acc64, _mm256_cvtepi32_epi64(_mm256_castsi256_si128(v32)));
    return _mm256_add_epi64(acc64, _mm256_cvtepi32_epi64(_mm256_extracti128_si256(v32, 1)));
}

inline int64_t sum64(__m256i v) {
    alignas(32) int64_t s[4];
    _mm256_store_si256(reinterpret_cast<__m256i*>(s), v);
    return s[0] + s[1] + s[2] + s[3];
}

// Σ I and Σ L² for the 32 pixels at x of rows u, c, d; with Masked, pixels before x + skip are
// left out (the overlapping last window of a row).
template <bool Masked>
inline void lapvStep(const uint8_t* u, const uint8_t* c, const uint8_t* d, int x, __m256i mask,
                     __m256i& l2, __m256i& si) {
    const __m256i zero = _mm256_setzero_si256();
    const __m256i ones8 = _mm256_set1_epi8(1);
    __m256i vc = load(c + x);
    const __m256i vl = load(c + x - 1), vr = load(c + x + 1), vu = load(u + x), vd = load(d + x);
    // Pairs (u,d) and (l,r) summed to 16 bits by maddubs with ones: u+d and l+r.
    const __m256i udLo = _mm256_maddubs_epi16(_mm256_unpacklo_epi8(vu, vd), ones8);
    const __m256i udHi = _mm256_maddubs_epi16(_mm256_unpackhi_epi8(vu, vd), ones8);
    const __m256i lrLo = _mm256_maddubs_epi16(_mm256_unpacklo_epi8(vl, vr), ones8);
    const __m256i lrHi = _mm256_maddubs_epi16(_mm256_unpackhi_epi8(vl, vr), ones8);
    const __m256i cLo = _mm256_slli_epi16(_mm256_unpacklo_epi8(vc, zero), 2);
    const __m256i cHi = _mm256_slli_epi16(_mm256_unpackhi_epi8(vc, zero), 2);
    __m256i lapLo = _mm256_sub_epi16(_mm256_add_epi16(udLo, lrLo), cLo);
    __m256i lapHi = _mm256_sub_epi16(_mm256_add_epi16(udHi, lrHi), cHi);
    if constexpr (Masked) {
        vc = _mm256_and_si256(vc, mask);
        lapLo = _mm256_and_si256(lapLo, _mm256_unpacklo_epi8(mask, mask));
        lapHi = _mm256_and_si256(lapHi, _mm256_unpackhi_epi8(mask, mask));
    }
    si = _mm256_add_epi64(si, _mm256_sad_epu8(vc, zero));
    l2 = _mm256_add_epi32(l2, _mm256_madd_epi16(lapLo, lapLo));
    l2 = _mm256_add_epi32(l2, _mm256_madd_epi16(lapHi, lapHi));
}

// Σ I and Σ (Gx² + Gy²) of the unscaled Sobel for 32 pixels, as two halves of 16 widened by
// zero-extending loads: plain 16-bit adds and subtracts and one multiply (madd) per square, so
// the multiply ports are not the bottleneck.
template <bool Masked>
inline void tengStep(const uint8_t* u, const uint8_t* c, const uint8_t* d, int x, __m256i mask,
                     __m256i& g2, __m256i& si) {
    const __m256i zero = _mm256_setzero_si256();
    __m256i cm = load(c + x);
    if constexpr (Masked) cm = _mm256_and_si256(cm, mask);
    si = _mm256_add_epi64(si, _mm256_sad_epu8(cm, zero));
    const auto w16 = [](const uint8_t* p) {
        return _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
    };
    for (int h = 0; h < 32; h += 16) {
        const int o = x + h;
        const __m256i ul = w16(u + o - 1), um = w16(u + o), ur = w16(u + o + 1);
        const __m256i cl = w16(c + o - 1), cr = w16(c + o + 1);
        const __m256i dl = w16(d + o - 1), dm = w16(d + o), dr = w16(d + o + 1);
        const __m256i cd = _mm256_sub_epi16(cr, cl);
        __m256i gx =
            _mm256_add_epi16(_mm256_add_epi16(_mm256_sub_epi16(ur, ul), _mm256_sub_epi16(dr, dl)),
                             _mm256_add_epi16(cd, cd));
        const __m256i vd = _mm256_sub_epi16(dm, um);
        __m256i gy =
            _mm256_add_epi16(_mm256_add_epi16(_mm256_sub_epi16(dl, ul), _mm256_sub_epi16(dr, ur)),
                             _mm256_add_epi16(vd, vd));
        if constexpr (Masked) {
            const __m256i m16 = _mm256_cvtepi8_epi16(h == 0 ? _mm256_castsi256_si128(mask)
                                                            : _mm256_extracti128_si256(mask, 1));
            gx = _mm256_and_si256(gx, m16);
            gy = _mm256_and_si256(gy, m16);
        }
        g2 = _mm256_add_epi32(g2, _mm256_madd_epi16(gx, gx));
        g2 = _mm256_add_epi32(g2, _mm256_madd_epi16(gy, gy));
    }
}

// TENG for two rows at once (y and y+1 from rows r0 = y−1 … r3 = y+2) over 32 pixels: the Sobel
// separates into per-row terms h = right − left and s = left + 2·middle + right, each computed
// once and shared by both output rows (Gx = h0 + 2h1 + h2, Gy = s2 − s0, and one row down).
template <bool Masked>
inline void tengStep2(const uint8_t* r0, const uint8_t* r1, const uint8_t* r2, const uint8_t* r3,
                      int x, __m256i mask, __m256i& g2, __m256i& si) {
    const __m256i zero = _mm256_setzero_si256();
    __m256i c1 = load(r1 + x), c2 = load(r2 + x);
    if constexpr (Masked) {
        c1 = _mm256_and_si256(c1, mask);
        c2 = _mm256_and_si256(c2, mask);
    }
    si = _mm256_add_epi64(si,
                          _mm256_add_epi64(_mm256_sad_epu8(c1, zero), _mm256_sad_epu8(c2, zero)));
    const auto w16 = [](const uint8_t* p) {
        return _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
    };
    for (int hh = 0; hh < 32; hh += 16) {
        const int o = x + hh;
        __m256i h[4], sm[4];
        const uint8_t* rows[4] = {r0, r1, r2, r3};
        for (int k = 0; k < 4; ++k) {
            const __m256i l = w16(rows[k] + o - 1), m = w16(rows[k] + o), r = w16(rows[k] + o + 1);
            h[k] = _mm256_sub_epi16(r, l);
            sm[k] = _mm256_add_epi16(_mm256_add_epi16(l, r), _mm256_add_epi16(m, m));
        }
        __m256i gxA = _mm256_add_epi16(_mm256_add_epi16(h[0], h[2]), _mm256_add_epi16(h[1], h[1]));
        __m256i gxB = _mm256_add_epi16(_mm256_add_epi16(h[1], h[3]), _mm256_add_epi16(h[2], h[2]));
        __m256i gyA = _mm256_sub_epi16(sm[2], sm[0]);
        __m256i gyB = _mm256_sub_epi16(sm[3], sm[1]);
        if constexpr (Masked) {
            const __m256i m16 = _mm256_cvtepi8_epi16(hh == 0 ? _mm256_castsi256_si128(mask)
                                                             : _mm256_extracti128_si256(mask, 1));
            gxA = _mm256_and_si256(gxA, m16);
            gxB = _mm256_and_si256(gxB, m16);
            gyA = _mm256_and_si256(gyA, m16);
            gyB = _mm256_and_si256(gyB, m16);
        }
        g2 = _mm256_add_epi32(
            g2, _mm256_add_epi32(_mm256_madd_epi16(gxA, gxA), _mm256_madd_epi16(gyA, gyA)));
        g2 = _mm256_add_epi32(
            g2, _mm256_add_epi32(_mm256_madd_epi16(gxB, gxB), _mm256_madd_epi16(gyB, gyB)));
    }
}

// TENG over @p a two rows at a time (half the loads and loop overhead of one row at a time); an
// odd last row goes through the one-row step. Needs a.w ≥ 32. A lane gains at most 16·1020² per
// two-row window: widen every 64 windows.
void tengSums2(const Luma8& img, const Rect& a, int64_t& sumI, int64_t& sumSq);

// Runs Step over every valid pixel of @p a: whole 32-pixel windows, then one overlapping masked
// window for the rest of a row. Needs a.w ≥ 32. The i32 sums are widened to i64 every 128
// windows: a lane gains at most 8·1020² per window, so it cannot overflow before.
template <
    void (*Full)(const uint8_t*, const uint8_t*, const uint8_t*, int, __m256i, __m256i&, __m256i&),
    void (*Tail)(const uint8_t*, const uint8_t*, const uint8_t*, int, __m256i, __m256i&, __m256i&)>
void sums(const Luma8& img, const Rect& a, int64_t& sumI, int64_t& sumSq) {
    __m256i acc32 = _mm256_setzero_si256(), acc64 = _mm256_setzero_si256();
    __m256i si = _mm256_setzero_si256();
    const int end = a.x + a.w;
    const int full = a.w / 32 * 32;
    const __m256i mask = tailMask(32 - (a.w - full));
    int windows = 0;
    for (int y = a.y; y < a.y + a.h; ++y) {
        const uint8_t* c = img.row(y);
        const uint8_t* u = img.row(y - 1);
        const uint8_t* d = img.row(y + 1);
        // A region is a narrow column of the frame: the hardware prefetcher does not see the
        // stride, so fetch a few rows ahead ourselves (0.40 -> 0.35 ms for a 1080p 16x9 grid).
        if (y + 4 < img.height) {
            const uint8_t* next = img.row(y + 4);
            for (int x = a.x - 1; x < end + 1; x += 64)
                _mm_prefetch(reinterpret_cast<const char*>(next + x), _MM_HINT_T0);
        }
        for (int x = a.x; x < a.x + full; x += 32)
            Full(u, c, d, x, mask, acc32, si);
        if (full < a.w) Tail(u, c, d, end - 32, mask, acc32, si);
        windows += a.w / 32 + 1;
        if (windows >= 128) {
            acc64 = widenAdd(acc64, acc32);
            acc32 = _mm256_setzero_si256();
            windows = 0;
        }
    }
    acc64 = widenAdd(acc64, acc32);
    sumI = sum64(si);
    sumSq = sum64(acc64);
}

// Scalar sums for regions narrower than one vector.
void lapvScalar(const Luma8& img, const Rect& a, int64_t& sumI, int64_t& sumL2) {
    sumI = sumL2 = 0;
    for (int y = a.y; y < a.y + a.h; ++y) {
        const uint8_t *c = img.row(y), *u = img.row(y - 1), *d = img.row(y + 1);
        for (int x = a.x; x < a.x + a.w; ++x) {
            const int v = u[x] + d[x] + c[x - 1] + c[x + 1] - 4 * c[x];
            sumL2 += v * v;
            sumI += c[x];
        }
    }
}

void tengScalar(const Luma8& img, const Rect& a, int64_t& sumI, int64_t& sumG2) {
    sumI = sumG2 = 0;
    for (int y = a.y; y < a.y + a.h; ++y) {
        const uint8_t *c = img.row(y), *u = img.row(y - 1), *d = img.row(y + 1);
        for (int x = a.x; x < a.x + a.w; ++x) {
            const int gx =
                (u[x + 1] - u[x - 1]) + 2 * (c[x + 1] - c[x - 1]) + (d[x + 1] - d[x - 1]);
            const int gy = (d[x - 1] - u[x - 1]) + 2 * (d[x] - u[x]) + (d[x + 1] - u[x + 1]);
            sumG2 += gx * gx + gy * gy;
            sumI += c[x];
        }
    }
}

void lapvSumsAvx2(const Luma8& img, const Rect& a, int64_t& sumI, int64_t& sumL2) {
    if (a.w < 32) return lapvScalar(img, a, sumI, sumL2);
    sums<lapvStep<false>, lapvStep<true>>(img, a, sumI, sumL2);
}

void tengSums2(const Luma8& img, const Rect& a, int64_t& sumI, int64_t& sumSq) {
    __m256i acc32 = _mm256_setzero_si256(), acc64 = _mm256_setzero_si256();
    __m256i si = _mm256_setzero_si256();
    const int end = a.x + a.w;
    const int full = a.w / 32 * 32;
    const __m256i mask = tailMask(32 - (a.w - full));
    int windows = 0;
    int y = a.y;
    for (; y + 1 < a.y + a.h; y += 2) {
        const uint8_t* r0 = img.row(y - 1);
        const uint8_t* r1 = img.row(y);
        const uint8_t* r2 = img.row(y + 1);
        const uint8_t* r3 = img.row(y + 2);
        // A region is a narrow column of the frame: the hardware prefetcher does not see the
        // stride, so fetch a few rows ahead ourselves.
        for (int k = 3; k <= 4; ++k) {
            if (y + k >= img.height) break;
            const uint8_t* next = img.row(y + k);
            for (int x = a.x - 1; x < end + 1; x += 64)
                _mm_prefetch(reinterpret_cast<const char*>(next + x), _MM_HINT_T0);
        }
        for (int x = a.x; x < a.x + full; x += 32)
            tengStep2<false>(r0, r1, r2, r3, x, mask, acc32, si);
        if (full < a.w) tengStep2<true>(r0, r1, r2, r3, end - 32, mask, acc32, si);
        windows += a.w / 32 + 1;
        if (windows >= 64) {
            acc64 = widenAdd(acc64, acc32);
            acc32 = _mm256_setzero_si256();
            windows = 0;
        }
    }
    if (y < a.y + a.h) {  // the odd last row
        const uint8_t *u = img.row(y - 1), *c = img.row(y), *d = img.row(y + 1);
        for (int x = a.x; x < a.x + full; x += 32)
            tengStep<false>(u, c, d, x, mask, acc32, si);
        if (full < a.w) tengStep<true>(u, c, d, end - 32, mask, acc32, si);
    }
    acc64 = widenAdd(acc64, acc32);
    sumI = sum64(si);
    sumSq = sum64(acc64);
}

void tengSumsAvx2(const Luma8& img, const Rect& a, int64_t& sumI, int64_t& sumG2) {
    if (a.w < 32) return tengScalar(img, a, sumI, sumG2);
    tengSums2(img, a, sumI, sumG2);
}

}  // namespace

namespace {

// The pixels of @p region whose 3×3 neighbourhood lies inside the image.
Rect validArea(const Luma8& img, const Rect& region) {
    const int x0 = std::max(region.x, 1), y0 = std::max(region.y, 1);
    const int x1 = std::min(region.x + region.w, img.width - 1);
    const int y1 = std::min(region.y + region.h, img.height - 1);
    return {x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0)};
}

}  // namespace

double simdLapv(const Luma8& img, const Rect& region, double noiseSigma) {
    const Rect a = validArea(img, region);
    if (a.w == 0 || a.h == 0) return 0.0;
    const int x0 = a.x, y0 = a.y, x1 = a.x + a.w, y1 = a.y + a.h;
    int64_t sumI = 0, sumL2 = 0;
    lapvSumsAvx2(img, a, sumI, sumL2);
    // Σ L telescopes: per column (top-outside − last + below-last − first), likewise per row.
    int64_t sumL = 0;
    for (int x = x0; x < x1; ++x)
        sumL += int(img.at(x, y0 - 1)) - img.at(x, y1 - 1) + img.at(x, y1) - img.at(x, y0);
    for (int y = y0; y < y1; ++y)
        sumL += int(img.at(x0 - 1, y)) - img.at(x1 - 1, y) + img.at(x1, y) - img.at(x0, y);
    return lapvFromSums(static_cast<double>(a.w) * a.h, static_cast<double>(sumI),
                        static_cast<double>(sumL), static_cast<double>(sumL2),
                        img.width / kReferenceWidthPx, noiseSigma * noiseSigma);
}

double simdTeng(const Luma8& img, const Rect& region, double noiseSigma) {
    const Rect a = validArea(img, region);
    if (a.w == 0 || a.h == 0) return 0.0;
    int64_t sumI = 0, sumG2 = 0;
    tengSumsAvx2(img, a, sumI, sumG2);
    // Unscaled Sobel is 8× the gradient: divide the squares by 64.
    return tengFromSums(static_cast<double>(a.w) * a.h, static_cast<double>(sumI),
                        static_cast<double>(sumG2) / 64.0, img.width / kReferenceWidthPx,
                        noiseSigma * noiseSigma);
}

}  // namespace infocus::detail
