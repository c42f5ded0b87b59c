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

void lapvSumsAvx2(const Luma8& img, const Rect& a, int64_t& sumI, int64_t& sumL2) {
    const __m256i ones = _mm256_set1_epi16(1);
    const __m256i zero = _mm256_setzero_si256();
    int64_t accI = 0, accL2 = 0;
    for (int y = a.y; y < a.y + a.h; ++y) {
        const uint8_t* c = img.row(y);
        const uint8_t* u = img.row(y - 1);
        const uint8_t* d = img.row(y + 1);
        __m256i l2 = _mm256_setzero_si256();  // 8 × i32, at most 2·1020² per lane per step
        __m256i si = _mm256_setzero_si256();  // 4 × i64 from sad
        int x = a.x;
        const int end = a.x + a.w;
        for (; x + 32 <= end; x += 32) {
            const __m256i vc = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(c + x));
            const __m256i vl = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(c + x - 1));
            const __m256i vr = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(c + x + 1));
            const __m256i vu = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(u + x));
            const __m256i vd = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(d + x));
            si = _mm256_add_epi64(si, _mm256_sad_epu8(vc, zero));
            // Pairs (u,d) and (l,r) summed to 16 bits by maddubs with ones: u+d and l+r.
            const __m256i ones8 = _mm256_set1_epi8(1);
            const __m256i udLo = _mm256_maddubs_epi16(_mm256_unpacklo_epi8(vu, vd), ones8);
            const __m256i udHi = _mm256_maddubs_epi16(_mm256_unpackhi_epi8(vu, vd), ones8);
            const __m256i lrLo = _mm256_maddubs_epi16(_mm256_unpacklo_epi8(vl, vr), ones8);
            const __m256i lrHi = _mm256_maddubs_epi16(_mm256_unpackhi_epi8(vl, vr), ones8);
            const __m256i cLo = _mm256_slli_epi16(_mm256_unpacklo_epi8(vc, zero), 2);
            const __m256i cHi = _mm256_slli_epi16(_mm256_unpackhi_epi8(vc, zero), 2);
            const __m256i lapLo = _mm256_sub_epi16(_mm256_add_epi16(udLo, lrLo), cLo);
            const __m256i lapHi = _mm256_sub_epi16(_mm256_add_epi16(udHi, lrHi), cHi);
            l2 = _mm256_add_epi32(l2, _mm256_madd_epi16(lapLo, lapLo));
            l2 = _mm256_add_epi32(l2, _mm256_madd_epi16(lapHi, lapHi));
        }
        (void)ones;
        // Horizontal sums; i32 lanes cannot overflow within one row (≤ 2·1020²·w/16 < 2³¹
        // for rows up to 16 000 px).
        alignas(32) int32_t l2s[8];
        alignas(32) int64_t sis[4];
        _mm256_store_si256(reinterpret_cast<__m256i*>(l2s), l2);
        _mm256_store_si256(reinterpret_cast<__m256i*>(sis), si);
        for (int i = 0; i < 8; ++i)
            accL2 += l2s[i];
        for (int i = 0; i < 4; ++i)
            accI += sis[i];
        for (; x < end; ++x) {
            const int v = u[x] + d[x] + c[x - 1] + c[x + 1] - 4 * c[x];
            accL2 += v * v;
            accI += c[x];
        }
    }
    sumI = accI;
    sumL2 = accL2;
}

