// SPDX-License-Identifier: MIT
// `infocus dof` and `infocus depth` as a user runs them: the built executable (path in $INFOCUS),
// its exit status, its table and its JSON. The depth fixture is rendered here from the thin-lens
// formulas, not taken from the program's own output.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace {

struct Run {
    int status = -1;
    std::string out;  // stdout and stderr together
};

Run run(const std::string& args) {
    const char* bin = std::getenv("INFOCUS");
    REQUIRE(bin != nullptr);
    Run r;
    FILE* p = ::popen((std::string(bin) + " " + args + " 2>&1").c_str(), "r");
    REQUIRE(p != nullptr);
    char buf[4096];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0)
        r.out.append(buf, n);
    const int st = ::pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return r;
}

bool has(const Run& r, const std::string& text) {
    return r.out.find(text) != std::string::npos;
}

double relErr(double got, double want) {
    return std::abs(got - want) / std::abs(want);
}

}  // namespace

TEST_CASE("dof prints the reference numbers as a table", "[cli]") {
    const auto r = run("dof --focal 50mm --fnumber 8 --focus 10m --coc 0.03mm");
    INFO(r.out);
    CHECK(r.status == 0);
    // 5114.6 mm, 223 214 mm, H 10 466.7 mm, H/2, shown to the printed precision.
    CHECK(has(r, "near limit        5.115 m"));
    CHECK(has(r, "far limit         223.2 m"));
    CHECK(has(r, "hyperfocal        10.47 m"));
    CHECK(has(r, "sharp from 5.233 m to infinity"));
    CHECK(has(r, "distances from the lens"));
}

TEST_CASE("dof writes a far-fetched magnitude as a number with an exponent", "[cli]") {
    // At f/1e300 the Airy disc is 2.44 λN = 1.34e+294 m, 4.47e+298 CoCs of 0.03 mm: as digits
    // it filled 300 columns of the table.
    const auto r = run("dof --focal 50mm --fnumber 1e300 --focus 2m --coc 0.03mm");
    REQUIRE(r.status == 0);
    CHECK_THAT(r.out,
               Catch::Contains("Airy disc 1.34e+294 m") && Catch::Contains("4.47e+298 × the CoC"));
    // Within the usual range nothing changes.
    const auto usual = run("dof --focal 50mm --fnumber 8 --focus 10m --coc 0.03mm");
    CHECK_THAT(usual.out,
               Catch::Contains("Airy disc 10.7 µm") && Catch::Contains("0.36 × the CoC"));
}

TEST_CASE("dof --json has the contract's fields, from the lens and from the sensor", "[cli]") {
    const auto r = run("dof --focal 50mm --fnumber 8 --focus 10m --coc 0.03mm --json");
    INFO(r.out);
    REQUIRE(r.status == 0);
    const auto j = nlohmann::json::parse(r.out);
    // Reference values to their stated digits (0.1 mm, 1 mm).
    CHECK(std::abs(j["hyperfocal_m"].get<double>() - 10.4667) < 0.5e-4);
    CHECK(std::abs(j["near_m"].get<double>() - 5.1146) < 0.5e-4);
    CHECK(std::abs(j["far_m"].get<double>() - 223.214) < 0.5e-3);
    CHECK(relErr(j["total_m"].get<double>(), j["far_m"].get<double>() - j["near_m"].get<double>()) <
          1e-12);
    CHECK(j["from"] == "lens");
    CHECK(j["coc_um"].get<double>() == Approx(30.0).epsilon(1e-12));
    CHECK(j["airy_um"].get<double>() == Approx(10.736).epsilon(1e-12));  // 2.44·0.55·8

    const auto s =
        run("dof --focal 50mm --fnumber 8 --focus 10m --coc 0.03mm --from sensor --json");
    REQUIRE(s.status == 0);
    const auto k = nlohmann::json::parse(s.out);
    CHECK(std::abs(k["near_m"].get<double>() - 5.1517) < 0.5e-4);
    CHECK(std::abs(k["far_m"].get<double>() - 200.552) < 0.5e-3);
    CHECK(k["from"] == "sensor");

    // Focused beyond the hyperfocal distance the far limit is infinite: null in JSON.
    const auto inf = run("dof --focal 50mm --fnumber 8 --focus 20m --coc 0.03mm --json");
    REQUIRE(inf.status == 0);
    const auto m = nlohmann::json::parse(inf.out);
    CHECK(m["far_m"].is_null());
    CHECK(m["total_m"].is_null());
}

