// SPDX-License-Identifier: MIT
// Autofocus on real photographs: the Raspberry Pi camera's focus sweep (../shared/data,
// Z in mm from the names zNNN_Z±ZZZ.jpg) opened as a lens (`DIR,bracket=FILE.csv`). The sharpest
// position is found by measuring every frame of the sweep; autofocus, started at either end,
// must end within 5 mm of it. The contrast schedule's frames on the same starts are printed
// beside autofocus's. Skipped without the data.
#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>

#include "infocus/analysis.h"
#include "infocus/source.h"
#include "src/pipeline/live/autofocus.h"
#include "src/pipeline/live/autofocus_baseline.h"

using namespace infocus;
namespace fs = std::filesystem;

namespace {

const fs::path kSweep = fs::path(INFOCUS_DATA_DIR) / "focus-sweep-pi";

// The sweep's positions file, from the names; the frames by position.
std::map<double, fs::path> writePositions(const fs::path& csv) {
    std::map<double, fs::path> frames;
    const std::regex name(R"(z(\d{3})_Z([+-]\d{3})\.jpg)");
    std::vector<std::pair<int, double>> rows;
    for (const auto& e : fs::directory_iterator(kSweep)) {
        std::smatch m;
        const std::string f = e.path().filename().string();
        if (!std::regex_match(f, m, name)) continue;
        rows.emplace_back(std::stoi(m[1]), std::stod(m[2]));
        frames[std::stod(m[2])] = e.path();
    }
    std::sort(rows.begin(), rows.end());
    std::ofstream out(csv);
    out << "frame,position,unit\n";
    for (const auto& [i, z] : rows)
        out << i << "," << z << ",mm\n";
    return frames;
}

// The subject's sharpness (middle half) of one photograph, 0 where the analyser finds it too
// dark or clipped to measure (the sweep's last frames, on the target, hold only hot pixels).
double sharpnessOf(const fs::path& file) {
    auto src = openSource(file.string());
    REQUIRE(src);
    REQUIRE((*src)->start());
    auto frame = (*src)->next();
    REQUIRE(frame);
    AnalysisOptions o;
    o.measureBlur = false;
    o.rois = {Rect{frame->size.width / 4, frame->size.height / 4, frame->size.width / 2,
                   frame->size.height / 2}};
    auto analyzer = Analyzer::create(o);
    REQUIRE(analyzer);
    auto a = (*analyzer)->analyze(*frame, 0);
    REQUIRE(a);
    return a->frameSharpness;
}

std::unique_ptr<live_detail::SourceTap> openBracket(const fs::path& csv, double start) {
    char text[512];
    std::snprintf(text, sizeof text, "%s,bracket=%s,pace=fast,focus=%g", kSweep.c_str(),
                  csv.c_str(), start);
    auto src = openSource(text);
    REQUIRE(src);
    auto tap = std::make_unique<live_detail::SourceTap>(std::move(*src));
    REQUIRE(tap->start());
    return tap;
}

// The frames continuous autofocus reads and the moves it asks for, the frames ending after a
// given count.
class CountingTap final : public live_detail::FrameTap {
public:
    CountingTap(live_detail::SourceTap& inner, uint64_t frames) : inner_(inner), left_(frames) {}
    Result<Frame> next(uint64_t& seen) override {
        if (left_ == 0) return makeError(ErrorKind::EndOfStream, "the test's frames ended");
        --left_;
        return inner_.next(seen);
    }
    Result<LensPosition> lensPosition() override { return inner_.lensPosition(); }
    Status moveLens(double value, uint64_t& before) override {
        ++moves;
        return inner_.moveLens(value, before);
    }
    FocusRange range() const override { return inner_.range(); }
    int settleFrames() const override { return inner_.settleFrames(); }
    int framesToSettle(double from, double to) const override {
        return inner_.framesToSettle(from, to);
    }
    SourceInfo info() const override { return inner_.info(); }
    int moves = 0;

private:
    live_detail::SourceTap& inner_;
    uint64_t left_;
};

}  // namespace