// Tenengrad: Σ I and Σ (Gx² + Gy²) with the unscaled Sobel (8× the gradient). Each difference
// pair comes from one maddubs over interleaved bytes with weights (w, −w).
void tengSumsAvx2(const Luma8& img, const Rect& a, int64_t& sumI, int64_t& sumG2) {
    const __m256i zero = _mm256_setzero_si256();
    const __m256i p1 = _mm256_set1_epi16(static_cast<int16_t>(0xff01));  // bytes (+1, −1)
    const __m256i p2 = _mm256_set1_epi16(static_cast<int16_t>(0xfe02));  // bytes (+2, −2)
    int64_t accI = 0, accG = 0;
    const auto load = [](const uint8_t* p) {
        return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
    };
    for (int y = a.y; y < a.y + a.h; ++y) {
        const uint8_t* c = img.row(y);
        const uint8_t* u = img.row(y - 1);
        const uint8_t* d = img.row(y + 1);
        __m256i g2 = _mm256_setzero_si256();
        __m256i si = _mm256_setzero_si256();
        int x = a.x;
        const int end = a.x + a.w;
        for (; x + 32 <= end; x += 32) {
            const __m256i ul = load(u + x - 1), um = load(u + x), ur = load(u + x + 1);
            const __m256i cl = load(c + x - 1), cm = load(c + x), cr = load(c + x + 1);
            const __m256i dl = load(d + x - 1), dm = load(d + x), dr = load(d + x + 1);
            si = _mm256_add_epi64(si, _mm256_sad_epu8(cm, zero));
            const auto diff = [](__m256i plus, __m256i minus, __m256i w, bool hi) {
                const __m256i pair =
                    hi ? _mm256_unpackhi_epi8(plus, minus) : _mm256_unpacklo_epi8(plus, minus);
                return _mm256_maddubs_epi16(pair, w);
            };
            for (bool hi : {false, true}) {
                const __m256i gx =
                    _mm256_add_epi16(_mm256_add_epi16(diff(ur, ul, p1, hi), diff(cr, cl, p2, hi)),
                                     diff(dr, dl, p1, hi));
                const __m256i gy =
                    _mm256_add_epi16(_mm256_add_epi16(diff(dl, ul, p1, hi), diff(dm, um, p2, hi)),
                                     diff(dr, ur, p1, hi));
                g2 = _mm256_add_epi32(g2, _mm256_madd_epi16(gx, gx));
                g2 = _mm256_add_epi32(g2, _mm256_madd_epi16(gy, gy));
            }
        }
        // i32 lanes: ≤ 4·2·1020² per 32 px step, safe for rows up to 8 000 px.
        alignas(32) int32_t gs[8];
        alignas(32) int64_t sis[4];
        _mm256_store_si256(reinterpret_cast<__m256i*>(gs), g2);
        _mm256_store_si256(reinterpret_cast<__m256i*>(sis), si);
        for (int i = 0; i < 8; ++i)
            accG += gs[i];
        for (int i = 0; i < 4; ++i)
            accI += sis[i];
        for (; x < end; ++x) {
            const int gx =
                (u[x + 1] - u[x - 1]) + 2 * (c[x + 1] - c[x - 1]) + (d[x + 1] - d[x - 1]);
            const int gy = (d[x - 1] - u[x - 1]) + 2 * (d[x] - u[x]) + (d[x + 1] - u[x + 1]);
            accG += gx * gx + gy * gy;
            accI += c[x];
        }
    }
    sumI = accI;
    sumG2 = accG;
}

}  // namespace

double simdLapv(const Luma8& img, const Rect& region, double noiseSigma) {
    const int x0 = std::max(region.x, 1), y0 = std::max(region.y, 1);
    const int x1 = std::min(region.x + region.w, img.width - 1);
    const int y1 = std::min(region.y + region.h, img.height - 1);
    if (x1 <= x0 || y1 <= y0) return 0.0;
    const Rect a{x0, y0, x1 - x0, y1 - y0};
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
    const int x0 = std::max(region.x, 1), y0 = std::max(region.y, 1);
    const int x1 = std::min(region.x + region.w, img.width - 1);
    const int y1 = std::min(region.y + region.h, img.height - 1);
    if (x1 <= x0 || y1 <= y0) return 0.0;
    const Rect a{x0, y0, x1 - x0, y1 - y0};
    int64_t sumI = 0, sumG2 = 0;
    tengSumsAvx2(img, a, sumI, sumG2);
    // Unscaled Sobel is 8× the gradient: divide the squares by 64.
    return tengFromSums(static_cast<double>(a.w) * a.h, static_cast<double>(sumI),
                        static_cast<double>(sumG2) / 64.0, img.width / kReferenceWidthPx,
                        noiseSigma * noiseSigma);
}

}  // namespace infocus::detail
