// SPDX-License-Identifier: MIT
// The sim's lens takes time and its frames arrive late: after set(), the next `delay` frames
// still show the old position (in the lens field and in the pixels); a frame before
// framesToSettle(from, to) discarded ones is not yet at rest, the one after is, and stays. The
// moving plane is where its formula puts it at known frame times: its frames equal those of a
// still plane at that distance.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>

#include "infocus/sim.h"
#include "infocus/source.h"
#include "replay/replay_sources.h"

using namespace infocus;

namespace {

std::unique_ptr<FrameSource> open(const std::string& text) {
    auto spec = parseSourceSpec(text);
    REQUIRE(spec.ok());
    auto src = replay::openSimSource(*spec);
    REQUIRE(src.ok());
    REQUIRE((*src)->start().ok());
    return std::move(*src);
}

bool samePixels(const Frame& a, const Frame& b) {
    return a.planes[0].size == b.planes[0].size &&
           std::memcmp(a.planes[0].data, b.planes[0].data, a.planes[0].size) == 0;
}

const std::string kScene =
    "sim:scene=plane,distance=0.5m,size=160x90,pace=fast,focal=25mm,fnumber=1.4,focus=0.5m";

}  // namespace

TEST_CASE("sim: after set(), the next delay frames show the old position") {
    // Defaults: delay 2 frames, travel 20 ms over 0–10 dpt, settle 10 ms; at 30 fps every move
    // ends within a frame.
    auto src = open(kScene);
    FocusControl* focus = src->focusControl();
    REQUIRE(focus);
    auto f0 = src->next();
    REQUIRE(f0.ok());
    REQUIRE(f0->lens->value == 2.0);
    REQUIRE(focus->set(5.0).ok());
    CHECK(focus->get()->value == 5.0);  // the position asked for
    // 2 frames in flight: the same pixels and position as before the move.
    for (int i = 0; i < 2; ++i) {
        auto f = src->next();
        REQUIRE(f.ok());
        CHECK(f->lens->value == 2.0);
        CHECK(samePixels(*f, *f0));
    }
    // 20 ms × 3/10 + 10 ms = 16 ms < one frame (33 ms): the next frame is at rest.
    CHECK(focus->framesToSettle(2.0, 5.0) == 2);
    auto f3 = src->next();
    CHECK(f3->lens->value == 5.0);
    CHECK_FALSE(samePixels(*f3, *f0));
    auto still = open(kScene.substr(0, kScene.size() - 4) + "0.2m");
    CHECK(samePixels(*f3, *still->next()));
}

TEST_CASE("sim: framesToSettle is exactly where frames come to rest") {
    struct Case {
        const char* options;
        int delay;
        double from, to;
    };
    // Fast frames make travel and settling span several of them.
    const Case cases[] = {
        {"fps=200", 2, 2.0, 5.0},                                   // 1.2 travel + 2 settle frames
        {"fps=200", 2, 2.0, 2.25},                                  // a short move: settling alone
        {"fps=200,delay=0", 0, 2.0, 10.0},                          // delivered at once
        {"fps=1000,delay=3,travel=50ms,settle=12ms", 3, 2.0, 0.0},  // 10 + 12 frames
        {"fps=30,delay=1,travel=500ms,settle=50ms", 1, 2.0, 9.0},   // a webcam's motor
        {"fps=30,travel=0ms,settle=0ms", 2, 2.0, 7.0},  // an ideal lens: the delay alone
    };
    for (const Case& c : cases) {
        INFO(c.options << ": " << c.from << " → " << c.to << " dpt");
        auto src = open(kScene + "," + c.options);
        FocusControl* focus = src->focusControl();
        REQUIRE(focus->set(c.from).ok());
        // Let the first move end (the settle frames of the longest move, then some).
        const int longest = focus->settleFrames();
        CHECK(longest >= focus->framesToSettle(c.from, c.to));
        Frame before;
        for (int i = 0; i <= longest + 1; ++i)
            before = *src->next();
        REQUIRE(before.lens->value == c.from);
        const int discard = focus->framesToSettle(c.from, c.to);
        REQUIRE(focus->set(c.to).ok());
        for (int i = 0; i < discard; ++i) {
            auto f = src->next();
            REQUIRE(f.ok());
            // Not yet at rest at the target...
            CHECK(f->lens->value != c.to);
            // ...and the frames in flight still at the old position.
            if (i < c.delay) {
                CHECK(f->lens->value == c.from);
                CHECK(samePixels(*f, before));
            }
        }
        // The first frame after them is at rest, and the lens stays.
        for (int i = 0; i < 5; ++i) {
            auto f = src->next();
            CHECK(f->lens->value == c.to);
        }
    }
}

TEST_CASE("sim: the moving plane is at its distance at known frame times") {
    // 1 m → 0.5 m over 4 s at 10 fps: frame k at k/10 s, distance 1 − 0.125·t m until 4 s.
    const std::string base = "sim:scene=plane,focus=0.6m,size=160x90,pace=fast,fps=10";
    auto config = parseSimOptions({{"distance", "1m"}, {"move", "0.5m:4s"}});
    REQUIRE(config.ok());
    CHECK(simDistanceAtM(*config, 0.0) == Approx(1.0).epsilon(1e-12));
    CHECK(simDistanceAtM(*config, 2.0) == Approx(0.75).epsilon(1e-12));
    CHECK(simDistanceAtM(*config, 3.2) == Approx(0.6).epsilon(1e-12));
    CHECK(simDistanceAtM(*config, 4.0) == Approx(0.5).epsilon(1e-12));
    CHECK(simDistanceAtM(*config, 60.0) == Approx(0.5).epsilon(1e-12));

    auto moving = open(base + ",distance=1m,move=0.5m:4s");
    const std::map<int, const char*> still = {
        {0, "1m"}, {20, "0.75m"}, {32, "0.6m"}, {40, "0.5m"}, {55, "0.5m"}};
    for (int k = 0; k <= 55; ++k) {
        auto f = moving->next();
        REQUIRE(f.ok());
        REQUIRE(f->sequence == static_cast<uint64_t>(k));
        auto it = still.find(k);
        if (it == still.end()) continue;
        INFO("frame " << k << ", plane at " << it->second);
        auto s = open(base + ",distance=" + it->second);
        CHECK(samePixels(*f, *s->next()));
    }
    // The plane in focus (0.6 m at 3.2 s) is the sharpest: the truth's blur is 0 there.
    auto r = SimRenderer::create(*parseSimOptions(
        {{"distance", "1m"}, {"move", "0.5m:4s"}, {"size", "160x90"}, {"focus", "0.6m"}}));
    REQUIRE(r.ok());
    CHECK((*r)->regions(1 / 0.6, 3.2)[0].blurDiameterPx == Approx(0).margin(1e-9));
    CHECK((*r)->regions(1 / 0.6, 0.0)[0].depthM == Approx(1.0).epsilon(1e-6));

    // Steps have no single plane to move.
    auto bad = parseSourceSpec("sim:scene=steps,move=0.5m:4s");
    CHECK(replay::openSimSource(*bad).error().kind == ErrorKind::Usage);
    for (const char* v : {"0.5m", "0.5m:0s", "0.5:4s", "0.5m:4", "m:4s"}) {
        INFO(v);
        auto spec = parseSourceSpec(std::string("sim:move=") + v);
        CHECK(replay::openSimSource(*spec).error().kind == ErrorKind::Usage);
    }
}
