// SPDX-License-Identifier: MIT
// AVX2 pixel kernels of the blur-width engine: the same arithmetic as the generic versions in
// blur.cpp, 8 or 16 pixels at a time. This file alone is compiled with -mavx2; blur.cpp calls it
// only after a run-time CPU check.
#include <immintrin.h>

#include "blur_kernels.h"

namespace infocus::detail {

namespace {

inline __m256i widen16(const uint8_t* p) {
    return _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
}

inline __m256 widen8f(const uint8_t* p) {
    return _mm256_cvtepi32_ps(
        _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))));
}

}  // namespace

void sobelRowAvx2(const uint8_t* a, const uint8_t* m, const uint8_t* c, int x0, int n, int16_t* gx,
                  int16_t* gy) {
    int i = 0;
    // 16 pixels per step: |gx|, |gy| ≤ 1020 fit int16. Loads reach x + 16, inside the row.
    for (; i + 16 <= n; i += 16) {
        const int x = x0 + i;
        const __m256i al = widen16(a + x - 1), ac = widen16(a + x), ar = widen16(a + x + 1);
        const __m256i ml = widen16(m + x - 1), mr = widen16(m + x + 1);
        const __m256i cl = widen16(c + x - 1), cc = widen16(c + x), cr = widen16(c + x + 1);
        const __m256i dx =
            _mm256_add_epi16(_mm256_add_epi16(_mm256_sub_epi16(ar, al), _mm256_sub_epi16(cr, cl)),
                             _mm256_slli_epi16(_mm256_sub_epi16(mr, ml), 1));
        const __m256i dy =
            _mm256_add_epi16(_mm256_add_epi16(_mm256_sub_epi16(cl, al), _mm256_sub_epi16(cr, ar)),
                             _mm256_slli_epi16(_mm256_sub_epi16(cc, ac), 1));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(gx + i), dx);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(gy + i), dy);
    }
    if (i < n) sobelRowGeneric(a, m, c, x0 + i, n - i, gx + i, gy + i);
}

int aboveThresholdAvx2(const uint8_t* r, ptrdiff_t stride, int x0, int x1, int width, float nx,
                       float ny, float thr, int32_t* out) {
    const __m256 vnx = _mm256_set1_ps(nx), vny = _mm256_set1_ps(ny);
    const __m256 half = _mm256_set1_ps(0.5f), vthr = _mm256_set1_ps(thr);
    int count = 0;
    int x = x0;
    // 8 pixels per step while the loads (up to x + 8 in this row and the next) stay inside the
    // image's rows; lanes past x1 are masked off.
    for (; x <= x1 && x + 8 < width; x += 8) {
        const __m256 dx = _mm256_sub_ps(widen8f(r + x + 1), widen8f(r + x - 1));
        const __m256 dy = _mm256_sub_ps(widen8f(r + x + stride), widen8f(r + x - stride));
        // Same operations and order as the generic kernel, so the same rounding (no FMA).
        const __m256 d =
            _mm256_mul_ps(half, _mm256_add_ps(_mm256_mul_ps(dx, vnx), _mm256_mul_ps(dy, vny)));
        unsigned mask =
            static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(d, vthr, _CMP_GT_OQ)));
        if (x1 - x < 7) mask &= (2u << (x1 - x)) - 1u;
        while (mask) {
            out[count++] = x - x0 + __builtin_ctz(mask);
            mask &= mask - 1;
        }
    }
    if (x <= x1) {
        const int n = aboveThresholdGeneric(r, stride, x, x1, width, nx, ny, thr, out + count);
        for (int k = 0; k < n; ++k)
            out[count + k] += x - x0;
        count += n;
    }
    return count;
}

}  // namespace infocus::detail
