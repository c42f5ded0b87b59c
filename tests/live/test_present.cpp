// SPDX-License-Identifier: MIT
// What every face shows the same way: heat classes, cycles, distances and the key map.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "infocus/blur.h"
#include "src/live/present.h"

using namespace infocus;
using namespace infocus::present;

namespace {

// Records the controls a key sends.
class Recorder final : public LiveControls {
public:
    std::vector<std::string> calls;
    Status focusStep(int steps) override {
        calls.push_back("step " + std::to_string(steps));
        return {};
    }
    Status focusTo(double) override { return {}; }
    Status autofocus() override {
        calls.push_back("autofocus");
        return makeError(ErrorKind::Unsupported, "no lens motor");
    }
    Status setContinuousAutofocus(bool on) override {
        calls.push_back(on ? "continuous on" : "continuous off");
        return {};
    }
    void resetPeak() override { calls.push_back("reset"); }
    Status setScoreRoi(std::optional<Rect>) override { return {}; }
    Status setMagnifier(std::optional<std::array<int, 3>>) override { return {}; }
    Status setGrid(int cols, int rows) override {
        calls.push_back("grid " + std::to_string(cols) + "x" + std::to_string(rows));
        return {};
    }
    Status setPeaking(PeakingMode m) override {
        calls.push_back("peaking " + std::string(peakingModeName(m)));
        return {};
    }
};

}  // namespace

TEST_CASE("distances read with 2-3 significant digits, mm below a metre") {
    CHECK(distanceText(0.5123) == "512 mm");
    CHECK(distanceText(0.999) == "999 mm");
    CHECK(distanceText(1.0) == "1.00 m");
    CHECK(distanceText(1.0449) == "1.04 m");
    CHECK(distanceText(12.46) == "12.5 m");
    CHECK(distanceText(230.4) == "230 m");
    CHECK(distanceText(INFINITY) == "infinity");
    CHECK(distanceText(std::optional<double>()) == "—");
}

TEST_CASE("heat classes are multiples of the circle of confusion, from a confident reading") {
    LiveRegion r;
    r.confidence = 0.9;
    CHECK(heatOf(r, 2.0) == Heat::Unknown);  // no reading
    r.blurPx = 2.0;
    CHECK(heatOf(r, 2.0) == Heat::InCoc);
    r.blurPx = 4.0;
    CHECK(heatOf(r, 2.0) == Heat::Near);
    r.blurPx = 8.0;
    CHECK(heatOf(r, 2.0) == Heat::Far);
    r.blurPx = 8.1;
    CHECK(heatOf(r, 2.0) == Heat::Beyond);
    CHECK(heatOf(r, 0.0) == Heat::Unknown);  // no circle of confusion to compare with
    // The engine's own cut: a reading just under it is not shown, one at it is.
    r.confidence = kLowBlurConfidence - 1e-9;
    CHECK(heatOf(r, 2.0) == Heat::Unknown);
    CHECK_FALSE(showsBlur(r));
    r.confidence = kLowBlurConfidence;
    CHECK(heatOf(r, 2.0) == Heat::Beyond);
    CHECK(heatName(Heat::InCoc) == "in_coc");
    CHECK(heatName(Heat::Unknown) == "unknown");
}

TEST_CASE("g cycles 16x9, 8x6, 4x3; p cycles off, coc, percentile") {
    CHECK(nextGrid(16, 9) == std::pair{8, 6});
    CHECK(nextGrid(8, 6) == std::pair{4, 3});
    CHECK(nextGrid(4, 3) == std::pair{16, 9});
    CHECK(nextGrid(12, 5) == std::pair{16, 9});  // a grid from --grid rejoins the cycle
    CHECK(nextPeaking(PeakingMode::Off) == PeakingMode::Coc);
    CHECK(nextPeaking(PeakingMode::Coc) == PeakingMode::Percentile);
    CHECK(nextPeaking(PeakingMode::Percentile) == PeakingMode::Off);
}

TEST_CASE("keys map to the same controls in every face") {
    Recorder r;
    LiveState s;
    s.cols = 8;
    s.rows = 6;
    s.peaking = PeakingMode::Coc;
    CHECK(actionForKey(Key::Left) == Action::FocusDown);
    CHECK(actionForKey(Key::ShiftRight) == Action::FocusUpFast);
    CHECK(actionForKey(Key::Escape) == Action::Quit);
    CHECK(actionForKey(Key::Char, 'q') == Action::Quit);
    CHECK(actionForKey(Key::Char, 'x') == Action::None);
    for (char c : {'a', 'r', 'g', 'p'})
        (void)apply(actionForKey(Key::Char, c), r, &s);
    CHECK(apply(actionForKey(Key::ShiftLeft), r, &s));
    CHECK(apply(actionForKey(Key::Right), r, &s));
    // Without a state the cycles have nothing to cycle from: nothing is sent.
    CHECK(apply(Action::NextGrid, r, nullptr));
    CHECK(r.calls == std::vector<std::string>{"autofocus", "reset", "grid 4x3",
                                              "peaking percentile", "step -10", "step 1"});
    // A control's refusal comes back to the face to show.
    CHECK_FALSE(apply(Action::Autofocus, r, &s));
}

TEST_CASE("the key help lists every binding once") {
    const std::string help = keyHelp();
    for (const KeyBinding& b : keyBindings())
        CHECK(help.find(std::string(b.keys)) != std::string::npos);
    CHECK(std::count(help.begin(), help.end(), '\n') == static_cast<long>(keyBindings().size()));
}
