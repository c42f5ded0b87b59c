// SPDX-License-Identifier: MIT
// The HTML report against ground truth: the thin-lens model's depth-of-field reference values, the
// simulated camera's known focus and tilt, and the regions' own blur against the CoC.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "infocus/analysis.h"
#include "infocus/luma.h"
#include "infocus/pipeline.h"
#include "infocus/report.h"

using namespace infocus;

namespace {

struct Run {
    std::string html;
    std::vector<FrameAnalysis> frames;
};

// Analyses @p frames frames of @p source on a 16×9 grid and reports them with @p optics.
Run reportOf(const std::string& source, const ReportOptics& optics, uint64_t frames = 1) {
    ReportOptions o;
    o.source = source;
    o.optics = optics;
    ReportWriter w(o);
    Run run;
    LumaConverter conv;
    AnalysisOptions ao;
    const Status st =
        analyzeSourceFrames(source, ao, frames, [&](const FrameAnalysis& a, const Frame& f) {
            run.frames.push_back(a);
            auto luma = conv.toLuma8(f);
            if (!luma) return Status(luma.error());
            return w.add(a, *luma);
        });
    REQUIRE(st);
    REQUIRE(w.frames() == frames);
    run.html = w.html();
    return run;
}

// The numbers after @p prefix in @p html, as the report printed them.
std::vector<double> numbersAfter(const std::string& html, const std::string& pattern) {
    std::smatch m;
    REQUIRE(std::regex_search(html, m, std::regex(pattern)));
    std::vector<double> v;
    for (size_t i = 1; i < m.size(); ++i)
        v.push_back(std::stod(m[i].str()));
    return v;
}

ReportOptics lens16(double cocPx = 2.0) {
    ReportOptics p;
    p.lens = optics::ThinLens{16e-3, 1.4};
    p.pixelPitch = 5.04e-6;  // the sim's 4608 × 1.4 µm sensor rendered 1280 wide
    p.cocPx = cocPx;
    p.cocSource = "test";
    return p;
}

}  // namespace

TEST_CASE("report: depth of field matches the thin-lens model's reference values", "[report]") {
    // 50 mm, f/8, c = 0.030 mm, focus 10 m: H = 10 466.7 mm, near 5 114.6 mm, far 223 214 mm.
    FrameAnalysis a;
    a.width = 640;
    a.height = 480;
    a.metric = "teng";
    a.regions.push_back({0,
                         0,
                         {0, 0, 640, 480},
                         1.0,
                         1.0,
                         0.5,
                         2.0,
                         std::nullopt,
                         std::nullopt,
                         0.9,
                         std::nullopt,
                         RegionStatus::Ok,
                         {}});
    ReportOptions o;
    o.optics.lens = optics::ThinLens{50e-3, 8.0};
    o.optics.pixelPitch = 15e-6;
    o.optics.cocPx = 2.0;  // 30 µm
    o.optics.focusDistance = 10.0;
    o.optics.focusSource = "--focus";
    ReportWriter w(o);
    REQUIRE(w.add(a, Luma8{}));
    const std::string h = w.html();
    CHECK(h.find("from 5.115 m to 223.2 m") != std::string::npos);
    CHECK(h.find("hyperfocal distance 10.47 m") != std::string::npos);
    // Blur per dioptre A z_s / pitch: A = 6.25 mm, z_s = 1/(1/f − 1/u) = 50.2513 mm.
    const auto k = numbersAfter(h, "each dioptre of defocus blurs by ([0-9.]+) px");
    CHECK(k[0] == Approx(6.25e-3 * 50.2513e-3 / 15e-6).epsilon(0.005));  // printed to 3 digits
    // A region of 2.0 px against a CoC of 2 px is sharp (at most the CoC).
    CHECK(numbersAfter(h, "In focus</b>: ([0-9]+) of the ([0-9]+) regions")[0] == 1);
}

TEST_CASE("report: a plane in focus is sharp, one a dioptre off is not (sim ground truth)",
          "[report]") {
    // 16 mm f/1.4 at 5.04 µm: A z_s / pitch = 36.9 px of blur per dioptre of defocus.
    const std::string lens = ",focal=16mm,fnumber=1.4";
    const Run in = reportOf("sim:scene=plane,distance=1m,focus=1m" + lens, lens16());
    const auto inFocus = numbersAfter(in.html, "In focus</b>: ([0-9]+) of the ([0-9]+) regions");
    INFO(inFocus[0] << " of " << inFocus[1]);
    // Enough of the 144 regions to judge: those whose blur reads with confidence ≥ 0.1 (93; the
    // confidence discounts edges whose profile does not look like a defocus).
    REQUIRE(inFocus[1] >= 80);
    // The true blur is 0; what the regions read is the estimator's scatter on sharp texture
    // (median 1.3 px, a fifth above 1.9 px): two thirds must be within a CoC of 2 px.
    CHECK(inFocus[0] >= 2.0 / 3.0 * inFocus[1]);
    // The report counts exactly the regions whose measured blur is within the CoC.
    int sharp = 0;
    for (const auto& r : in.frames[0].regions)
        if (r.blurWidthPx && r.confidence >= 0.1 && *r.blurWidthPx <= 2.0) ++sharp;
    CHECK(inFocus[0] == sharp);

    // Focused at 0.5 m, the plane at 1 m is 1 dpt off: a true blur of 37 px, nothing sharp.
    const Run off = reportOf("sim:scene=plane,distance=1m,focus=0.5m" + lens, lens16());
    CHECK(numbersAfter(off.html, "In focus</b>: ([0-9]+) of")[0] == 0);
    CHECK(off.html.find("500.0 mm from the lens (lens position of the frame)") !=
          std::string::npos);
}

