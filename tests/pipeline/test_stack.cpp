// SPDX-License-Identifier: MIT
// Focus stacks: recorded sweeps of the simulated camera against its true depths, the real stacks
// of ../shared/data for what a correct tool must show on them (a focus band moving across a
// tilted board, three heights of a switch, an all-in-focus composite as sharp as the sharpest
// frame everywhere), and the positions file's rules.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "infocus/luma.h"
#include "infocus/metrics.h"
#include "infocus/recording.h"
#include "infocus/sim.h"
#include "infocus/source.h"
#include "infocus/stack.h"
#include "src/pipeline/stack_internal.h"
#include "tests/common/scratch_dir.h"
#include "tests/common/test_data.h"

using namespace infocus;

namespace {

// Records one frame of the simulated camera @p text at each of @p dioptres into @p dir, as
// `infocus record` would of a camera whose lens is moved between frames.
void recordSweep(const std::string& text, const std::vector<double>& dioptres,
                 const std::string& dir) {
    auto src = openSource(text);
    REQUIRE(src);
    FrameSource& s = **src;
    FocusControl* control = s.focusControl();
    REQUIRE(control);
    auto writer = RecordingWriter::create(dir, makeRecordingHeader(s.info(), control));
    REQUIRE(writer);
    REQUIRE(s.start());
    for (double p : dioptres) {
        REQUIRE(control->set(p));
        // The lens shows a move some frames later (docs/recording.md): the settle frames pass.
        for (int i = 0; i < control->settleFrames(); ++i)
            REQUIRE(s.next());
        auto f = s.next();
        REQUIRE(f);
        REQUIRE(f->lens);
        REQUIRE(f->lens->dioptres);
        REQUIRE(*f->lens->dioptres == Approx(p).margin(1e-9));
        REQUIRE((*writer)->append(*f));
    }
    s.stop();
    REQUIRE((*writer)->close());
}

std::vector<double> evenly(double from, double to, int n) {
    std::vector<double> v;
    for (int i = 0; i < n; ++i)
        v.push_back(from + (to - from) * i / (n - 1));
    return v;
}

std::unique_ptr<SimRenderer> truthOf(const std::string& text) {
    auto spec = parseSourceSpec(text);
    REQUIRE(spec);
    auto cfg = parseSimOptions(spec->options);
    REQUIRE(cfg);
    auto r = SimRenderer::create(*cfg);
    REQUIRE(r);
    return std::move(*r);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

}  // namespace

TEST_CASE("a recorded sweep of the simulated camera: every region's peak at its true focus",
          "[stack][sim]") {
    // A 16 mm f/1.4 lens blurs 37 px a dioptre at 1280 px; steps of 0.05 dpt.
    const std::string lens = ",focal=16mm,fnumber=1.4,size=1280x720,pace=fast";
    // Dioptres, for both measures. The sharpness peaks are measured within 0.006 dpt; the blur
    // V's vertices within 0.0121 (steps) and 0.0130 (tilted: a region's blur rests on a few
    // edges, and a tilted region spans 0.03 dpt of depth).
    const double tolerance = 0.02, vTolerance = 0.02;
    test::ScratchDir tmp("infocus-stack-");
    StackOptions o;
    o.maps = false;

    SECTION("a plane tilted 30° about the image's x axis") {
        const std::string text = "sim:scene=tilted,tilt=30,distance=1m" + lens;
        recordSweep(text, evenly(0.5, 1.6, 23), tmp.file("rec"));
        o.cols = 4;
        o.rows = 4;
        auto r = analyzeStack(tmp.file("rec"), o);
        REQUIRE(r);
        CHECK(r->axisUnit == "dioptre");
        auto truth = truthOf(text);
        double worstPeak = 0, worstV = 0;
        for (const StackRegion& g : r->regions) {
            const double z = truth->depthAtM(g.rect.x + g.rect.w / 2, g.rect.y + g.rect.h / 2);
            INFO("region " << g.col << "," << g.row << ": true focus " << 1 / z << " dpt");
            REQUIRE(g.status == StackRegionStatus::Ok);
            REQUIRE(g.peakDioptres);
            CHECK(*g.peakDioptres == Approx(1 / z).margin(tolerance));
            CHECK(*g.inFocusDistance == Approx(1 / *g.peakDioptres));
            worstPeak = std::max(worstPeak, std::abs(*g.peakDioptres - 1 / z));
            CHECK(g.blurFit);
            if (!g.blurFit) continue;
            CHECK(g.blurFit->position == Approx(1 / z).margin(vTolerance));
            worstV = std::max(worstV, std::abs(g.blurFit->position - 1 / z));
        }
        std::printf("tilted: worst error %.4f dpt by sharpness, %.4f dpt by the blur V\n",
                    worstPeak, worstV);
    }
    SECTION("four planes at steps") {
        const std::string text = "sim:scene=steps,distances=0.8m:1m:1.25m:1.6m" + lens;
        recordSweep(text, evenly(0.4, 1.5, 23), tmp.file("rec"));
        o.cols = 16;
        o.rows = 2;
        auto r = analyzeStack(tmp.file("rec"), o);
        REQUIRE(r);
        const double truth[] = {1.25, 1.0, 0.8, 0.625};
        double worstPeak = 0, worstV = 0;
        for (const StackRegion& g : r->regions) {
            // The two columns in each band's middle: away from a depth step, where the sim's
            // gather blurs across it.
            if (g.col % 4 == 0 || g.col % 4 == 3) continue;
            INFO("column " << g.col << ", row " << g.row);
            REQUIRE(g.status == StackRegionStatus::Ok);
            REQUIRE(g.peakDioptres);
            CHECK(*g.peakDioptres == Approx(truth[g.col / 4]).margin(tolerance));
            worstPeak = std::max(worstPeak, std::abs(*g.peakDioptres - truth[g.col / 4]));
            CHECK(g.blurFit);
            if (!g.blurFit) continue;
            CHECK(g.blurFit->position == Approx(truth[g.col / 4]).margin(vTolerance));
            worstV = std::max(worstV, std::abs(g.blurFit->position - truth[g.col / 4]));
        }
        std::printf("steps: worst error %.4f dpt by sharpness, %.4f dpt by the blur V\n", worstPeak,
                    worstV);
    }
}

TEST_CASE("the blur V on a stage's axis: over the object's dioptres, with a floor", "[stack]") {
    // A stage moving the object from 130 to 0 mm from where it would reach the lens (Z = 20 to
    // -110, the pole at -126.25, one of those tried), each region in focus at its own Z: the
    // thin-lens blur K·|1/z - 1/u| with a 3 px floor in quadrature, and a deterministic
    // ±0.3 px scatter. Tolerances: the pole exactly, the vertex within 0.5 mm; a V straight on
    // the axis misses it by more (checked, so that the test can tell the two apart).
    StackResult r;
    r.axisUnit = "mm";
    for (int i = 0; i <= 130; ++i) {
        r.frames.push_back(StackFrame{static_cast<uint64_t>(i), "", {}, 0});
        r.axis.push_back(20.0 - i);
    }
    const double pole = -126.25, floorPx = 3, k = 2000;  // px·mm
    std::vector<stack_detail::BlurReadings> regions;
    for (double focus : {-40.0, -50.0, -60.0}) {
        stack_detail::BlurReadings g;
        for (size_t i = 0; i < r.axis.size(); ++i) {
            const double x = r.axis[i];
            const double b = std::hypot(k * std::abs(1 / (x - pole) - 1 / (focus - pole)), floorPx);
            if (b > 25) continue;  // as wider readings are left out
            g.x.push_back(x);
            g.b.push_back(b + 0.3 * (static_cast<int>(i * 7 % 5) - 2) / 2.0);
            g.w.push_back(0.5);
        }
        regions.push_back(g);
    }
    r.blurPole = stack_detail::chooseBlurPole(regions, r);
    REQUIRE(r.blurPole);
    CHECK(*r.blurPole == Approx(pole).margin(1e-9));
    for (size_t n = 0; n < regions.size(); ++n) {
        const double focus = -40.0 - 10.0 * n;
        INFO("in focus at Z = " << focus);
        auto v = stack_detail::fitRegionBlurV(regions[n], r);
        REQUIRE(v);
        CHECK(v->position == Approx(focus).margin(0.5));
        CHECK(v->floorPx == Approx(floorPx).margin(0.5));
        CHECK(
            r.blurModelPx(*v, focus + 20) ==
            Approx(std::hypot(k * std::abs(1 / (focus + 20 - pole) - 1 / (focus - pole)), floorPx))
                .epsilon(0.1));
        StackResult straight = r;
        straight.blurPole.reset();
        auto s = stack_detail::fitRegionBlurV(regions[n], straight);
        if (s) CHECK(std::abs(s->position - focus) > 1.0);
        std::printf("stage axis, in focus at %.0f mm: vertex %.2f mm over the pole, %s\n", focus,
                    v->position,
                    s ? ("straight V " + std::to_string(s->position)).c_str() : "no straight V");
    }
}

TEST_CASE("pcb: the focus band moves monotonically down the tilted board", "[stack][data]") {
    const auto dir = test::requireData("focus-stack/pcb");
    StackOptions o;
    auto r = analyzeStack((dir / "pcb_*.jpg").string(), o);
    REQUIRE(r);
    REQUIRE(r->frames.size() == 7u);
    // The board recedes up the image: each row's median peak frame, top to bottom, must fall
    // (or rise) steadily, by at least two frames over the image. Tolerance: a row may repeat
    // the previous row's median within 0.25 frame.
    std::vector<double> rowPeak;
    for (int row = 0; row < o.rows; ++row) {
        std::vector<double> v;
        for (const StackRegion& g : r->regions)
            if (g.row == row && g.peakFrame) v.push_back(*g.peakFrame);
        REQUIRE(v.size() >= 3u);
        rowPeak.push_back(median(v));
        std::printf("pcb row %d: median peak frame %.2f of %zu regions\n", row, rowPeak.back(),
                    v.size());
    }
    const double dir0 = rowPeak.back() > rowPeak.front() ? 1.0 : -1.0;
    CHECK(std::abs(rowPeak.back() - rowPeak.front()) >= 2.0);
    for (size_t i = 1; i < rowPeak.size(); ++i)
        CHECK(dir0 * (rowPeak[i] - rowPeak[i - 1]) >= -0.25);
    // The dense map moves the same way: the median of each band of map rows.
    const FocusMap& m = r->map;
    std::vector<double> band;
    for (int b = 0; b < 4; ++b) {
        std::vector<double> v;
        for (int y = b * m.rows / 4; y < (b + 1) * m.rows / 4; ++y)
            for (int x = 0; x < m.cols; ++x)
                if (std::isfinite(m.peakFrame[static_cast<size_t>(y) * m.cols + x]))
                    v.push_back(m.peakFrame[static_cast<size_t>(y) * m.cols + x]);
        REQUIRE(!v.empty());
        band.push_back(median(v));
        std::printf("pcb map band %d: median peak frame %.2f\n", b, band.back());
    }
    for (size_t i = 1; i < band.size(); ++i)
        CHECK(dir0 * (band[i] - band[i - 1]) > 0);

    SECTION("the composite is as sharp as the sharpest frame in every textured tile") {
        REQUIRE(r->composite.size() == static_cast<size_t>(r->width) * r->height);
        Luma8 comp{r->composite.data(), r->width, r->height, r->width, nullptr};
        SharpnessParams sp;
        int tiles = 0, sharp = 0;
        double worst = HUGE_VAL;
        for (const StackRegion& g : r->regions) {
            if (g.status != StackRegionStatus::Ok) continue;
            const double best = *std::max_element(g.sharpness.begin(), g.sharpness.end());
            const double c = regionSharpness(comp, g.rect, sp);
            ++tiles;
            // Tolerance: the composite keeps 85 % of the best frame's sharpness in each tile
            // (a tile spanning the band's edge blends two frames).
            sharp += c >= 0.85 * best;
            worst = std::min(worst, c / best);
            INFO("tile " << g.col << "," << g.row << ": composite " << c << ", best frame "
                         << best);
            CHECK(c >= 0.85 * best);
        }
        std::printf(
            "pcb composite: %d of %d textured tiles at least 85 %% of the best frame "
            "(worst %.2f)\n",
            sharp, tiles, worst);
    }
}

TEST_CASE("depthmap: the switch's top, its body and the board take three different peaks",
          "[stack][data]") {
    const auto dir = test::requireData("focus-stack/depthmap");
    StackOptions o;
    o.maps = false;
    auto r = analyzeStack(dir.string(), o);
    REQUIRE(r);
    REQUIRE(r->frames.size() == 10u);
    // On the 8×6 grid: the board at the corners and beside the pads, the switch body at the
    // four corners of its moulding, the top at the button in the centre.
    const auto peaksAt = [&](std::initializer_list<std::pair<int, int>> cells) {
        std::vector<double> v;
        for (auto [c, rr] : cells)
            for (const StackRegion& g : r->regions)
                if (g.col == c && g.row == rr && g.peakFrame) v.push_back(*g.peakFrame);
        REQUIRE(v.size() == cells.size());
        std::sort(v.begin(), v.end());
        return v;
    };
    const auto board = peaksAt({{0, 0}, {7, 0}, {0, 5}, {7, 5}, {1, 2}, {6, 2}});
    const auto body = peaksAt({{2, 2}, {5, 2}, {2, 4}, {5, 4}});
    const auto top = peaksAt({{3, 3}, {4, 3}, {4, 2}});
    std::printf("depthmap peak frames: board %.2f to %.2f, body %.2f to %.2f, top %.2f to %.2f\n",
                board.front(), board.back(), body.front(), body.back(), top.front(), top.back());
    // Three heights: each group's peaks apart from the next group's by at least half a frame
    // (the frames are the only unit here), the board lowest, the top highest.
    CHECK(body.front() - board.back() >= 0.5);
    CHECK(top.front() - body.back() >= 0.5);
}

TEST_CASE("a positions file: its rows and its faults", "[stack]") {
    test::ScratchDir tmp("infocus-stack-");
    const auto write = [&](const std::string& text) {
        std::ofstream(tmp.file("p.csv")) << text;
        return readPositionsCsv(tmp.file("p.csv"));
    };
    auto ok = write("frame,position,unit\n1,0.5,m\n0,1.5,dpt\n2,-50,mm\n");
    REQUIRE(ok);
    REQUIRE(ok->size() == 3u);
    CHECK((*ok)[0].unit == "dioptre");
    CHECK(*(*ok)[0].dioptres == 1.5);
    CHECK(*(*ok)[1].dioptres == 2.0);
    CHECK(!(*ok)[2].dioptres);
    CHECK((*ok)[2].value == -50);
    for (const char* badText : {"0,1,dpt\n0,2,dpt\n", "0,1,dpt\n2,2,dpt\n", "0,abc,dpt\n", "0,1\n",
                                "0,-1,m\n", "x,1,dpt\n", ""}) {
        INFO(badText);
        auto b = write(badText);
        REQUIRE(!b);
        CHECK(b.error().kind == ErrorKind::Usage);
        CHECK(b.error().message.find("p.csv") != std::string::npos);
    }
    CHECK(readPositionsCsv(tmp.file("none.csv")).error().kind == ErrorKind::NotFound);
}

TEST_CASE("a stack without texture: every region is marked, none given a peak", "[stack]") {
    // Five frames of a flat grey with white noise (σ 2 grey levels), different in each frame.
    test::ScratchDir tmp("infocus-stack-");
    SourceInfo info;
    info.sourceString = "flat";
    info.format = PixelFormat::GREY;
    info.size = {320, 240};
    auto writer = RecordingWriter::create(tmp.file("rec"), makeRecordingHeader(info, nullptr));
    REQUIRE(writer);
    uint32_t state = 12345;
    const auto gauss = [&] {  // Irwin-Hall: twelve uniforms, σ 1
        double s = 0;
        for (int i = 0; i < 12; ++i) {
            state = state * 1664525u + 1013904223u;
            s += (state >> 8) / double(1 << 24);
        }
        return s - 6.0;
    };
    for (int f = 0; f < 5; ++f) {
        Image<uint8_t> img(320, 240);
        for (int y = 0; y < 240; ++y)
            for (int x = 0; x < 320; ++x)
                img.at(x, y) = static_cast<uint8_t>(std::lround(100 + 2 * gauss()));
        Frame frame = frameFromLuma(img.view());
        frame.sequence = f;
        REQUIRE((*writer)->append(frame));
    }
    REQUIRE((*writer)->close());
    StackOptions o;
    o.cols = 4;
    o.rows = 3;
    auto r = analyzeStack(tmp.file("rec"), o);
    REQUIRE(r);
    for (const StackRegion& g : r->regions) {
        INFO("region " << g.col << "," << g.row << ": " << g.statusReason);
        CHECK(g.status == StackRegionStatus::NoTexture);
        CHECK(!g.peakFrame);
        CHECK(!g.agree);
    }
    CHECK(stackAgreement(*r).textured == 0);
    // Whole-stack faults: too few frames, positions of the wrong count or direction.
    o.positions = {LensPosition{1, "mm", {}}, LensPosition{2, "mm", {}}};
    CHECK(analyzeStack(tmp.file("rec"), o).error().kind == ErrorKind::Usage);
    o.positions.clear();
    for (double p : {1.0, 2.0, 2.0, 3.0, 4.0})
        o.positions.push_back(LensPosition{p, "mm", {}});
    CHECK(analyzeStack(tmp.file("rec"), o).error().message.find("frames 1 and 2") !=
          std::string::npos);
}
