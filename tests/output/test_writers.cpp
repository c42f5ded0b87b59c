// SPDX-License-Identifier: MIT
// The writers against their formats: the analyze JSONL (nulls for blur not measured, a round
// trip), its CSV (header, one row per region, empty cells), a dof answer's JSON (null for
// infinity) and the lengths written for people.
#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "infocus/output.h"

using namespace infocus;
using Json = nlohmann::json;

namespace {

// A 2x1 grid of a 640x480 frame: region 0 with every blur field, region 1 without an edge.
FrameAnalysis twoRegions() {
    FrameAnalysis a;
    a.frame = 7;
    a.timestampNs = 1'500'000'000;
    a.width = 640;
    a.height = 480;
    a.metric = "teng";
    a.frameSharpness = 0.25;
    RegionResult sharp;
    sharp.col = 0;
    sharp.rect = {0, 0, 320, 480};
    sharp.sharpness = 0.5;
    sharp.edgeWidthPx = 1.75;
    sharp.blurSigmaPx = 0.5;
    sharp.blurWidthPx = 2.5;
    sharp.mtf50CyPx = 0.3125;
    sharp.mtf50pCyPx = 0.375;
    sharp.confidence = 0.875;
    RegionResult flat;
    flat.col = 1;
    flat.rect = {320, 0, 320, 480};
    flat.sharpness = 0.125;
    a.regions = {sharp, flat};
    return a;
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);)
        out.push_back(l);
    return out;
}

}  // namespace