TEST_CASE("report: the in-focus line and the tilt of a tilted plane (sim ground truth)",
          "[report]") {
    // A plane tilted 60° about the x axis, 1 m away on the axis, focused at 1 m: the in-focus
    // line is the image's centre row (y = 360) and the scene meets the plane of focus at 60°.
    const Run r = reportOf(
        "sim:scene=tilted,tilt=60,axis=x,distance=1m,focus=1m,focal=16mm,fnumber=1.4", lens16());
    const auto line = numbersAfter(r.html,
                                   "It crosses the image from \\(([-0-9.]+), ([-0-9.]+)\\) to "
                                   "\\(([-0-9.]+), ([-0-9.]+)\\) px");
    const double yMid = line[1] + (line[3] - line[1]) * (640.0 - line[0]) / (line[2] - line[0]);
    INFO("in-focus line " << line[0] << "," << line[1] << " to " << line[2] << "," << line[3]);
    CHECK(std::abs(yMid - 360.0) <= 20.0);  // one region is 80 px high
    const auto tilt = numbersAfter(r.html, "meets the plane of focus at ([0-9.]+)&deg;");
    CHECK(tilt[0] == Approx(60.0).margin(3.0));
    // Both readings of the single focus setting: the plane crosses the axis near 1 m either way.
    const std::regex onAxis("crosses (?:the optical axis|it) at ([0-9.]+) (mm|m)\\b");
    int readings = 0;
    for (auto it = std::sregex_iterator(r.html.begin(), r.html.end(), onAxis);
         it != std::sregex_iterator(); ++it, ++readings) {
        const double d = std::stod((*it)[1].str()) * ((*it)[2].str() == "mm" ? 1e-3 : 1.0);
        INFO("plane on the axis at " << d << " m");
        CHECK(std::abs(d - 1.0) <= 0.05);
    }
    CHECK(readings == 2);
    // The line is drawn on the frame.
    CHECK(r.html.find("stroke-dasharray") != std::string::npos);
}

TEST_CASE("report: self-contained, one section per frame, a summary of a stack", "[report]") {
    const Run r = reportOf("sim:scene=plane,distance=1m,focus=1m,size=640x360", ReportOptics{}, 3);
    const std::string& h = r.html;
    CHECK(h.rfind("<!DOCTYPE html>", 0) == 0);
    CHECK(h.find("data:image/jpeg;base64,") != std::string::npos);
    // Nothing is fetched: no script, stylesheet link or remote address but the SVG namespace.
    CHECK(h.find("<script") == std::string::npos);
    CHECK(h.find("<link") == std::string::npos);
    std::string rest =
        std::regex_replace(h, std::regex("xmlns=\"http://www.w3.org/2000/svg\""), "");
    CHECK(rest.find("http") == std::string::npos);
    size_t sections = 0;
    for (size_t p = h.find("<h2 id=\"frame"); p != std::string::npos;
         p = h.find("<h2 id=\"frame", p + 1))
        ++sections;
    CHECK(sections == 3);
    CHECK(h.find("<h2>Frames</h2>") != std::string::npos);
    // Without a lens the report stays in pixels and says what would add distances.
    CHECK(h.find("This report is in pixels of the image") != std::string::npos);
    CHECK(h.find("--pixel-pitch") != std::string::npos);
    CHECK(h.find("Depth of field</b>") == std::string::npos);
}

TEST_CASE("report: the source is shown as text, never as markup", "[report]") {
    FrameAnalysis a;
    a.width = 64;
    a.height = 64;
    ReportOptions o;
    o.source = "clip<script>alert(1)</script>.y4m";
    ReportWriter w(o);
    REQUIRE(w.add(a, Luma8{}));
    const std::string h = w.html();
    CHECK(h.find("<script>") == std::string::npos);
    CHECK(h.find("clip&lt;script&gt;") != std::string::npos);
}

TEST_CASE("report: written whole or not at all", "[report]") {
    const auto dir = std::filesystem::temp_directory_path() / "infocus_report_test";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "r.html").string();
    REQUIRE(writeFileAtomically(path, "first"));
    REQUIRE(writeFileAtomically(path, "second"));
    std::ifstream f(path);
    std::stringstream s;
    s << f.rdbuf();
    CHECK(s.str() == "second");
    CHECK(!std::filesystem::exists(path + ".part"));
    const Status missing = writeFileAtomically((dir / "no" / "r.html").string(), "x");
    REQUIRE(!missing);
    CHECK(missing.error().message.find((dir / "no").string()) != std::string::npos);
    std::filesystem::remove_all(dir);
}
