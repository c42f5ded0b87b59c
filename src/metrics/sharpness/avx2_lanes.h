// SPDX-License-Identifier: MIT
// Internal: lane helpers shared by the AVX2 sharpness kernels (kernels_avx2.cpp, dct_avx2.cpp).
// Only files compiled with -mavx2 include it.
#pragma once

#include <immintrin.h>

#include <cstdint>

namespace infocus::detail::avx2 {

// 32 pixels from @p p (unaligned).
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

// Adds 8 float lanes into 4 double lanes.
inline __m256d addAsDouble(__m256d acc, __m256 v) {
    acc = _mm256_add_pd(acc, _mm256_cvtps_pd(_mm256_castps256_ps128(v)));
    return _mm256_add_pd(acc, _mm256_cvtps_pd(_mm256_extractf128_ps(v, 1)));
}

// The sum of the 4 double lanes.
inline double sumPd(__m256d v) {
    alignas(32) double s[4];
    _mm256_store_pd(s, v);
    return s[0] + s[1] + s[2] + s[3];
}

// The sum of the 4 i64 lanes.
inline int64_t sum64(__m256i v) {
    alignas(32) int64_t s[4];
    _mm256_store_si256(reinterpret_cast<__m256i*>(s), v);
    return s[0] + s[1] + s[2] + s[3];
}

}  // namespace infocus::detail::avx2