TEST_CASE("dof presets, pixels and the inverse problem", "[cli]") {
    // Full frame: c = 43.267 mm / 1500 = 28.844 µm.
    auto r = run("dof --focal 50mm --fnumber 8 --focus 10m --sensor full-frame --json");
    REQUIRE(r.status == 0);
    CHECK(nlohmann::json::parse(r.out)["coc_um"].get<double>() == Approx(28.844).epsilon(1e-4));
    // 2 px of 1.4 µm = 2.8 µm.
    r = run("dof --focal 4.74mm --fnumber 1.8 --focus 1m --coc-px 2 --pixel-pitch 1.4um --json");
    REQUIRE(r.status == 0);
    CHECK(nlohmann::json::parse(r.out)["coc_um"].get<double>() == Approx(2.8).epsilon(1e-12));
    // Wanted 2 m to 5 m: focus at the dioptric midpoint 1/(0.35 dpt) = 2.857 m.
    r = run("dof --focal 50mm --near 2m --far 5m --coc 0.03mm --json");
    INFO(r.out);
    REQUIRE(r.status == 0);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(relErr(j["focus_m"].get<double>(), 2.0 / 0.7) < 1e-9);
    CHECK(relErr(j["near_m"].get<double>(), 2.0) < 1e-9);
    CHECK(relErr(j["far_m"].get<double>(), 5.0) < 1e-9);
}

TEST_CASE("usage errors exit 2 and say what to type", "[cli]") {
    // Each command must exit 2 and print the text after it.
    const auto usage = [](const std::string& command, const std::string& text) {
        INFO(command);
        const Run r = run(command);
        CHECK(r.status == 2);
        CHECK(has(r, text));
    };
    usage("dof --focal 50 --fnumber 8 --focus 10m", "--focal 50: give a unit, e.g. --focal 50mm");
    usage("dof --focal 50mm --fnumber 0 --focus 10m", "f-number must be positive");
    usage("dof --focal 0mm --fnumber 8 --focus 10m", "focal length must be positive");
    usage("dof --focal 50mm --fnumber 8 --focus 40mm", "inside the focal length");
    usage("dof --focal 50mm --fnumber 8 --focus 10", "--focus 10: give a unit, e.g. --focus 10m");
    usage("dof --focal 50mm --fnumber 8", "give the focus distance");
    CHECK(run("dof --focal 50mm --fnumber 8 --focus 10m --coc 0.03mm --sensor m43").status == 2);
    usage("dof --focal 50mm --fnumber 8 --focus 10m --sensor potato", "unknown sensor");
    usage("depth x.jsonl --focal 25mm --fnumber 1.4 --focus 0.5 --pixel-pitch 3.45um",
          "give a unit");
    // Values that no comparison refuses (inf, NaN) are refused by name.
    usage("depth sim: --frames 1 --lens rpi-cam3 --blur-floor inf",
          "--blur-floor must be a finite 0 or more pixels");
    usage("depth sim: --frames 1 --lens rpi-cam3 --min-confidence nan",
          "--min-confidence must be a number from 0 to 1");
    usage("depth sim: --lens rpi-cam3 --frames -1", "not a frame count");
    // CLI11's own errors are said by the command, with where its options are listed.
    usage("record sim: --frames 2", "infocus record: --output is required");
    usage("record sim: --frames 2", "Run 'infocus record --help' for the options.");
    usage("record sim: -o /tmp/infocus-never-made --frames 0",
          "--frames: '0' is not a frame count; give a whole number ≥ 1");
    usage("record sim: -o /tmp/infocus-never-made --seconds -1",
          "--seconds: '-1' is not a duration here; give seconds above 0, e.g. 10");
    usage("bench --seconds nan", "give seconds above 0 and at most 10");
}

