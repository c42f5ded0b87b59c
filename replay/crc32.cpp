// SPDX-License-Identifier: MIT
// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320). Whole 64-byte blocks are folded with
// carry-less multiplication where the CPU has it (Gopal et al., "Fast CRC computation for
// generic polynomials using PCLMULQDQ", Intel 2009): a replayed recording checks every frame, and
// this runs at memory speed where zlib's tables do not. zlib takes the rest, and everything on a
// CPU without it.
#include <zlib.h>

#include <cstdint>

#include "replay/recording_format.h"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace infocus::replay {

namespace {

#if defined(__x86_64__)

// x^k mod P(x), bit-reflected, for the fold distances: 4 × 128 + 32 and 4 × 128 − 32 bits
// (four lanes), 128 + 32 and 128 − 32 (one lane), 64 (to 64 bits); then P(x) and
// ⌊x^64 / P(x)⌋ for the Barrett reduction to 32 bits.
constexpr uint64_t kFold4Lo = 0x154442bd4, kFold4Hi = 0x1c6e41596;
constexpr uint64_t kFold1Lo = 0x1751997d0, kFold1Hi = 0x0ccaa009e;
constexpr uint64_t kFold64 = 0x163cd6124;
constexpr uint64_t kPoly = 0x1db710641, kMu = 0x1f7011641;

// @p x folded forward over a distance whose constants are @p k (low lane: x's low half).
__attribute__((target("pclmul,sse4.1"))) inline __m128i fold(__m128i x, __m128i k) {
    return _mm_xor_si128(_mm_clmulepi64_si128(x, k, 0x00), _mm_clmulepi64_si128(x, k, 0x11));
}

// The CRC register (not inverted) after @p size bytes at @p p, from @p reg; size ≥ 64 and a
// multiple of 16.
__attribute__((target("pclmul,sse4.1"))) uint32_t foldBlocks(uint32_t reg, const uint8_t* p,
                                                             size_t size) {
    const auto load = [](const uint8_t* q) {
        return _mm_loadu_si128(reinterpret_cast<const __m128i*>(q));
    };
    __m128i lane[4] = {load(p), load(p + 16), load(p + 32), load(p + 48)};
    lane[0] = _mm_xor_si128(lane[0], _mm_cvtsi32_si128(static_cast<int>(reg)));
    p += 64, size -= 64;
    const __m128i k4 =
        _mm_set_epi64x(static_cast<long long>(kFold4Hi), static_cast<long long>(kFold4Lo));
    for (; size >= 64; p += 64, size -= 64)
        for (int i = 0; i < 4; ++i)
            lane[i] = _mm_xor_si128(fold(lane[i], k4), load(p + 16 * i));
    // The four lanes into one, then any 16-byte blocks left.
    const __m128i k1 =
        _mm_set_epi64x(static_cast<long long>(kFold1Hi), static_cast<long long>(kFold1Lo));
    __m128i x = lane[0];
    for (int i = 1; i < 4; ++i)
        x = _mm_xor_si128(fold(x, k1), lane[i]);
    for (; size >= 16; p += 16, size -= 16)
        x = _mm_xor_si128(fold(x, k1), load(p));
    // 128 bits to 64, 64 to 32 bits (still shifted), then Barrett's reduction.
    const __m128i low32 = _mm_setr_epi32(-1, 0, -1, 0);
    x = _mm_xor_si128(_mm_srli_si128(x, 8), _mm_clmulepi64_si128(x, k1, 0x10));
    const __m128i k64 = _mm_set_epi64x(0, static_cast<long long>(kFold64));
    x = _mm_xor_si128(_mm_srli_si128(x, 4),
                      _mm_clmulepi64_si128(_mm_and_si128(x, low32), k64, 0x00));
    const __m128i pm = _mm_set_epi64x(static_cast<long long>(kMu), static_cast<long long>(kPoly));
    __m128i t = _mm_clmulepi64_si128(_mm_and_si128(x, low32), pm, 0x10);
    t = _mm_clmulepi64_si128(_mm_and_si128(t, low32), pm, 0x00);
    return static_cast<uint32_t>(_mm_extract_epi32(_mm_xor_si128(x, t), 1));
}

bool haveClmul() {
    static const bool have = __builtin_cpu_supports("pclmul") && __builtin_cpu_supports("sse4.1");
    return have;
}

#endif

}  // namespace

uint32_t crc32(const void* data, size_t size, uint32_t crc) {
    const auto* p = static_cast<const uint8_t*>(data);
#if defined(__x86_64__)
    if (size >= 64 && haveClmul()) {
        const size_t blocks = size & ~size_t{15};
        crc = ~foldBlocks(~crc, p, blocks);
        p += blocks, size -= blocks;
    }
#endif
    return static_cast<uint32_t>(::crc32_z(crc, p, size));
}

}  // namespace infocus::replay
