// SPDX-License-Identifier: MIT
// Vectorised DCT sums behind DCTR: the AC energy of 8×8 blocks from exact integer sums, the
// low-frequency coefficients transformed in float. This file alone is compiled with -mavx2;
// sharpness.cpp calls it only after a run-time CPU check.
#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "avx2_lanes.h"
#include "kernels.h"

namespace infocus::detail {

using namespace avx2;

namespace {

// DCTR by Parseval: the AC energy of an orthonormal block transform is Σ p² − DC², exact in
// integers, so only the nine low-frequency coefficients (1 ≤ u + v ≤ 3) need transforming; the
// high-frequency energy is the rest. Columns first, in 16-bit lanes (one per image column, exact
// butterflies), then the rows of 8 blocks at a time after a transpose (one float lane per
// block). Raw transforms omit the normalisation α_0 = 1/√8, α_k = 1/2: squares are weighted by
// α_u² α_v² (1/32 with one zero index, 1/16 with none) at the end.
namespace dct {

// cos(kπ/16), k = 0 … 7.
inline float cosPi16(int k) {
    return static_cast<float>(std::cos(k * 3.14159265358979323846 / 16.0));
}

// The raw 8-point DCT-II terms 1 … 3 of a vector x from its butterflies s_k = x_k + x_{7−k} and
// d_k = x_k − x_{7−k}: t1 = Σ cos((2k+1)π/16) d_k, t2 = cos(π/8)(s0 − s3) + cos(3π/8)(s1 − s2)
// (given as s03 = s0 − s3 and s12 = s1 − s2), t3 = Σ cos(3(2k+1)π/16) d_k.
struct Terms {
    __m256 t1, t2, t3;
};

inline Terms terms(__m256 s03, __m256 s12, const __m256 d[4]) {
    static const float c1 = cosPi16(1), c2 = cosPi16(2), c3 = cosPi16(3), c5 = cosPi16(5),
                       c6 = cosPi16(6), c7 = cosPi16(7);
    const auto k = [](float v) { return _mm256_set1_ps(v); };
    Terms t;
    t.t1 = _mm256_fmadd_ps(
        k(c1), d[0],
        _mm256_fmadd_ps(k(c3), d[1], _mm256_fmadd_ps(k(c5), d[2], _mm256_mul_ps(k(c7), d[3]))));
    t.t2 = _mm256_fmadd_ps(k(c2), s03, _mm256_mul_ps(k(c6), s12));
    t.t3 = _mm256_fmsub_ps(
        k(c3), d[0],
        _mm256_fmadd_ps(k(c7), d[1], _mm256_fmadd_ps(k(c1), d[2], _mm256_mul_ps(k(c5), d[3]))));
    return t;
}

inline void transpose8(__m256 r[8]) {
    __m256 t[8], u[8];
    for (int i = 0; i < 8; i += 2) {
        t[i] = _mm256_unpacklo_ps(r[i], r[i + 1]);
        t[i + 1] = _mm256_unpackhi_ps(r[i], r[i + 1]);
    }
    for (int i = 0; i < 8; i += 4) {
        u[i] = _mm256_shuffle_ps(t[i], t[i + 2], 0x44);
        u[i + 1] = _mm256_shuffle_ps(t[i], t[i + 2], 0xEE);
        u[i + 2] = _mm256_shuffle_ps(t[i + 1], t[i + 3], 0x44);
        u[i + 3] = _mm256_shuffle_ps(t[i + 1], t[i + 3], 0xEE);
    }
    for (int i = 0; i < 4; ++i) {
        r[i] = _mm256_permute2f128_ps(u[i], u[i + 4], 0x20);
        r[i + 4] = _mm256_permute2f128_ps(u[i], u[i + 4], 0x31);
    }
}

inline void toFloat(__m256i v16, __m256& lo, __m256& hi) {
    lo = _mm256_cvtepi32_ps(_mm256_cvtepi16_epi32(_mm256_castsi256_si128(v16)));
    hi = _mm256_cvtepi32_ps(_mm256_cvtepi16_epi32(_mm256_extracti128_si256(v16, 1)));
}

}  // namespace dct

}  // namespace

DctSums simdDctSums(const Luma8& img, const Rect& a) {
    using namespace dct;
    DctSums out;
    const int nbx = a.w / 8, nby = a.h / 8;
    if (nbx == 0 || nby == 0) return out;
    out.blocks = static_cast<double>(nbx) * nby;
    // Column transforms of one chunk of up to 8 blocks: raw terms v = 0 … 3 per column.
    alignas(32) float buf[4][64];
    __m256i sq64 = _mm256_setzero_si256(), dc64 = sq64;
    __m256d lowA = _mm256_setzero_pd(), lowB = lowA;  // weights 1/32 and 1/16
    for (int by = 0; by < nby; ++by) {
        const uint8_t* rows[8];
        for (int y = 0; y < 8; ++y)
            rows[y] = img.row(a.y + 8 * by + y) + a.x;
        for (int cb = 0; cb < nbx; cb += 8) {
            const int nb = std::min(8, nbx - cb);
            __m256i sq32 = _mm256_setzero_si256();
            for (int g = 0; g < 4; ++g) {
                float* col[4] = {buf[0] + 16 * g, buf[1] + 16 * g, buf[2] + 16 * g,
                                 buf[3] + 16 * g};
                if (2 * g >= nb) {  // past the last block: zero terms add nothing
                    for (float* c : col)
                        std::fill(c, c + 16, 0.0f);
                    continue;
                }
                // One block (8 bytes) or two (16 bytes): never read past the region's blocks.
                const bool two = 2 * g + 1 < nb;
                const int x = (cb + 2 * g) * 8;
                __m256i p[8];
                for (int y = 0; y < 8; ++y) {
                    const auto* src = reinterpret_cast<const __m128i*>(rows[y] + x);
                    p[y] = _mm256_cvtepu8_epi16(two ? _mm_loadu_si128(src) : _mm_loadl_epi64(src));
                    sq32 = _mm256_add_epi32(sq32, _mm256_madd_epi16(p[y], p[y]));
                }
                __m256i s16[4], d16[4];
                for (int k = 0; k < 4; ++k) {
                    s16[k] = _mm256_add_epi16(p[k], p[7 - k]);
                    d16[k] = _mm256_sub_epi16(p[k], p[7 - k]);
                }
                const __m256i t0 = _mm256_add_epi16(_mm256_add_epi16(s16[0], s16[1]),
                                                    _mm256_add_epi16(s16[2], s16[3]));
                // Only what the cosine weights multiply goes to float: d_k, s0 − s3, s1 − s2.
                __m256 dLo[4], dHi[4], t0Lo, t0Hi, s03Lo, s03Hi, s12Lo, s12Hi;
                for (int k = 0; k < 4; ++k)
                    toFloat(d16[k], dLo[k], dHi[k]);
                toFloat(t0, t0Lo, t0Hi);
                toFloat(_mm256_sub_epi16(s16[0], s16[3]), s03Lo, s03Hi);
                toFloat(_mm256_sub_epi16(s16[1], s16[2]), s12Lo, s12Hi);
                const Terms lo = terms(s03Lo, s12Lo, dLo), hi = terms(s03Hi, s12Hi, dHi);
                _mm256_store_ps(col[0], t0Lo), _mm256_store_ps(col[0] + 8, t0Hi);
                _mm256_store_ps(col[1], lo.t1), _mm256_store_ps(col[1] + 8, hi.t1);
                _mm256_store_ps(col[2], lo.t2), _mm256_store_ps(col[2] + 8, hi.t2);
                _mm256_store_ps(col[3], lo.t3), _mm256_store_ps(col[3] + 8, hi.t3);
            }
            sq64 = widenAdd(sq64, sq32);
            // Row transforms, one lane per block: coefficient (u, v) is row term u of column
            // term v. Needed: (1..3, 0), (0..2, 1), (0..1, 2), (0, 3); (0, 0) is the block sum.
            __m256 a32 = _mm256_setzero_ps(), b16 = a32;
            // Column term 3 needs only row term 0, the sum of each block's 8 values: a tree
            // of horizontal adds instead of a transpose.
            {
                const float* c3 = buf[3];
                const auto pair = [&](int b) {
                    return _mm256_hadd_ps(_mm256_load_ps(c3 + 8 * b),
                                          _mm256_load_ps(c3 + 8 * b + 8));
                };
                const __m256 g0 = _mm256_hadd_ps(pair(0), pair(2));
                const __m256 g1 = _mm256_hadd_ps(pair(4), pair(6));
                const __m256 u0 = _mm256_add_ps(_mm256_permute2f128_ps(g0, g1, 0x20),
                                                _mm256_permute2f128_ps(g0, g1, 0x31));
                a32 = _mm256_fmadd_ps(u0, u0, a32);
            }
            for (int v = 0; v < 3; ++v) {
                __m256 r[8];
                for (int b = 0; b < 8; ++b)
                    r[b] = _mm256_load_ps(buf[v] + 8 * b);
                transpose8(r);
                __m256 s[4], d[4];
                for (int k = 0; k < 4; ++k) {
                    s[k] = _mm256_add_ps(r[k], r[7 - k]);
                    d[k] = _mm256_sub_ps(r[k], r[7 - k]);
                }
                const __m256 u0 =
                    _mm256_add_ps(_mm256_add_ps(s[0], s[1]), _mm256_add_ps(s[2], s[3]));
                if (v == 0) {
                    // Block sums are integers below 2^14: exact in float, squared in int32.
                    const __m256i sum = _mm256_cvtps_epi32(u0);
                    dc64 = widenAdd(dc64, _mm256_mullo_epi32(sum, sum));
                } else {
                    a32 = _mm256_fmadd_ps(u0, u0, a32);
                }
                const Terms t = terms(_mm256_sub_ps(s[0], s[3]), _mm256_sub_ps(s[1], s[2]), d);
                if (v == 0) {
                    a32 = _mm256_fmadd_ps(t.t1, t.t1, a32);
                    a32 = _mm256_fmadd_ps(t.t2, t.t2, a32);
                    a32 = _mm256_fmadd_ps(t.t3, t.t3, a32);
                } else {
                    b16 = _mm256_fmadd_ps(t.t1, t.t1, b16);
                    if (v == 1) b16 = _mm256_fmadd_ps(t.t2, t.t2, b16);
                }
            }
            lowA = addAsDouble(lowA, a32);
            lowB = addAsDouble(lowB, b16);
        }
    }
    const double sumSq = static_cast<double>(sum64(sq64));
    const double sumDc2 = static_cast<double>(sum64(dc64));
    out.ac = sumSq - sumDc2 / 64.0;
    const double low = sumPd(lowA) / 32.0 + sumPd(lowB) / 16.0;
    out.hf = std::max(0.0, out.ac - low);
    return out;
}

}  // namespace infocus::detail
