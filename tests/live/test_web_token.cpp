// SPDX-License-Identifier: MIT
// The web view's token check and the digests behind it: SHA-256 and base64 against their
// standards' test vectors, the comparison's answers, and its time where two tokens differ at the
// first byte against the last (measured and printed, not asserted).
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>

#include "src/live/web/web_control.h"
#include "src/live/web/web_encode.h"

using infocus::web::base64;
using infocus::web::sameSecret;
using infocus::web::sha256;

namespace {

std::string hex(const std::array<uint8_t, 32>& d) {
    std::string out;
    char two[3];
    for (uint8_t b : d) {
        std::snprintf(two, sizeof two, "%02x", b);
        out += two;
    }
    return out;
}

}  // namespace

TEST_CASE("sha256 matches the FIPS 180-4 examples") {
    CHECK(hex(sha256("")) == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    CHECK(hex(sha256("abc")) == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    // 56 bytes: the padding needs a second block.
    CHECK(hex(sha256("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq")) ==
          "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    CHECK(hex(sha256(std::string(1000000, 'a'))) ==
          "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST_CASE("base64 matches the RFC 4648 examples") {
    CHECK(base64("").empty());
    CHECK(base64("f") == "Zg==");
    CHECK(base64("fo") == "Zm8=");
    CHECK(base64("foo") == "Zm9v");
    CHECK(base64("foob") == "Zm9vYg==");
    CHECK(base64("fooba") == "Zm9vYmE=");
    CHECK(base64("foobar") == "Zm9vYmFy");
    CHECK(base64(std::string("\xff\xfe\x00", 3)) == "//4A");
}

TEST_CASE("sameSecret tells equal tokens from any other") {
    const std::string token = "0123456789abcdef0123456789abcdef";
    CHECK(sameSecret(token, token));
    CHECK(sameSecret("", ""));
    CHECK_FALSE(sameSecret("", token));
    CHECK_FALSE(sameSecret(token.substr(0, 31), token));
    CHECK_FALSE(sameSecret(token + "0", token));
    for (size_t i : {size_t{0}, size_t{15}, size_t{31}}) {
        std::string other = token;
        other[i] ^= 1;
        CHECK_FALSE(sameSecret(other, token));
    }
    // A string that shares the token's prefix but embeds a NUL is another string.
    CHECK_FALSE(sameSecret(std::string("0123456789abcdef\0", 17), token));
}

TEST_CASE("sameSecret takes as long wherever two tokens differ") {
    const std::string token = "0123456789abcdef0123456789abcdef";
    std::string first = token, last = token;
    first[0] ^= 1;
    last[31] ^= 1;
    using Clock = std::chrono::steady_clock;
    // Each timed alternately so that the machine's load falls on both alike.
    double tFirst = 1e9, tLast = 1e9, tSame = 1e9;
    bool sink = false;
    for (int round = 0; round < 20; ++round) {
        for (int which = 0; which < 3; ++which) {
            const std::string& given = which == 0 ? first : which == 1 ? last : token;
            const auto t0 = Clock::now();
            for (int i = 0; i < 2000; ++i)
                sink ^= sameSecret(given, token);
            const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
            double& best = which == 0 ? tFirst : which == 1 ? tLast : tSame;
            best = std::min(best, ns / 2000);
        }
    }
    std::printf(
        "sameSecret, best of 20 x 2000: differ at byte 0 %.1f ns, at byte 31 %.1f ns, equal "
        "%.1f ns (%d)\n",
        tFirst, tLast, tSame, static_cast<int>(sink));
    SUCCEED("measured, not asserted");
}