TEST_CASE("depth names the line and the field of a record it cannot read", "[cli]") {
    char path[] = "/tmp/infocus-depth-bad-XXXXXX.jsonl";
    const int fd = ::mkstemps(path, 6);
    REQUIRE(fd >= 0);
    ::close(fd);
    std::ofstream(path) << "{\"frame\": 0, \"regions\": []}\n";
    const Run r = run(std::string("depth ") + path + " --lens rpi-cam3");
    std::remove(path);
    INFO(r.out);
    CHECK(r.status == 1);
    CHECK(has(r, "line 1: analysis record: key 'width' not found"));
    CHECK(!has(r, "json.exception"));
}

TEST_CASE("depth refuses a record value analyze never writes, and names it", "[cli]") {
    // One good region; each case puts one value out of its range (a float, a negative length, a
    // confidence past 1). Read as they were, they drew an image of -2147483648 columns or fitted
    // the plane to a blur of -3 px.
    const auto record = [](const std::string& width, const std::string& x, const std::string& w,
                           const std::string& blur, const std::string& confidence) {
        return "{\"frame\": 0, \"width\": " + width + ", \"height\": 480, \"regions\": [" +
               "{\"col\": 0, \"row\": 0, \"x\": " + x + ", \"y\": 0, \"w\": " + w +
               ", \"h\": 80, \"sharpness\": 0.01, \"blur_width_px\": " + blur +
               ", \"confidence\": " + confidence + "}]}\n";
    };
    const std::pair<std::string, std::string> cases[] = {
        {record("1e308", "0", "80", "2.0", "0.5"), "\"width\" must be a whole number from 1"},
        {record("-1", "0", "80", "2.0", "0.5"), "\"width\" must be a whole number from 1"},
        {record("640", "1e308", "80", "2.0", "0.5"), "region 1: \"x\" must be a whole number"},
        {record("640", "0", "0", "2.0", "0.5"), "region 1: \"w\" must be a whole number from 1"},
        {record("640", "0", "80", "-3", "0.5"), "region 1: \"blur_width_px\" must be 0.0 or more"},
        {record("640", "0", "80", "2.0", "7"), "region 1: \"confidence\" must be 0.0 to 1.0"},
    };
    for (const auto& [text, message] : cases) {
        char path[] = "/tmp/infocus-depth-range-XXXXXX.jsonl";
        const int fd = ::mkstemps(path, 6);
        REQUIRE(fd >= 0);
        ::close(fd);
        std::ofstream(path) << text;
        const Run r = run(std::string("depth ") + path + " --lens rpi-cam3 --focus 1m");
        std::remove(path);
        INFO(text << r.out);
        CHECK(r.status == 1);
        CHECK(has(r, "line 1: analysis record: " + message));
    }
    // The same record in range is read.
    char path[] = "/tmp/infocus-depth-range-XXXXXX.jsonl";
    const int fd = ::mkstemps(path, 6);
    REQUIRE(fd >= 0);
    ::close(fd);
    std::ofstream(path) << record("640", "0", "80", "2.0", "0.5");
    const Run ok = run(std::string("depth ") + path + " --lens rpi-cam3 --focus 1m");
    std::remove(path);
    INFO(ok.out);
    CHECK(ok.status == 0);
}