TEST_CASE("continuous autofocus holds still on a textureless subject and says why") {
    // Twelve flat grey frames with a sensor's noise (uniform ±3 grey levels), a bracket at
    // 0–11 mm: no edge anywhere, yet a sharpness above 0.
    const fs::path dir = fs::temp_directory_path() / "infocus-test-af-flat";
    fs::remove_all(dir);
    fs::create_directories(dir / "frames");
    std::ofstream csv(dir / "positions.csv");
    csv << "frame,position,unit\n";
    uint32_t state = 12345;
    for (int i = 0; i < 12; ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "f%02d.pgm", i);
        std::ofstream pgm(dir / "frames" / name, std::ios::binary);
        pgm << "P5\n320 240\n255\n";
        for (int p = 0; p < 320 * 240; ++p) {
            state = state * 1664525u + 1013904223u;
            pgm.put(static_cast<char>(96 + static_cast<int>(state >> 29) - 3));
        }
        csv << i << "," << i << ",mm\n";
    }
    csv.close();
    char text[512];
    std::snprintf(text, sizeof text, "%s,bracket=%s,pace=fast,focus=5", (dir / "frames").c_str(),
                  (dir / "positions.csv").c_str());
    auto src = openSource(text);
    REQUIRE(src);
    live_detail::SourceTap inner(std::move(*src));
    REQUIRE(inner.start());
    CountingTap tap(inner, 90);  // three seconds at 30 fps
    std::vector<LiveAutofocus> reports;
    std::atomic<bool> stop{false};
    live_detail::runAutofocusContinuous(
        tap, {}, [&](const LiveAutofocus& a) { reports.push_back(a); }, stop);
    REQUIRE_FALSE(reports.empty());
    std::printf(
        "continuous autofocus on a flat, noisy subject: %d lens moves in 90 frames, %s: %s\n",
        tap.moves, std::string(liveAutofocusStateName(reports.back().state)).c_str(),
        reports.back().reason.c_str());
    CHECK(tap.moves == 0);
    CHECK(reports.back().state == LiveAutofocusState::Holding);
    CHECK(reports.back().reason.find("edges") != std::string::npos);
    fs::remove_all(dir);
}

TEST_CASE("autofocus on the Pi sweep as a lens ends at its sharpest frame") {
    if (!fs::exists(kSweep / "z070_Z-050.jpg")) {
        WARN("SKIP: no test data at " << kSweep);
        std::exit(77);
    }
    const fs::path csv = fs::temp_directory_path() / "infocus-test-af-pi.csv";
    const auto frames = writePositions(csv);
    REQUIRE(frames.size() == 131);
    // Every frame measured: the sharpest position.
    double bestZ = 0, best = -1;
    for (const auto& [z, file] : frames) {
        const double s = sharpnessOf(file);
        if (s > best) best = s, bestZ = z;
    }
    std::printf("the sweep's sharpest frame (all 131 measured): Z %+.0f mm\n", bestZ);

    for (const double start : {20.0, -100.0}) {
        auto tap = openBracket(csv, start);
        std::atomic<bool> stop{false};
        const LiveAutofocus af = live_detail::runAutofocusOnce(*tap, {}, {}, stop);
        auto at = tap->lensPosition();
        REQUIRE(at);
        auto base = openBracket(csv, start);
        const live_detail::ContrastRun run = live_detail::runContrastSchedule(*base, std::nullopt);
        std::printf(
            "from Z %+.0f mm: autofocus ends at Z %+.1f mm in %d frames (%s: %s); the contrast "
            "schedule at Z %+.1f mm in %d frames\n",
            start, at->value, af.frames, std::string(liveAutofocusStateName(af.state)).c_str(),
            af.reason.c_str(), run.position, run.frames);
        INFO("from " << start << ": " << af.reason);
        CHECK(af.state == LiveAutofocusState::Focused);
        CHECK(std::abs(at->value - bestZ) <= 5.0);
    }
    fs::remove(csv);
}
