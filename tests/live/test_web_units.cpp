// SPDX-License-Identifier: MIT
// The web face's parts on their own: the listen address, the /control commands against a
// recording set of controls, and the frame hub over a scripted view.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "src/live/web/web.h"
#include "src/live/web/web_control.h"
#include "src/live/web/web_hub.h"

using namespace infocus;

namespace {

// Records the controls a command sends; refuses a grid over 64 columns as the pipeline would.
class Recorder final : public LiveControls {
public:
    std::vector<std::string> calls;
    Status focusStep(int steps) override {
        calls.push_back("step " + std::to_string(steps));
        return {};
    }
    Status focusTo(double v) override {
        calls.push_back("to " + std::to_string(v));
        return {};
    }
    Status autofocus() override {
        calls.push_back("autofocus");
        return makeError(ErrorKind::Unsupported, "autofocus is already running");
    }
    Status setContinuousAutofocus(bool on) override {
        calls.push_back(on ? "continuous on" : "continuous off");
        return {};
    }
    void resetPeak() override { calls.push_back("reset"); }
    Status setScoreRoi(std::optional<Rect> roi) override {
        calls.push_back(roi ? "roi " + std::to_string(roi->w) : std::string("roi none"));
        return {};
    }
    Status setMagnifier(std::optional<std::array<int, 3>> m) override {
        if (m && (*m)[2] != 1 && (*m)[2] != 2)
            return makeError(ErrorKind::Usage, "magnifier zoom must be 1 or 2");
        calls.push_back("magnifier");
        return {};
    }
    Status setGrid(int cols, int rows) override {
        if (cols > 64) return makeError(ErrorKind::Usage, "at most 64 columns");
        calls.push_back("grid " + std::to_string(cols) + "x" + std::to_string(rows));
        return {};
    }
    Status setPeaking(PeakingMode m) override {
        calls.push_back("peaking " + std::string(peakingModeName(m)));
        return {};
    }
};

// A view whose states are published by the test.
class ScriptedView final : public LiveView {
public:
    void publish(uint64_t frame) {
        auto s = std::make_shared<LiveState>();
        s->frame = frame;
        {
            std::lock_guard lock(m_);
            state_ = s;
        }
    }
    std::shared_ptr<const LiveState> state() const override {
        std::lock_guard lock(m_);
        return state_;
    }
    std::shared_ptr<const LiveState> waitForState(std::optional<uint64_t> after,
                                                  std::chrono::milliseconds timeout) override {
        const auto until = std::chrono::steady_clock::now() + timeout;
        while (std::chrono::steady_clock::now() < until) {
            if (auto s = state(); s && (!after || s->frame > *after)) return s;
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        return nullptr;
    }
    bool ended() const override { return false; }
    Status endStatus() const override { return {}; }
    SourceInfo info() const override { return {}; }
    Status focusStep(int) override { return {}; }
    Status focusTo(double) override { return {}; }
    Status autofocus() override { return {}; }
    Status setContinuousAutofocus(bool) override { return {}; }
    void resetPeak() override {}
    Status setScoreRoi(std::optional<Rect>) override { return {}; }
    Status setMagnifier(std::optional<std::array<int, 3>>) override { return {}; }
    Status setGrid(int, int) override { return {}; }
    Status setPeaking(PeakingMode) override { return {}; }

private:
    mutable std::mutex m_;
    std::shared_ptr<const LiveState> state_;
};

}  // namespace

TEST_CASE("listen addresses: IPv4, localhost, bracketed IPv6, loopback or not") {
    auto a = parseListenAddress("127.0.0.1:8080");
    REQUIRE(a);
    CHECK(a->host == "127.0.0.1");
    CHECK(a->port == 8080);
    CHECK(a->loopback);
    a = parseListenAddress("0.0.0.0:0");
    REQUIRE(a);
    CHECK(a->port == 0);
    CHECK_FALSE(a->loopback);
    a = parseListenAddress("localhost:9000");
    REQUIRE(a);
    CHECK(a->host == "127.0.0.1");
    CHECK(a->loopback);
    a = parseListenAddress("[::1]:8080");
    REQUIRE(a);
    CHECK(a->host == "::1");
    CHECK(a->loopback);
    a = parseListenAddress("[::]:8080");
    REQUIRE(a);
    CHECK_FALSE(a->loopback);
    for (const char* bad : {"127.0.0.1", "127.0.0.1:", "127.0.0.1:65536", "127.0.0.1:-1",
                            "127.0.0.1:80a", "example.com:80", "[::1:80", "[zz]:80", ":80"}) {
        INFO(bad);
        const auto r = parseListenAddress(bad);
        REQUIRE_FALSE(r);
        CHECK(r.error().kind == ErrorKind::Usage);
        CHECK(r.error().message.find("ADDR:PORT") != std::string::npos);
    }
}

TEST_CASE("control commands reach the controls, or say what is wrong with them") {
    Recorder c;
    const auto run = [&](const std::string& body, bool lens = true) {
        return web::runControl(body, c, lens);
    };
    CHECK(run(R"({"focus_step": -10})").httpStatus == 200);
    CHECK(run(R"({"focus": 2.5})").httpStatus == 200);
    CHECK(run(R"({"reset_peak": true})").httpStatus == 200);
    CHECK(run(R"({"roi": [10, 20, 30, 40]})").httpStatus == 200);
    CHECK(run(R"({"roi": null})").httpStatus == 200);
    CHECK(run(R"({"grid": [8, 6]})").httpStatus == 200);
    CHECK(run(R"({"peaking": "coc"})").httpStatus == 200);
    CHECK(run(R"({"magnifier": [5, 5, 2]})").httpStatus == 200);
    CHECK(c.calls == std::vector<std::string>{"step -10", "to 2.500000", "reset", "roi 30",
                                              "roi none", "grid 8x6", "peaking coc", "magnifier"});

    // A refusal keeps its kind: the caller's value 400, a source that cannot 409.
    CHECK(run(R"({"grid": [100, 6]})").httpStatus == 400);
    CHECK(run(R"({"magnifier": [5, 5, 3]})").httpStatus == 400);
    CHECK(run(R"({"autofocus": true})").httpStatus == 409);
    CHECK(run(R"({"focus_step": 1})", false).httpStatus == 409);
    CHECK(run(R"({"autofocus": true})", false).httpStatus == 409);
    CHECK(run(R"({"autofocus": "continuous"})", false).httpStatus == 409);

    // Continuous focus switches on and off by name.
    c.calls.clear();
    CHECK(run(R"({"autofocus": "continuous"})").httpStatus == 200);
    CHECK(run(R"({"autofocus": "off"})").httpStatus == 200);
    CHECK(c.calls == std::vector<std::string>{"continuous on", "continuous off"});

    // Malformed bodies never reach the controls.
    c.calls.clear();
    for (const char* bad :
         {"", "not json", "[]", "{}", R"({"focus_step": 1, "focus": 2})", R"({"focus_step": 1.5})",
          R"({"focus_step": 99999999999})", R"({"focus": "near"})", R"({"roi": [1, 2, 3]})",
          R"({"grid": "16x9"})", R"({"peaking": "on"})", R"({"reset_peak": 1})",
          R"({"autofocus": false})", R"({"autofocus": "sometimes"})", R"({"launch": true})"}) {
        INFO(bad);
        const web::ControlReply r = run(bad);
        CHECK(r.httpStatus == 400);
        const auto j = nlohmann::json::parse(r.body, nullptr, false);
        REQUIRE(j.is_object());
        CHECK(j.contains("error"));
    }
    CHECK(c.calls.empty());
}

TEST_CASE("the frame hub hands each client the newest state and stops at once") {
    ScriptedView view;
    web::FrameHub hub(view, 80);
    view.publish(1);
    auto s = hub.waitNewer(std::nullopt, std::nullopt, false, std::chrono::milliseconds(2000));
    REQUIRE(s);
    REQUIRE(s->state);
    CHECK(s->state->frame == 1);
    // Nothing newer: a client waits out its time-out rather than see the same state again.
    CHECK_FALSE(hub.waitNewer(1, std::nullopt, false, std::chrono::milliseconds(100)));
    // Two states published before the client looks: once the hub has followed the view, the
    // client sees only the newest (the hub keeps no queue).
    view.publish(2);
    view.publish(3);
    REQUIRE(hub.waitNewer(2, std::nullopt, false, std::chrono::milliseconds(2000)));
    s = hub.waitNewer(1, std::nullopt, false, std::chrono::milliseconds(2000));
    REQUIRE(s);
    CHECK(s->state->frame == 3);
    // stop() wakes a waiting client at once.
    const auto t0 = std::chrono::steady_clock::now();
    std::thread stopper([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        hub.stop();
    });
    CHECK_FALSE(hub.waitNewer(3, std::nullopt, false, std::chrono::milliseconds(5000)));
    stopper.join();
    CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::milliseconds(2000));
    CHECK(hub.stopping());
}
