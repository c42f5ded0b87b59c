// SPDX-License-Identifier: MIT
// Vectorised sums of the pixel operators (LAPV, LAPM, TENG, TENV, Brenner, GLVN): one pass over
// the pixels with AVX2, exact integer arithmetic. For LAPV, Σ L comes from the region's border
// alone because the Laplacian's sum telescopes; and the sum of Immerkær's noise kernel. This file
// alone is compiled with -mavx2; sharpness.cpp calls it only after a run-time CPU check.
#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "avx2_lanes.h"
#include "kernels.h"

namespace infocus::detail {

using namespace avx2;

namespace {

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

// The Sobel separates into per-row terms h = right − left and s = left + 2·middle + right:
// Gx = h(y−1) + 2·h(y) + h(y+1) and Gy = s(y+1) − s(y−1). The TENG kernel walks down vertical
// strips of a region keeping the terms of the rows above in registers, so each image row of a
// strip is loaded and split once, not three times. A region of a grid fits in L1, so the later
// strips of a region read what the first one brought in.

// Per-row terms of 32 pixels at x in an even/odd layout: 16-bit lane i of the "e" vectors holds
// pixel x + 2i, of the "o" vectors pixel x + 2i + 1. Three plain loads give both: the low byte of
// a 16-bit lane of the load at x − 1 is the left neighbour of pixel x + 2i, its high byte the
// pixel itself, and so on; one multiply-add with weights (1, 2) forms left + 2·middle.
struct RowTerms32 {
    __m256i he, ho, se, so, centre;
};

inline RowTerms32 rowTerms32(const uint8_t* p, int x) {
    const __m256i lowByte = _mm256_set1_epi16(0x00ff);
    const __m256i w12 = _mm256_set1_epi16(0x0201);  // byte weights 1 (low), 2 (high)
    const __m256i a = load(p + x - 1), c = load(p + x), b = load(p + x + 1);
    const __m256i ae = _mm256_and_si256(a, lowByte), ce = _mm256_and_si256(c, lowByte);
    const __m256i be = _mm256_and_si256(b, lowByte), bo = _mm256_srli_epi16(b, 8);
    return {_mm256_sub_epi16(be, ae), _mm256_sub_epi16(bo, ce),
            _mm256_add_epi16(_mm256_maddubs_epi16(a, w12), be),
            _mm256_add_epi16(_mm256_maddubs_epi16(c, w12), bo), c};
}

// Accumulates one row of Sobel components: Σ (Gx² + Gy²) into @p acc32, and with Variance also
// Σ (Gx² + Gy²)² into @p sqf. Per pixel G from interleaved (Gx, Gy) pairs is exact in float
// (G < 2^21); its square is rounded to float (6e-8), and the caller moves @p sqf into doubles
// every few rows, so TENV agrees with the reference to about 1e-6.
template <bool Variance>
inline void addGradient(__m256i gx, __m256i gy, __m256i& acc32, __m256& sqf) {
    if constexpr (Variance) {
        const __m256i lo = _mm256_unpacklo_epi16(gx, gy), hi = _mm256_unpackhi_epi16(gx, gy);
        const __m256i gLo = _mm256_madd_epi16(lo, lo), gHi = _mm256_madd_epi16(hi, hi);
        acc32 = _mm256_add_epi32(acc32, _mm256_add_epi32(gLo, gHi));
        const __m256 fLo = _mm256_cvtepi32_ps(gLo), fHi = _mm256_cvtepi32_ps(gHi);
        sqf = _mm256_fmadd_ps(fLo, fLo, _mm256_fmadd_ps(fHi, fHi, sqf));
    } else {
        acc32 = _mm256_add_epi32(
            acc32, _mm256_add_epi32(_mm256_madd_epi16(gx, gx), _mm256_madd_epi16(gy, gy)));
    }
}

// Rows between moves of the float squares into doubles: a lane gains 4 squares per row, so 16
// float additions at most.
constexpr int kFloatRows = 4;

// The running sums of one strip, kept by value so that they stay in registers: i32 lanes
// widened into i64 every 128 rows (no strip kernel adds more than 8·1020² to a lane per row, so
// none can overflow before), and with Squares the float squares moved into doubles every
// kFloatRows rows. Call endRow() after each row and addTo() once at the end.
template <bool Squares>
struct StripSums {
    __m256i acc32 = _mm256_setzero_si256(), acc64 = _mm256_setzero_si256();
    __m256 sqf = _mm256_setzero_ps();
    __m256d sqd = _mm256_setzero_pd();
    int rows = 0;