TEST_CASE("JSONL: blur not measured is null, and no lens position is null") {
    const std::string line = toJsonLine(twoRegions());
    CHECK(line.find('\n') == std::string::npos);
    const Json j = Json::parse(line);
    CHECK(j["frame"] == 7);
    CHECK(j["timestamp_ns"] == 1'500'000'000);
    CHECK(j["lens_position"].is_null());
    CHECK(j["width"] == 640);
    CHECK(j["height"] == 480);
    REQUIRE(j["regions"].size() == 2);
    const Json& flat = j["regions"][1];
    CHECK(flat["x"] == 320);
    CHECK(flat["w"] == 320);
    CHECK(flat["edge_width_px"].is_null());
    CHECK(flat["blur_sigma_px"].is_null());
    CHECK(flat["blur_width_px"].is_null());
    CHECK(flat["mtf50_cy_px"].is_null());
    CHECK(flat["mtf50p_cy_px"].is_null());
    CHECK(flat["confidence"] == 0.0);
    const Json& sharp = j["regions"][0];
    CHECK(sharp["blur_width_px"] == 2.5);
    CHECK(sharp["blur_sigma_px"] == 0.5);
    CHECK(sharp["edge_width_px"] == 1.75);
    CHECK(sharp["mtf50_cy_px"] == 0.3125);
    CHECK(sharp["mtf50p_cy_px"] == 0.375);
    CHECK(sharp["confidence"] == 0.875);
}

TEST_CASE("JSONL: a lens position that is not a number is written as unknown") {
    // A camera or a damaged recording may report NaN; JSON has no NaN, and an object with a null
    // value would be refused when read back.
    FrameAnalysis a = twoRegions();
    a.lens = LensPosition{std::nan(""), "dioptre", std::nan("")};
    const std::string line = toJsonLine(a);
    CHECK(Json::parse(line)["lens_position"].is_null());
    auto back = parseJsonLine(line);
    REQUIRE(back);
    CHECK_FALSE(back->lens);
    // A finite position with an unknown dioptre value keeps the position and leaves dioptres out.
    a.lens = LensPosition{512.0, "v4l2", std::numeric_limits<double>::infinity()};
    const Json j = Json::parse(toJsonLine(a));
    CHECK(j["lens_position"]["value"] == 512.0);
    CHECK_FALSE(j["lens_position"].contains("dioptres"));
}

// The values are binary fractions: JSON keeps a double exactly, so they come back equal.
TEST_CASE("JSONL: a line read back holds the fields written") {
    FrameAnalysis a = twoRegions();
    a.lens = LensPosition{2.0, "dioptre", 2.0};
    a.noiseSigma = 1.5;
    const auto back = parseJsonLine(toJsonLine(a));
    REQUIRE(back);
    CHECK(back->frame == 7);
    CHECK(back->timestampNs == 1'500'000'000);
    REQUIRE(back->lens);
    CHECK(back->lens->value == 2.0);
    CHECK(back->lens->unit == "dioptre");
    CHECK(back->lens->dioptres == 2.0);
    CHECK(back->metric == "teng");
    CHECK(back->noiseSigma == 1.5);
    CHECK(back->frameSharpness == 0.25);
    REQUIRE(back->regions.size() == 2);
    for (size_t i = 0; i < 2; ++i) {
        const RegionResult& w = a.regions[i];
        const RegionResult& r = back->regions[i];
        CHECK(r.col == w.col);
        CHECK(r.row == w.row);
        CHECK(r.rect.x == w.rect.x);
        CHECK(r.rect.w == w.rect.w);
        CHECK(r.sharpness == w.sharpness);
        CHECK(r.edgeWidthPx == w.edgeWidthPx);
        CHECK(r.blurSigmaPx == w.blurSigmaPx);
        CHECK(r.blurWidthPx == w.blurWidthPx);
        CHECK(r.mtf50CyPx == w.mtf50CyPx);
        CHECK(r.mtf50pCyPx == w.mtf50pCyPx);
        CHECK(r.confidence == w.confidence);
    }
}

TEST_CASE("JSONL: a malformed line fails naming the field") {
    const auto r = parseJsonLine(R"({"frame": 0, "width": -3, "height": 2, "regions": []})");
    REQUIRE_FALSE(r);
    CHECK(r.error().kind == ErrorKind::Corrupt);
    CHECK(r.error().message.find("\"width\"") != std::string::npos);
}

TEST_CASE("CSV: the header once, one row per region, empty cells for what is missing") {
    std::ostringstream out;
    writeAnalysisCsv(out, twoRegions(), true);
    writeAnalysisCsv(out, twoRegions(), false);
    const auto rows = lines(out.str());
    REQUIRE(rows.size() == 1 + 2 * 2);
    CHECK(rows[0] ==
          "frame,timestamp_ns,lens_value,lens_unit,width,height,col,row,x,y,w,h,sharpness,"
          "edge_width_px,blur_sigma_px,blur_width_px,mtf50_cy_px,mtf50p_cy_px,confidence,status,"
          "reason");
    // No lens: its two cells empty; no edge: the three blur cells empty.
    CHECK(rows[1] ==
          "7,1500000000,,,640,480,0,0,0,0,320,480,0.5,1.75,0.5,2.5,0.3125,0.375,0.875,ok,");
    CHECK(rows[2] == "7,1500000000,,,640,480,1,0,320,0,320,480,0.125,,,,,,0,ok,");
    CHECK(rows[3] == rows[1]);
    // A dark region: no score, no blur, its status and reason.
    FrameAnalysis a = twoRegions();
    a.regions[1].status = RegionStatus::Dark;
    a.regions[1].statusReason = "dark: mean 0.10";
    std::ostringstream dark;
    writeAnalysisCsv(dark, a, false);
    CHECK(lines(dark.str())[1] ==
          "7,1500000000,,,640,480,1,0,320,0,320,480,,,,,,,,dark,dark: mean 0.10");
}

TEST_CASE("JSONL: a dark region and a black frame have null scores and say why") {
    FrameAnalysis a = twoRegions();
    a.noiseReason = "cannot be estimated";
    for (RegionResult& r : a.regions) {
        r.status = RegionStatus::Dark;
        r.statusReason = "dark: mean 0.10";
    }
    const Json j = Json::parse(toJsonLine(a));
    CHECK(j["frame_sharpness"].is_null());
    CHECK(j["noise_sigma"].is_null());
    CHECK(j["noise_reason"] == "cannot be estimated");
    CHECK(j["regions"][0]["sharpness"].is_null());
    CHECK(j["regions"][0]["blur_width_px"].is_null());
    CHECK(j["regions"][0]["status"] == "dark");
    CHECK(j["regions"][0]["reason"] == "dark: mean 0.10");
    const auto back = parseJsonLine(toJsonLine(a));
    REQUIRE(back);
    CHECK(back->noiseReason == "cannot be estimated");
    CHECK(back->regions[1].status == RegionStatus::Dark);
    CHECK(back->regions[1].statusReason == "dark: mean 0.10");
    CHECK_FALSE(back->regions[1].blurWidthPx);
    // An Ok region has "status" and no "reason".
    const Json ok = Json::parse(toJsonLine(twoRegions()));
    CHECK(ok["regions"][0]["status"] == "ok");
    CHECK_FALSE(ok["regions"][0].contains("reason"));
}

TEST_CASE("dof JSON: an infinite far limit is null, the wanted limits only when asked") {
    optics::DofInput in;
    in.lens = {0.05, 8.0};
    in.focusDistance = 10.0;
    in.coc = 30e-6;
    optics::DofResult r;
    r.focusDistance = 10.0;
    r.exact = {5.0, HUGE_VAL};
    const Json j = Json::parse(dofJson(r, in, "--coc"));
    CHECK(j["near_m"] == 5.0);
    CHECK(j["far_m"].is_null());
    CHECK(j["total_m"].is_null());
    CHECK(j["coc_source"] == "--coc");
    CHECK_FALSE(j.contains("wanted_near_m"));
    const Json w = Json::parse(dofJson(r, in, "--coc", DofWanted{2.0, HUGE_VAL}));
    CHECK(w["wanted_near_m"] == 2.0);
    CHECK(w["wanted_far_m"].is_null());
}

TEST_CASE("distances for people") {
    CHECK(formatDistance(HUGE_VAL) == "infinity");
    CHECK(formatDistance(0.5123) == "512.3 mm");
    CHECK(formatDistance(5.115) == "5.115 m");
    CHECK(formatDistance(223.2) == "223.2 m");
    CHECK(formatSensorLength(30e-6) == "30.0 µm");
    CHECK(formatSensorLength(1.4e-3) == "1.40 mm");
}

TEST_CASE("live JSON: the web view's fields, null where a state has none") {
    LiveState s;
    s.frame = 12;
    s.sequence = 40;
    s.width = 1920;
    s.height = 1080;
    s.source = "sim:";
    s.liveCamera = true;
    s.metric = "teng";
    Json bare = Json::parse(liveStateJson(s));
    CHECK(bare["source"] == "sim:");
    CHECK(bare["sequence"] == 40);
    CHECK(bare["live_camera"] == true);
    CHECK(bare["has_focus_control"] == false);
    CHECK(bare["focus_range"].is_null());
    CHECK(bare["peaking"] == "off");
    CHECK(bare["roi"].is_null());
    CHECK(bare["magnifier"].is_null());
    CHECK(bare["preview"].is_null());
    CHECK(bare["in_focus_line"].is_null());

    s.hasFocusControl = true;
    s.focusRange = FocusRange{0.0, 10.0, 0.0, 1.0, "dioptre"};
    s.peaking = PeakingMode::Percentile;
    s.scoreRoi = Rect{600, 300, 200, 100};
    s.magnifier = Magnifier{960, 540, 2, Image<uint8_t>(128, 128), Rect{928, 508, 64, 64}};
    s.preview = std::make_shared<const Image<uint8_t>>(960, 540);
    s.inFocusLine = optics::ImageSegment{0.0, 10.5, 1919.0, 20.25};
    Json full = Json::parse(liveStateJson(s));
    CHECK(full["has_focus_control"] == true);
    CHECK(full["focus_range"] ==
          Json({{"min", 0.0}, {"max", 10.0}, {"step", 0.0}, {"unit", "dioptre"}}));
    CHECK(full["peaking"] == "percentile");
    CHECK(full["roi"] == Json({600, 300, 200, 100}));
    CHECK(full["magnifier"] == Json({{"x", 960}, {"y", 540}, {"zoom", 2}}));
    CHECK(full["preview"] == Json({{"width", 960}, {"height", 540}}));
    CHECK(full["in_focus_line"]["y1"].get<double>() == Approx(20.25).margin(1e-12));

    // A region too dark to measure: its status, and no score standing in for one.
    LiveRegion ok, dark;
    ok.sharpness = 0.5;
    ok.depthNearM = 0.7;
    ok.depthFarM = std::numeric_limits<double>::infinity();
    dark.col = 1;
    dark.status = RegionStatus::Dark;
    s.regions = {ok, dark};
    Json regions = Json::parse(liveStateJson(s))["regions"];
    REQUIRE(regions.size() == 2);
    CHECK(regions[0]["status"] == "ok");
    CHECK(regions[0]["sharpness"].get<double>() == Approx(0.5).margin(1e-12));
    CHECK(regions[1]["status"] == "dark");
    CHECK(regions[1]["sharpness"].is_null());
    CHECK(regions[0]["depth_m"] == Json({0.7, "inf"}));
    CHECK(regions[1]["depth_m"].is_null());
}