TEST_CASE("depth on a blur map rendered from the thin-lens model", "[cli]") {
    // 25 mm f/1.4 focused at 0.5 m, 3.45 µm pixels, 1920x1080, 16x9 regions; the scene plane
    // meets the axis at 0.52 m and is tilted 20° about the image's x axis (depth grows down).
    const double f = 25e-3, n = 1.4, u = 0.5, pitch = 3.45e-6, z0 = 0.52;
    const double tilt = 20.0 * M_PI / 180.0;
    const double aperture = f / n, zs = f * u / (u - f);  // A = f/N; 1/f = 1/u + 1/z_s
    const double c = 1.0 / z0, b = c * std::tan(tilt);    // plane bY + cZ = 1
    nlohmann::json frame;
    frame["frame"] = 0;
    frame["timestamp_ns"] = 0;
    frame["lens_position"] = nullptr;
    frame["width"] = 1920;
    frame["height"] = 1080;
    std::vector<double> depth;
    for (int row = 0; row < 9; ++row)
        for (int col = 0; col < 16; ++col) {
            const int x = col * 120, y = row * 120;
            const double sy = (y + 60 - 540) * pitch;  // sensor y of the region centre
            const double z = zs / (b * sy + c * zs);   // chief ray (x, y, z_s)·t meets the plane
            const double blur = aperture * zs * std::abs(1.0 / z - 1.0 / u) / pitch;
            depth.push_back(z);
            frame["regions"].push_back({{"col", col},
                                        {"row", row},
                                        {"x", x},
                                        {"y", y},
                                        {"w", 120},
                                        {"h", 120},
                                        {"sharpness", 0.5},
                                        {"edge_width_px", 0.68705 * blur},
                                        {"blur_sigma_px", nullptr},
                                        {"blur_width_px", blur},
                                        {"confidence", 0.9}});
        }
    char path[] = "/tmp/infocus_depth_XXXXXX.jsonl";
    const int fd = ::mkstemps(path, 6);
    REQUIRE(fd >= 0);
    ::close(fd);
    std::ofstream(path) << frame.dump() << "\n";

    const std::string lens = " --focal 25mm --fnumber 1.4 --focus 0.5m --pixel-pitch 3.45um";
    const auto r = run(std::string("depth ") + path + lens + " --json");
    INFO(r.out.substr(0, 2000));
    REQUIRE(r.status == 0);
    const auto j = nlohmann::json::parse(r.out);
    const auto& regions = j["regions"];
    REQUIRE(regions.size() == 144);
    int matched = 0;
    for (size_t i = 0; i < regions.size(); ++i) {
        const double z = depth[i];
        // The true depth is one of the two roots (1e-9 relative: double arithmetic only).
        const auto& o = regions[i];
        const bool nearOk = relErr(o["near_m"].get<double>(), z) < 1e-9;
        const bool farOk = !o["far_m"].is_null() && relErr(o["far_m"].get<double>(), z) < 1e-9;
        matched += nearOk || farOk;
    }
    CHECK(matched == 144);
    const auto& plane = j["plane"];
    REQUIRE(plane.is_object());
    CHECK(plane["inliers"] == 144);
    // The plane crosses focus (Z = 0.5 m) at sensor y = z_s (1/u − c)/b: a horizontal line.
    CHECK(std::abs(plane["line_angle_deg"].get<double>() - 0.0) < 1e-6);
    // One of the two reported planes is the true one: 20° tilt, on axis at 0.52 m.
    bool found = false;
    for (const auto& s : plane["scene_planes"])
        found = found || (std::abs(s["tilt_deg"].get<double>() - 20.0) < 1e-6 &&
                          std::abs(s["depth_on_axis_m"].get<double>() - 0.52) < 1e-9);
    CHECK(found);

    // The same through stdin, as a table.
    const auto t = run("depth -" + lens + " < " + path);
    INFO(t.out.substr(0, 2000));
    CHECK(t.status == 0);
    CHECK(has(t, "tilt 20.00 deg"));
    std::remove(path);
}
