// SPDX-License-Identifier: MIT
// A real focus sweep (Raspberry Pi camera v1 moved along Z over a printed grid, best focus near
// Z = −50 mm, the last frames black on the target): every frame analysed, dark ones included,
// and the sweep's own peak logic run over the recorded frames through a lens control that
// stands for the robot's Z axis.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "../common/test_data.h"
#include "infocus/analysis.h"
#include "infocus/source.h"
#include "infocus/sweep.h"

using namespace infocus;
namespace fs = std::filesystem;

namespace {

// Where the sharpest frame must lie: the recording's own finding (Z ≈ −50 mm) ± 10 mm.
constexpr double kBestZLo = -60, kBestZHi = -40;
// The frames that are black on the target.
constexpr double kBlackFromZ = -107;

// The sweep's frames by machine Z in mm, from the names zNNN_Z±ZZZ.jpg.
std::map<int, fs::path> framesByZ() {
    const fs::path dir = test::requireData("focus-sweep-pi");
    std::map<int, fs::path> out;
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        if (name.size() == 14 && name[0] == 'z' && name.substr(4, 2) == "_Z" &&
            e.path().extension() == ".jpg")
            out[std::stoi(name.substr(6, 4))] = e.path();
    }
    if (out.size() != 131)
        test::skipExecutable("focus-sweep-pi holds " + std::to_string(out.size()) +
                             " frames, not the 131 of Z = +20 … −110");
    return out;
}

AnalysisOptions grid4x4() {
    AnalysisOptions o;
    o.cols = 4;
    o.rows = 4;
    return o;
}

// The recorded sweep as a camera: the lens control moves along Z in mm, and each frame is the
// one recorded at the nearest Z.
class RecordedSweep final : public FrameSource {
public:
    explicit RecordedSweep(std::map<int, fs::path> frames) : frames_(std::move(frames)) {
        control_.lo = frames_.begin()->first;
        control_.hi = frames_.rbegin()->first;
    }
    SourceInfo info() const override {
        SourceInfo i;
        i.sourceString = "focus-sweep-pi";
        return i;
    }
    Status start() override { return {}; }
    Result<Frame> next() override {
        const int z = static_cast<int>(std::lround(control_.value));
        const auto it = frames_.find(z);
        if (it == frames_.end()) return makeError(ErrorKind::EndOfStream, "no frame at this Z");
        // The image source is kept until the next frame: the frame may borrow its buffer.
        auto s = openSource(it->second.string());
        if (!s) return s.error();
        image_ = std::move(*s);
        if (auto st = image_->start(); !st) return st.error();
        auto f = image_->next();
        if (f) f->lens = LensPosition{static_cast<double>(z), "mm", std::nullopt};
        return f;
    }
    void stop() override {}
    SourceStats stats() const override { return {}; }
    FocusControl* focusControl() override { return &control_; }

private:
    struct Control final : FocusControl {
        FocusRange range() const override { return {lo, hi, 1, lo, "mm"}; }
        Result<LensPosition> get() override { return LensPosition{value, "mm", std::nullopt}; }
        Status set(double v) override {
            value = std::round(v);
            return {};
        }
        int settleFrames() const override { return 0; }
        double lo = 0, hi = 0, value = 0;
    } control_;
    std::map<int, fs::path> frames_;
    std::unique_ptr<FrameSource> image_;
};

}  // namespace

TEST_CASE("every region of the Pi sweep is sharpest near Z = -50, black frames unmeasured",
          "[sweep][real]") {
    const auto frames = framesByZ();
    auto analyzer = Analyzer::create(grid4x4());
    REQUIRE(analyzer);
    std::vector<double> bestScore(16, -1), bestZ(16, 0);
    double bestFrame = -1, bestFrameZ = 0;
    int blackFrames = 0;
    for (const auto& [z, path] : frames) {
        auto src = openSource(path.string());
        REQUIRE(src);
        REQUIRE((*src)->start());
        auto frame = (*src)->next();
        REQUIRE(frame);
        auto a = (*analyzer)->analyze(*frame, 0);
        REQUIRE(a);
        REQUIRE(a->regions.size() == 16u);
        for (size_t r = 0; r < 16; ++r) {
            const RegionResult& reg = a->regions[r];
            if (reg.status == RegionStatus::Ok && reg.sharpness > bestScore[r])
                bestScore[r] = reg.sharpness, bestZ[r] = z;
        }
        if (hasMeasurableRegion(*a) && a->frameSharpness > bestFrame)
            bestFrame = a->frameSharpness, bestFrameZ = z;
        if (z > kBlackFromZ) continue;
        // Black on the target: no score, no blur, a reason in every region.
        ++blackFrames;
        INFO("Z = " << z);
        CHECK_FALSE(hasMeasurableRegion(*a));
        for (const RegionResult& reg : a->regions) {
            CHECK(reg.status == RegionStatus::Dark);
            CHECK_THAT(reg.statusReason, Catch::StartsWith("dark: "));
            CHECK_FALSE(reg.blurWidthPx);
        }
        CHECK_FALSE(a->noiseSigma);
        CHECK_FALSE(a->noiseReason.empty());
    }
    CHECK(blackFrames == 4);
    for (size_t r = 0; r < 16; ++r) {
        INFO("region " << r << " sharpest at Z = " << bestZ[r]);
        CHECK(bestZ[r] >= kBestZLo);
        CHECK(bestZ[r] <= kBestZHi);
    }
    INFO("whole frame sharpest at Z = " << bestFrameZ);
    CHECK(bestFrameZ >= kBestZLo);
    CHECK(bestFrameZ <= kBestZHi);
}

TEST_CASE("the sweep's peak logic over the recorded Pi sweep finds Z near -50", "[sweep][real]") {
    RecordedSweep camera(framesByZ());
    SweepOptions o;
    o.from = -110;
    o.to = 20;
    o.steps = 131;  // every recorded frame, 1 mm apart
    o.analysis = grid4x4();
    o.analysis.measureBlur = false;
    auto r = runSweep(camera, o);
    REQUIRE(r);
    REQUIRE(r->steps.size() >= 131u);  // and the refinement about the first pass's best
    REQUIRE(r->best);
    INFO("best Z " << r->best->position);
    CHECK(r->best->position >= kBestZLo);
    CHECK(r->best->position <= kBestZHi);
    CHECK_FALSE(r->best->atEnd);
    REQUIRE(r->regionBest.size() == 16u);
    for (size_t i = 0; i < 16; ++i) {
        REQUIRE(r->regionBest[i]);
        INFO("region " << i << " best Z " << r->regionBest[i]->position);
        CHECK(r->regionBest[i]->position >= kBestZLo);
        CHECK(r->regionBest[i]->position <= kBestZHi);
    }
}