    void endRow() {
        ++rows;
        if constexpr (Squares) {
            if (rows % kFloatRows == 0) {
                sqd = addAsDouble(sqd, sqf);
                sqf = _mm256_setzero_ps();
            }
        }
        if (rows == 128) {
            acc64 = widenAdd(acc64, acc32);
            acc32 = _mm256_setzero_si256();
            rows = 0;
        }
    }
    // Adds the strip's sums to the caller's (@p squares with Squares only).
    void addTo(__m256i& sum64, __m256d* squares) const {
        sum64 = _mm256_add_epi64(sum64, widenAdd(acc64, acc32));
        if constexpr (Squares) *squares = _mm256_add_pd(*squares, addAsDouble(sqd, sqf));
    }
};

// Σ I and Σ (Gx² + Gy²) of the unscaled Sobel over columns x … x+31 of rows y0 … y1−1 (with
// Variance also Σ (Gx² + Gy²)²). A lane of the i32 sum gains at most 8·1020² per row: widened to
// i64 every 128 rows, before it can overflow.
template <bool Variance>
void tengStrip32(const Luma8& img, int x, int y0, int y1, __m256i& acc64, __m256d& sqd,
                 __m256i& siOut) {
    const RowTerms32 r0 = rowTerms32(img.row(y0 - 1), x);
    const RowTerms32 r1 = rowTerms32(img.row(y0), x);
    // Σ I takes each row as it is loaded (rows y0 … y1, the last one taken back at the end), so
    // no row's raw bytes stay live across iterations: 16 registers hold the rest without spills.
    __m256i si = _mm256_sad_epu8(r1.centre, _mm256_setzero_si256());
    __m256i se0 = r0.se, so0 = r0.so, se1 = r1.se, so1 = r1.so, he1 = r1.he, ho1 = r1.ho;
    __m256i te = _mm256_add_epi16(r0.he, he1), to = _mm256_add_epi16(r0.ho, ho1);
    StripSums<Variance> sums;
    for (int y = y0; y < y1; ++y) {
        const RowTerms32 r2 = rowTerms32(img.row(y + 1), x);
        si = _mm256_add_epi64(si, _mm256_sad_epu8(r2.centre, _mm256_setzero_si256()));
        const __m256i te2 = _mm256_add_epi16(he1, r2.he), to2 = _mm256_add_epi16(ho1, r2.ho);
        addGradient<Variance>(_mm256_add_epi16(te, te2), _mm256_sub_epi16(r2.se, se0), sums.acc32,
                              sums.sqf);
        addGradient<Variance>(_mm256_add_epi16(to, to2), _mm256_sub_epi16(r2.so, so0), sums.acc32,
                              sums.sqf);
        se0 = se1, so0 = so1, se1 = r2.se, so1 = r2.so, he1 = r2.he, ho1 = r2.ho;
        te = te2, to = to2;
        sums.endRow();
    }
    sums.addTo(acc64, &sqd);
    si = _mm256_sub_epi64(si, _mm256_sad_epu8(load(img.row(y1) + x), _mm256_setzero_si256()));
    siOut = _mm256_add_epi64(siOut, si);
}

inline __m256i load16(const uint8_t* p) {
    return _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
}

// The same for 16 columns at x, in natural order (16-bit lane i is pixel x + i); with Masked the
// pixels before x + skip are left out (the overlapping last strip of a region).
template <bool Variance, bool Masked>
void tengStrip16(const Luma8& img, int x, int y0, int y1, int skip, __m256i& acc64, __m256d& sqd,
                 __m128i& siOut) {
    __m128i si = _mm_setzero_si128();
    const auto terms = [&](const uint8_t* p, __m256i& h, __m256i& s) {
        const __m256i l = load16(p + x - 1), m = load16(p + x), r = load16(p + x + 1);
        h = _mm256_sub_epi16(r, l);
        s = _mm256_add_epi16(_mm256_add_epi16(l, r), _mm256_add_epi16(m, m));
    };
    const __m128i mask8 = _mm256_castsi256_si128(tailMask(skip));
    const __m256i mask16 = _mm256_cvtepi8_epi16(mask8);
    __m256i h0, s0, h1, s1;
    terms(img.row(y0 - 1), h0, s0);
    terms(img.row(y0), h1, s1);
    __m256i t = _mm256_add_epi16(h0, h1);
    StripSums<Variance> sums;
    for (int y = y0; y < y1; ++y) {
        __m128i c = _mm_loadu_si128(reinterpret_cast<const __m128i*>(img.row(y) + x));
        if constexpr (Masked) c = _mm_and_si128(c, mask8);
        si = _mm_add_epi64(si, _mm_sad_epu8(c, _mm_setzero_si128()));
        __m256i h2, s2;
        terms(img.row(y + 1), h2, s2);
        const __m256i t2 = _mm256_add_epi16(h1, h2);
        __m256i gx = _mm256_add_epi16(t, t2), gy = _mm256_sub_epi16(s2, s0);
        if constexpr (Masked) {
            gx = _mm256_and_si256(gx, mask16);
            gy = _mm256_and_si256(gy, mask16);
        }
        addGradient<Variance>(gx, gy, sums.acc32, sums.sqf);
        s0 = s1, s1 = s2, h1 = h2, t = t2;
        sums.endRow();
    }
    sums.addTo(acc64, &sqd);
    siOut = _mm_add_epi64(siOut, si);
}

// The pixel-local operators walked down 16-column strips in natural order: LAPM
// (|2c − l − r| + |2c − u − d|), Brenner ((c[x+2] − c)² + (c[y+2] − c)²) and GLVN (c²). Each
// keeps the centre values of the rows it needs again in registers. A lane of the i32 sum gains
// at most 4·255² per row: widened every 128 rows.
enum class LocalOp { Lapm, Brenner, Glvn };

template <LocalOp Op, bool Masked>
void localStrip16(const Luma8& img, int x, int y0, int y1, int skip, __m256i& acc64,
                  __m128i& siOut) {
    __m128i si = _mm_setzero_si128();
    const __m128i mask8 = _mm256_castsi256_si128(tailMask(skip));
    const __m256i mask16 = _mm256_cvtepi8_epi16(mask8);
    const __m256i ones = _mm256_set1_epi16(1);
    StripSums<false> sums;
    // Centre values of rows y − 1 (LAPM), y and y + 1.
    __m256i mPrev = Op == LocalOp::Lapm ? load16(img.row(y0 - 1) + x) : ones;
    __m256i mCur = load16(img.row(y0) + x);
    __m256i mNext = Op == LocalOp::Glvn ? ones : load16(img.row(y0 + 1) + x);
    for (int y = y0; y < y1; ++y) {
        __m128i c = _mm_loadu_si128(reinterpret_cast<const __m128i*>(img.row(y) + x));
        if constexpr (Masked) c = _mm_and_si128(c, mask8);
        si = _mm_add_epi64(si, _mm_sad_epu8(c, _mm_setzero_si128()));
        __m256i v;
        if constexpr (Op == LocalOp::Glvn) {
            v = _mm256_cvtepu8_epi16(c);
            sums.acc32 = _mm256_add_epi32(sums.acc32, _mm256_madd_epi16(v, v));
        } else if constexpr (Op == LocalOp::Lapm) {
            const uint8_t* p = img.row(y) + x;
            const __m256i c2 = _mm256_add_epi16(mCur, mCur);
            const __m256i mBelow = load16(img.row(y + 1) + x);
            const __m256i h = _mm256_sub_epi16(c2, _mm256_add_epi16(load16(p - 1), load16(p + 1)));
            const __m256i w = _mm256_sub_epi16(c2, _mm256_add_epi16(mPrev, mBelow));
            v = _mm256_add_epi16(_mm256_abs_epi16(h), _mm256_abs_epi16(w));
            if constexpr (Masked) v = _mm256_and_si256(v, mask16);
            sums.acc32 = _mm256_add_epi32(sums.acc32, _mm256_madd_epi16(v, ones));
            mPrev = mCur, mCur = mBelow;
        } else {
            const __m256i mTwoBelow = load16(img.row(y + 2) + x);
            __m256i h = _mm256_sub_epi16(load16(img.row(y) + x + 2), mCur);
            __m256i w = _mm256_sub_epi16(mTwoBelow, mCur);
            if constexpr (Masked) {
                h = _mm256_and_si256(h, mask16);
                w = _mm256_and_si256(w, mask16);
            }
            sums.acc32 = _mm256_add_epi32(
                sums.acc32, _mm256_add_epi32(_mm256_madd_epi16(h, h), _mm256_madd_epi16(w, w)));
            mCur = mNext, mNext = mTwoBelow;
        }
        sums.endRow();
    }
    sums.addTo(acc64, nullptr);
    siOut = _mm_add_epi64(siOut, si);
}

// LAPM and Brenner over columns x … x+31 in the even/odd layout of rowTerms32: the centre row
// values of pixels x + 2i and x + 2i + 1 are the low and high bytes of the 16-bit lanes of one
// plain load, so the rows kept for the vertical terms cost two operations each. Widened like
// localStrip16.
template <LocalOp Op>
void localStrip32(const Luma8& img, int x, int y0, int y1, __m256i& acc64, __m256i& siOut) {
    __m256i si = _mm256_setzero_si256();
    const __m256i zero = _mm256_setzero_si256(), ones = _mm256_set1_epi16(1);
    const __m256i lowByte = _mm256_set1_epi16(0x00ff);
    const auto evenOf = [&](__m256i v) { return _mm256_and_si256(v, lowByte); };
    const auto oddOf = [](__m256i v) { return _mm256_srli_epi16(v, 8); };
    // Raw centre bytes of row y (for Σ I) and the even/odd values of rows y − 1 (LAPM), y, y + 1.
    __m256i cCur = load(img.row(y0) + x);
    __m256i ePrev = zero, oPrev = zero, eNext = zero, oNext = zero;
    if constexpr (Op == LocalOp::Lapm) {
        const __m256i p = load(img.row(y0 - 1) + x);
        ePrev = evenOf(p), oPrev = oddOf(p);
    } else {
        const __m256i n = load(img.row(y0 + 1) + x);
        eNext = evenOf(n), oNext = oddOf(n);
    }
    __m256i eCur = evenOf(cCur), oCur = oddOf(cCur);
    StripSums<false> sums;
    for (int y = y0; y < y1; ++y) {
        si = _mm256_add_epi64(si, _mm256_sad_epu8(cCur, zero));
        const uint8_t* p = img.row(y) + x;
        if constexpr (Op == LocalOp::Lapm) {
            const __m256i cBelow = load(img.row(y + 1) + x);
            const __m256i eBelow = evenOf(cBelow), oBelow = oddOf(cBelow);
            // Left of an even pixel: low byte at x − 1; right of an odd one: high byte at x + 1.
            const __m256i leftE = evenOf(load(p - 1)), rightO = oddOf(load(p + 1));
            const __m256i e2 = _mm256_add_epi16(eCur, eCur), o2 = _mm256_add_epi16(oCur, oCur);
            const __m256i hE = _mm256_sub_epi16(e2, _mm256_add_epi16(leftE, oCur));
            const __m256i hO = _mm256_sub_epi16(o2, _mm256_add_epi16(eCur, rightO));
            const __m256i vE = _mm256_sub_epi16(e2, _mm256_add_epi16(ePrev, eBelow));
            const __m256i vO = _mm256_sub_epi16(o2, _mm256_add_epi16(oPrev, oBelow));
            const __m256i sum =
                _mm256_add_epi16(_mm256_add_epi16(_mm256_abs_epi16(hE), _mm256_abs_epi16(hO)),
                                 _mm256_add_epi16(_mm256_abs_epi16(vE), _mm256_abs_epi16(vO)));
            sums.acc32 = _mm256_add_epi32(sums.acc32, _mm256_madd_epi16(sum, ones));
            ePrev = eCur, oPrev = oCur, eCur = eBelow, oCur = oBelow, cCur = cBelow;
        } else {
            const __m256i cTwoBelow = load(img.row(y + 2) + x);
            const __m256i eTwo = evenOf(cTwoBelow), oTwo = oddOf(cTwoBelow);
            const __m256i right2 = load(p + 2);
            const __m256i hE = _mm256_sub_epi16(evenOf(right2), eCur);
            const __m256i hO = _mm256_sub_epi16(oddOf(right2), oCur);
            const __m256i vE = _mm256_sub_epi16(eTwo, eCur), vO = _mm256_sub_epi16(oTwo, oCur);
            sums.acc32 = _mm256_add_epi32(
                sums.acc32, _mm256_add_epi32(_mm256_madd_epi16(hE, hE), _mm256_madd_epi16(hO, hO)));
            sums.acc32 = _mm256_add_epi32(
                sums.acc32, _mm256_add_epi32(_mm256_madd_epi16(vE, vE), _mm256_madd_epi16(vO, vO)));
            cCur = load(img.row(y + 1) + x);
            eCur = eNext, oCur = oNext, eNext = eTwo, oNext = oTwo;
        }
        sums.endRow();
    }
    sums.addTo(acc64, nullptr);
    siOut = _mm256_add_epi64(siOut, si);
}

constexpr int kL1Bytes = 32 * 1024;

// Runs the strips of one operator over @p a (a.w ≥ 16) in bands of rows whose pixels fit in L1
// (32 KiB), so that the later strips of a band find them there (each band costs a row or two of
// extra terms per strip): 32-column strips where @p Strip32 is given, then 16-column ones, then
// one overlapping masked 16-column strip, so at most 15 columns per row are computed twice.
template <typename S32, typename S16>
void runStrips(const Rect& a, S32&& strip32, S16&& strip16) {
    const int end = a.x + a.w;
    const int band = std::max(32, kL1Bytes / 2 / (a.w + 2));
    for (int y0 = a.y; y0 < a.y + a.h; y0 += band) {
        const int y1 = std::min(a.y + a.h, y0 + band);
        int x = a.x;
        for (; x + 32 <= end && strip32(x, y0, y1); x += 32) {
        }
        for (; x + 16 <= end; x += 16)
            strip16(x, y0, y1, 0);
        if (x < end) strip16(end - 16, y0, y1, 16 - (end - x));
    }
}

int64_t total(__m256i v, __m128i v16) {
    alignas(16) int64_t s16[2];
    _mm_store_si128(reinterpret_cast<__m128i*>(s16), v16);
    return sum64(v) + s16[0] + s16[1];
}

template <bool Variance>
void tengStrips(const Luma8& img, const Rect& a, int64_t& sumI, int64_t& sumG, double& sumG2) {
    __m256i acc64 = _mm256_setzero_si256(), si = acc64;
    __m256d sqd = _mm256_setzero_pd();
    __m128i si16 = _mm_setzero_si128();
    runStrips(
        a,
        [&](int x, int y0, int y1) {
            tengStrip32<Variance>(img, x, y0, y1, acc64, sqd, si);
            return true;
        },
        [&](int x, int y0, int y1, int skip) {
            if (skip)
                tengStrip16<Variance, true>(img, x, y0, y1, skip, acc64, sqd, si16);
            else
                tengStrip16<Variance, false>(img, x, y0, y1, 0, acc64, sqd, si16);
        });
    sumI = total(si, si16);
    sumG = sum64(acc64);
    sumG2 = sumPd(sqd);
}

template <LocalOp Op>
void localStrips(const Luma8& img, const Rect& a, int64_t& sumI, int64_t& sumA) {
    __m256i acc64 = _mm256_setzero_si256(), si = acc64;
    __m128i si16 = _mm_setzero_si128();
    runStrips(
        a,
        [&](int x, int y0, int y1) {
            if constexpr (Op == LocalOp::Glvn) return false;  // no neighbours: nothing to share
            localStrip32<Op>(img, x, y0, y1, acc64, si);
            return true;
        },
        [&](int x, int y0, int y1, int skip) {
            if (skip)
                localStrip16<Op, true>(img, x, y0, y1, skip, acc64, si16);
            else
                localStrip16<Op, false>(img, x, y0, y1, 0, acc64, si16);
        });
    sumI = total(si, si16);
    sumA = sum64(acc64);
}

}  // namespace

bool simdSums(const Luma8& img, const Rect& a, FocusOperator op, OperatorSums& out) {
    if (a.w <= 0 || a.h <= 0) return false;
    int64_t sumI = 0, sumA = 0, sumA2 = 0;
    switch (op) {
        case FocusOperator::Lapv: {
            if (a.w < 32) return false;
            sums<lapvStep<false>, lapvStep<true>>(img, a, sumI, sumA2);
            // Σ L telescopes: per column (top-outside − last + below-last − first), likewise per
            // row.
            const int x0 = a.x, y0 = a.y, x1 = a.x + a.w, y1 = a.y + a.h;
            for (int x = x0; x < x1; ++x)
                sumA += int(img.at(x, y0 - 1)) - img.at(x, y1 - 1) + img.at(x, y1) - img.at(x, y0);
            for (int y = y0; y < y1; ++y)
                sumA += int(img.at(x0 - 1, y)) - img.at(x1 - 1, y) + img.at(x1, y) - img.at(x0, y);
            out = {static_cast<double>(a.w) * a.h, static_cast<double>(sumI),
                   static_cast<double>(sumA), static_cast<double>(sumA2)};
            return true;
        }
        case FocusOperator::Teng:
        case FocusOperator::Tenv: {
            if (a.w < 16) return false;
            double sumG2 = 0;
            if (op == FocusOperator::Teng)
                tengStrips<false>(img, a, sumI, sumA, sumG2);
            else
                tengStrips<true>(img, a, sumI, sumA, sumG2);
            // Unscaled Sobel is 8× the gradient: G is 64× too large, G² 4096×.
            out = {static_cast<double>(a.w) * a.h, static_cast<double>(sumI),
                   static_cast<double>(sumA) / 64.0, sumG2 / 4096.0};
            return true;
        }
        case FocusOperator::Lapm:
        case FocusOperator::Brenner:
        case FocusOperator::Glvn: {
            if (a.w < 16) return false;
            if (op == FocusOperator::Lapm) localStrips<LocalOp::Lapm>(img, a, sumI, sumA);
            if (op == FocusOperator::Brenner) localStrips<LocalOp::Brenner>(img, a, sumI, sumA);
            if (op == FocusOperator::Glvn) localStrips<LocalOp::Glvn>(img, a, sumI, sumA2);
            out = {static_cast<double>(a.w) * a.h, static_cast<double>(sumI),
                   static_cast<double>(sumA), static_cast<double>(sumA2)};
            return true;
        }
        case FocusOperator::Dctr:
            break;
    }
    return false;
}

int64_t simdImmerkaerSum(const Luma8& img, const Rect& a, int rowStep, int64_t* atEnds) {
    if (a.w < 32) return -1;
    // The centre pixels at the ends of the range, counted from the loads the kernel makes anyway.
    const __m256i lowEnd = _mm256_set1_epi8(static_cast<char>(kNoiseLowEnd));
    const __m256i highEnd = _mm256_set1_epi8(static_cast<char>(kNoiseHighEnd));
    const __m256i oneByte = _mm256_set1_epi8(1), zero = _mm256_setzero_si256();
    __m256i ends = zero;
    // M = [1 −2 1]ᵀ[1 −2 1]: per-row terms q = l − 2m + r, then q(y−1) − 2q(y) + q(y+1), in the
    // even/odd layout of rowTerms32 (one multiply-add forms l − 2m).
    const __m256i lowByte = _mm256_set1_epi16(0x00ff), ones = _mm256_set1_epi16(1);
    const __m256i w1m2 = _mm256_set1_epi16(static_cast<int16_t>(0xfe01));  // bytes 1, −2
    const auto q = [&](const uint8_t* p, __m256i& e, __m256i& o) {
        const __m256i l = load(p - 1), c = load(p), r = load(p + 1);
        e = _mm256_add_epi16(_mm256_maddubs_epi16(l, w1m2), _mm256_and_si256(r, lowByte));
        o = _mm256_add_epi16(_mm256_maddubs_epi16(c, w1m2), _mm256_srli_epi16(r, 8));
    };
    const int end = a.x + a.w, full = a.w / 32 * 32;
    const __m256i mask = tailMask(32 - (a.w - full));
    const __m256i maskE = _mm256_srai_epi16(_mm256_slli_epi16(mask, 8), 8);
    const __m256i maskO = _mm256_srai_epi16(mask, 8);
    __m256i acc64 = _mm256_setzero_si256();
    for (int y = a.y; y < a.y + a.h; y += rowStep) {
        const uint8_t *u = img.row(y - 1), *c = img.row(y), *d = img.row(y + 1);
        // A lane gains at most 2·16·255 per window: a row of any width fits in i32.
        __m256i acc32 = _mm256_setzero_si256();
        const auto window = [&](int x, bool masked) {
            __m256i ue, uo, ce, co, de, dO;
            q(u + x, ue, uo);
            q(c + x, ce, co);
            q(d + x, de, dO);
            __m256i ne = _mm256_abs_epi16(
                _mm256_sub_epi16(_mm256_add_epi16(ue, de), _mm256_add_epi16(ce, ce)));
            __m256i no = _mm256_abs_epi16(
                _mm256_sub_epi16(_mm256_add_epi16(uo, dO), _mm256_add_epi16(co, co)));
            const __m256i v = load(c + x);
            __m256i atEnd = _mm256_or_si256(_mm256_cmpeq_epi8(_mm256_min_epu8(v, lowEnd), v),
                                            _mm256_cmpeq_epi8(_mm256_max_epu8(v, highEnd), v));
            if (masked) {
                ne = _mm256_and_si256(ne, maskE);
                no = _mm256_and_si256(no, maskO);
                atEnd = _mm256_and_si256(atEnd, mask);
            }
            acc32 = _mm256_add_epi32(acc32, _mm256_madd_epi16(_mm256_add_epi16(ne, no), ones));
            ends = _mm256_add_epi64(ends, _mm256_sad_epu8(_mm256_and_si256(atEnd, oneByte), zero));
        };
        for (int x = a.x; x < a.x + full; x += 32)
            window(x, false);
        if (full < a.w) window(end - 32, true);
        acc64 = widenAdd(acc64, acc32);
    }
    if (atEnds) *atEnds = sum64(ends);
    return sum64(acc64);
}

LevelSums levelSumsAvx2(const Luma8& img, const Rect& region, int step, int topFrom) {
    if (region.w < 32 || step < 1 || step > 2) return levelSumsGeneric(img, region, step, topFrom);
    // Bytes that are samples: all of them, or every second one from the window's first byte.
    const __m256i evenBytes = _mm256_set1_epi16(0x00ff);
    const __m256i sampled = step == 1 ? _mm256_set1_epi8(-1) : evenBytes;
    // The last window ends at the region's end; its first sample sits where the parity of the
    // bytes it backs over says, and the bytes already read are masked off.
    const int full = region.w / 32 * 32;
    const int back = region.w - full;  // 0..31 bytes left after the whole windows
    __m256i tail = tailMask(32 - back);
    if (step == 2) {
        const __m256i parity = (region.w % 2 == 0) ? evenBytes : _mm256_slli_epi16(evenBytes, 8);
        tail = _mm256_and_si256(tail, parity);
    }
    const __m256i ones = _mm256_set1_epi8(1), zero = _mm256_setzero_si256();
    const __m256i floor = _mm256_set1_epi8(static_cast<char>(std::clamp(topFrom, 0, 255)));
    const bool noTop = topFrom > 255;
    __m256i sum = zero, top = zero;
    const auto window = [&](const uint8_t* p, __m256i keep) {
        const __m256i v = _mm256_and_si256(load(p), keep);
        sum = _mm256_add_epi64(sum, _mm256_sad_epu8(v, zero));
        // v ≥ floor where max(v, floor) = v; a masked-off byte (0) counts only for floor 0.
        const __m256i atTop = _mm256_and_si256(_mm256_cmpeq_epi8(_mm256_max_epu8(v, floor), v),
                                               _mm256_and_si256(keep, ones));
        top = _mm256_add_epi64(top, _mm256_sad_epu8(atTop, zero));
    };
    for (int y = region.y; y < region.y + region.h; y += step) {
        const uint8_t* row = img.row(y) + region.x;
        for (int x = 0; x < full; x += 32)
            window(row + x, sampled);
        if (back > 0) window(row + region.w - 32, tail);
    }
    LevelSums out;
    out.sum = sum64(sum);
    out.top = noTop ? 0 : sum64(top);
    return out;
}

}  // namespace infocus::detail
