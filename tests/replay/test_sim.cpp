// SPDX-License-Identifier: MIT
// The simulated camera against the thin-lens model's thin-lens defocus model: the per-region disc
// diameter equals ΔX_i computed independently here, a rendered edge rises 10–90 % over
// 0.68705·d, the disc rendering equals a brute-force convolution of the interpolated texture,
// focus moves after one settle frame with one frame in flight (delay=1), and frames are
// deterministic per seed.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>

#include "infocus/sim.h"
#include "infocus/source.h"
#include "replay/replay_sources.h"

using namespace infocus;

namespace {

Result<std::unique_ptr<FrameSource>> openSim(const std::string& text) {
    auto spec = parseSourceSpec(text);
    if (!spec) return spec.error();
    return replay::openSimSource(*spec);
}

std::unique_ptr<SimRenderer> renderer(const std::string& options) {
    auto spec = parseSourceSpec("sim:" + options);
    REQUIRE(spec.ok());
    auto config = parseSimOptions(spec->options);
    REQUIRE(config.ok());
    auto r = SimRenderer::create(*config);
    REQUIRE(r.ok());
    return std::move(*r);
}

// The thin lens (docs/optics.md), in the "linear in dioptric defocus" form: ΔX_i = A·z_s·|1/z_o −
// 1/u|, with the thin-lens sensor distance z_s = f·u/(u − f) and A = f/N. Independent of the
// renderer's form A·|z_s(1/f − 1/z_o) − 1|; both are equal by 1/f = 1/z_s + 1/u.
double thinLensBlurM(double f, double n, double u, double zo) {
    const double zs = f * u / (u - f);
    return (f / n) * zs * std::abs(1.0 / zo - 1.0 / u);
}

// Pi Camera Module 3 at 1280 px wide: 1.4 µm × 4608 / 1280 = 5.04 µm per output pixel.
constexpr double kF = 4.74e-3, kN = 1.8, kPitch1280 = 1.4e-6 * 4608 / 1280;

// 10–90 % rise (pixels) of a falling edge profile between levels @p hi and @p lo, with linear
// interpolation between samples.
double riseWidth(const std::vector<double>& p, double hi, double lo) {
    const auto crossing = [&](double level) {
        for (size_t i = 1; i < p.size(); ++i)
            if (p[i - 1] >= level && p[i] < level)
                return (i - 1) + (p[i - 1] - level) / (p[i - 1] - p[i]);
        return -1.0;
    };
    const double x90 = crossing(lo + 0.9 * (hi - lo)), x10 = crossing(lo + 0.1 * (hi - lo));
    REQUIRE(x90 >= 0);
    REQUIRE(x10 >= 0);
    return x10 - x90;
}

}  // namespace

TEST_CASE("the renderer's blur diameter is the thin-lens model's ΔX_i") {
    SimLens lens;
    for (double u : {0.3, 1.2, 5.0})
        for (double zo : {0.1, 0.25, 0.6, 1.2, 3.0, 100.0}) {
            const double expect = thinLensBlurM(kF, kN, u, zo);
            auto got = simBlurDiameterM(lens, 1.0 / u, zo);
            REQUIRE(got.has_value());
            // Same quantity by two algebraic routes: equal to rounding (1e-9 relative).
            REQUIRE(*got == Approx(expect).epsilon(1e-9).margin(1e-15));
        }
    // Focus at infinity: z_s = f, ΔX_i = A·f/z_o.
    REQUIRE(*simBlurDiameterM(lens, 0.0, 2.0) == Approx(kF / kN * kF / 2.0).epsilon(1e-12));
    REQUIRE(!simBlurDiameterM(lens, 1.0 / 0.004, 2.0).has_value());  // focus inside f

    // Per region of the steps scene: the rendered diameter is ΔX_i in pixels, quantised.
    auto r = renderer("scene=steps,distances=0.25m:0.5m:1m:2m,focus=1m,size=1280x720");
    const auto regions = r->regions(1.0);
    REQUIRE(regions.size() == 4);
    const double depths[] = {0.25, 0.5, 1.0, 2.0};
    for (size_t i = 0; i < 4; ++i) {
        const Rect& rc = regions[i].rect;
        const double expectPx = thinLensBlurM(kF, kN, 1.0, depths[i]) / kPitch1280;
        INFO("region " << i << " expect " << expectPx << " px");
        REQUIRE(regions[i].depthM == Approx(depths[i]).epsilon(1e-6));  // float depth map
        REQUIRE(regions[i].blurDiameterPx == Approx(expectPx).epsilon(1e-6));
        for (int x : {rc.x, rc.x + rc.w / 2, rc.x + rc.w - 1}) {
            // Quantisation to 1/16 px: at most half a step away.
            REQUIRE(std::abs(r->renderedDiameterPxAt(x, rc.y + 3, 1.0) - expectPx) <=
                    kSimDiameterStepPx / 2 + 1e-9);
        }
    }
    // The in-focus band is sharp; the nearest band has the largest blur.
    REQUIRE(regions[2].blurDiameterPx < 1e-9);
    REQUIRE(regions[0].blurDiameterPx > regions[1].blurDiameterPx);
}

TEST_CASE("a rendered edge rises 10-90 % over 0.68705 d") {
    // A vertical edge (angle 0) at 0.1 m, 1280 px wide (5.04 um per pixel); the focus, beyond
    // the edge, sets the disc diameter d.
    for (double wantPx : {3.0, 6.0, 12.0, 20.0}) {
        // Solve ΔX_i(u) = wantPx for the far focus: 1/u = 1/zo − b/(A·z_s), iterating z_s
        // (which depends weakly on u).
        const double zo = 0.1, b = wantPx * kPitch1280;
        double invU = 1.0 / zo;
        for (int i = 0; i < 50; ++i) {
            const double zs = 1.0 / (1.0 / kF - invU);
            invU = 1.0 / zo - b / ((kF / kN) * zs);
        }
        REQUIRE(invU > 0);
        char opts[128];
        std::snprintf(opts, sizeof opts,
                      "scene=edges,angle=0,distance=0.1m,focus=%.9fdpt,size=1280x720", invU);
        auto r = renderer(opts);
        const double d = r->blurDiameterPxAt(640, 360, invU);
        REQUIRE(d == Approx(wantPx).epsilon(1e-6));
        const Image<float> sharp = r->sharpImage();
        const Image<float> img = r->render(invU);
        // A light-to-dark step in the sharp chart with flat areas ±30 px around it.
        const auto light = [&](int x, int y) { return sharp.at(x, y) > 150; };
        int row = -1, edge = -1;
        for (int y = 360; y < 680 && edge < 0; ++y)
            for (int x = 641; x < 1200; ++x)
                if (light(x - 1, y) && !light(x, y) && !light(x + 29, y) && light(x - 30, y) &&
                    !light(x + 5, y - 30) && !light(x + 5, y + 30) && light(x - 6, y - 30) &&
                    light(x - 6, y + 30)) {
                    row = y;
                    edge = x;
                    break;
                }
        REQUIRE(edge > 0);
        std::vector<double> profile;
        for (int x = edge - 29; x <= edge + 28; ++x)
            profile.push_back(img.at(x, row));
        const double rise = riseWidth(profile, 204.0, 51.0);
        INFO("d = " << d << " px, rise " << rise << " px, 0.68705 d = " << 0.68705 * d);
        // The sensor's 1-pixel area integration widens the rise slightly: allow 0.3 px + 2 %.
        REQUIRE(std::abs(rise - 0.68705 * d) <= 0.3 + 0.02 * d);
        WARN("edge d=" << d << " px: rise " << rise << " px vs 0.68705 d = " << 0.68705 * d);
    }
}

TEST_CASE("disc rendering equals a brute-force pixel-area-integrated convolution") {
    auto r =
        renderer("scene=plane,distance=0.5m,focus=1m,size=96x64,seed=7,focal=25mm,fnumber=1.4");
    const double d = r->blurDiameterPxAt(10, 10, 1.0);
    REQUIRE(d > 5);
    REQUIRE(d < 15);
    // Pixels of 67 µm: the diffraction core (σ 0.005 px) is left out of the brute force.
    REQUIRE(r->diffractionSigmaPx() < 0.01);
    const double dq = r->renderedDiameterPxAt(10, 10, 1.0);
    const Image<float> sharp = r->sharpImage();
    const Image<float> img = r->render(1.0);
    // The texture (each pixel's area average of the sharp scene) is read as a continuous image,
    // interpolated with Keys' cubic (a = −0.5), and blurred by the disc: a point u of the disc
    // takes texture pixel k with weight keys(k_x − u_x)·keys(k_y − u_y). Summed over 128 × 128
    // points per pixel inside the disc.
    const double rad = dq / 2;
    const int ext = static_cast<int>(std::ceil(rad + 2));
    const int side = 2 * ext + 1;
    std::vector<double> k(side * side);
    double sum = 0;
    const auto keys = [](double x) {
        x = std::abs(x);
        if (x < 1) return 1.5 * x * x * x - 2.5 * x * x + 1;
        if (x < 2) return -0.5 * x * x * x + 2.5 * x * x - 4 * x + 2;
        return 0.0;
    };
    for (int j = 0; j < 128 * side; ++j)
        for (int i = 0; i < 128 * side; ++i) {
            const double ux = -ext - 0.5 + (i + 0.5) / 128, uy = -ext - 0.5 + (j + 0.5) / 128;
            if (ux * ux + uy * uy > rad * rad) continue;
            const int x0 = static_cast<int>(std::floor(ux)), y0 = static_cast<int>(std::floor(uy));
            for (int dy = y0 - 1; dy <= y0 + 2; ++dy)
                for (int dx = x0 - 1; dx <= x0 + 2; ++dx) {
                    const double w = keys(dx - ux) * keys(dy - uy);
                    k[(dy + ext) * side + dx + ext] += w;
                    sum += w;
                }
        }
    double worst = 0;
    for (int y = ext; y < 64 - ext; ++y)
        for (int x = ext; x < 96 - ext; ++x) {
            double s = 0;
            for (int dy = -ext; dy <= ext; ++dy)
                for (int dx = -ext; dx <= ext; ++dx)
                    s += k[(dy + ext) * side + dx + ext] * sharp.at(x + dx, y + dy);
            worst = std::max(worst, std::abs(s / sum - img.at(x, y)));
        }
    // Sampling of the disc's rim differs (128² points against an exact chord): a few
    // hundredths of a grey level.
    INFO("largest difference " << worst << " grey levels");
    REQUIRE(worst < 0.05);
}

TEST_CASE("every scene renders with its depth layout") {
    SECTION("plane in focus renders the sharp texture but for diffraction") {
        auto r = renderer("scene=plane,distance=1.2m,focus=1.2m,size=160x90");
        const Image<float> sharp = r->sharpImage(), img = r->render(1.0 / 1.2);
        // σ = 0.01 px here: the core moves 0.03 % of each pixel to its neighbours, so less than
        // 0.1 % of the largest grey step (195 levels).
        REQUIRE(r->diffractionSigmaPx() == Approx(0.0103).epsilon(0.01));
        double worst = 0, mean = 0;
        for (int y = 0; y < 90; ++y)
            for (int x = 0; x < 160; ++x) {
                const double e = std::abs(img.at(x, y) - sharp.at(x, y));
                worst = std::max(worst, e);
                mean += e / (160 * 90);
            }
        INFO("worst " << worst << ", mean " << mean);
        REQUIRE(worst < 0.2);
        REQUIRE(mean < 0.02);
        REQUIRE(mean > 0.0);
    }
    SECTION("steps: one depth per band, left to right") {
        auto r = renderer("scene=steps,size=200x100");
        const auto regions = r->regions(1 / 1.2);
        REQUIRE(regions.size() == 5);  // default 0.3 0.6 1.2 2.4 4.8 m
        REQUIRE(regions[0].depthM == Approx(0.3).epsilon(1e-6));
        REQUIRE(regions[4].depthM == Approx(4.8).epsilon(1e-6));
        REQUIRE(r->depthAtM(0, 50) == Approx(0.3).epsilon(1e-6));
        REQUIRE(r->depthAtM(199, 50) == Approx(4.8).epsilon(1e-6));
    }
    SECTION("tilted: depth grows down the image (axis x) or across it (axis y)") {
        auto rx = renderer("scene=tilted,tilt=30,axis=x,distance=1m,size=320x180");
        REQUIRE(rx->depthAtM(160, 10) < rx->depthAtM(160, 90));
        REQUIRE(rx->depthAtM(160, 90) < rx->depthAtM(160, 170));
        REQUIRE(rx->depthAtM(10, 90) == Approx(rx->depthAtM(300, 90)).epsilon(1e-6));
        // Centre row: the plane's distance on the axis (pixel centre is ½ px off axis).
        REQUIRE(rx->depthAtM(160, 90) == Approx(1.0).epsilon(1e-2));
        // Off axis: Z = d / (1 − tanθ·v), v = y_sensor / f (ray through the lens centre).
        const double v = (170 + 0.5 - 90) * (1.4e-6 * 4608 / 320) / kF;
        REQUIRE(rx->depthAtM(160, 170) ==
                Approx(1.0 / (1 - std::tan(30 * M_PI / 180) * v)).epsilon(1e-5));
        auto ry = renderer("scene=tilted,tilt=30,axis=y,distance=1m,size=320x180");
        REQUIRE(ry->depthAtM(10, 90) < ry->depthAtM(310, 90));
        REQUIRE(ry->regions(1.0).size() == 16 * 9);
        const Image<float> img = ry->render(1.0);
        REQUIRE(img.width() == 320);
    }
    SECTION("edges: two grey levels in the sharp chart") {
        auto r = renderer("scene=edges,size=320x240");
        const Image<float> sharp = r->sharpImage();
        int light = 0, dark = 0;
        for (int y = 0; y < 240; ++y)
            for (int x = 0; x < 320; ++x) {
                light += sharp.at(x, y) > 203.9f;
                dark += sharp.at(x, y) < 51.1f;
            }
        REQUIRE(light > 320 * 240 / 2);  // squares cover a quarter of the chart
        REQUIRE(dark > 320 * 240 / 8);
    }
}

TEST_CASE("sim: source frames, focus control with one settle frame, determinism") {
    auto s = openSim(
        "sim:scene=plane,distance=0.5m,focus=0.5m,size=64x48,pace=fast,noise=0.01,focal=25mm,delay="
        "1,"
        "fnumber=1.4");
    REQUIRE(s.ok());
    FrameSource& src = **s;
    REQUIRE(src.info().format == PixelFormat::GREY);
    FocusControl* focus = src.focusControl();
    REQUIRE(focus != nullptr);
    REQUIRE(focus->range().unit == "dioptre");
    REQUIRE(focus->settleFrames() == 1);
    REQUIRE(src.start().ok());
    auto f0 = src.next();
    REQUIRE(f0.ok());
    REQUIRE(f0->lens->unit == "dioptre");
    REQUIRE(*f0->lens->dioptres == Approx(2.0).epsilon(1e-12));
    REQUIRE(focus->set(0.5).ok());
    auto f1 = src.next();  // the settle frame: still the old position
    auto f2 = src.next();
    REQUIRE(f1->lens->value == Approx(2.0).epsilon(1e-12));
    REQUIRE(f2->lens->value == Approx(0.5).epsilon(1e-12));
    REQUIRE(f2->sequence == 2);
    // 30 fps default; timestamps are rounded to whole ns, so a step may be 1 ns longer.
    REQUIRE(std::abs(f2->timestampNs - f1->timestampNs - 33'333'333) <= 1);
    // Defocus lowers the image's contrast: the sum of absolute horizontal differences drops.
    const auto activity = [](const Frame& f) {
        double a = 0;
        for (int y = 0; y < f.size.height; ++y)
            for (int x = 1; x < f.size.width; ++x)
                a += std::abs(f.planes[0].data[y * f.planes[0].stride + x] -
                              f.planes[0].data[y * f.planes[0].stride + x - 1]);
        return a;
    };
    REQUIRE(activity(*f2) < 0.7 * activity(*f1));
    REQUIRE(focus->set(50.0).ok());  // clamped to the range
    REQUIRE(focus->get()->value == Approx(10.0).epsilon(1e-12));

    // Same seed, same frames; another seed, another texture.
    auto a = openSim("sim:size=64x48,pace=fast,noise=0.02,seed=3");
    auto b = openSim("sim:size=64x48,pace=fast,noise=0.02,seed=3");
    auto c = openSim("sim:size=64x48,pace=fast,noise=0.02,seed=4");
    REQUIRE(((*a)->start().ok() && (*b)->start().ok() && (*c)->start().ok()));
    for (int i = 0; i < 3; ++i) {
        auto fa = (*a)->next(), fb = (*b)->next(), fc = (*c)->next();
        REQUIRE(std::memcmp(fa->planes[0].data, fb->planes[0].data, 64 * 48) == 0);
        REQUIRE(std::memcmp(fa->planes[0].data, fc->planes[0].data, 64 * 48) != 0);
    }
}

TEST_CASE("the default lens is the rpi-cam3 preset") {
    const optics::LensPreset* cam3 = optics::findLensPreset("rpi-cam3");
    REQUIRE(cam3 != nullptr);
    const SimLens lens;
    CHECK(lens.focalLengthM == cam3->focalLength);
    CHECK(lens.fNumber == cam3->fNumber);
    CHECK(lens.sensorPixelPitchM == cam3->pixelPitch);
    CHECK(lens.sensorSize.width == cam3->sensorWidthPx);
    CHECK(lens.sensorSize.height == cam3->sensorHeightPx);
    CHECK(SimConfig{}.lens.focalLengthM == cam3->focalLength);
}

TEST_CASE("sim: YUYV output, options and errors") {
    auto s = openSim("sim:size=32x16,format=YUYV,pace=fast");
    REQUIRE(s.ok());
    REQUIRE((*s)->start().ok());
    auto f = (*s)->next();
    REQUIRE(f->format == PixelFormat::YUYV);
    REQUIRE(f->planes[0].data[1] == 128);
    for (const char* bad : {"sim:scene=cube", "sim:focus=1.2", "sim:size=12", "sim:tilt=85",
                            "sim:colour=red", "sim:distance=-1m", "sim:noise=2",
                            // A rate whose frame period overflows int64 nanoseconds: the second
                            // frame was stamped -9223372036854775808 ns.
                            "sim:fps=1e-300", "sim:fps=1e9"}) {
        INFO(bad);
        auto e = openSim(bad);
        REQUIRE(!e.ok());
        REQUIRE(e.error().kind == ErrorKind::Usage);
        REQUIRE_THAT(e.error().message, Catch::Contains("sim:"));
    }
}

TEST_CASE("sim: numeric options out of range are usage errors naming the option") {
    for (const char* bad :
         {"seed=18446744073709551616", "seed=1.5", "size=30x20", "size=99999999999x20", "angle=nan",
          "angle=inf", "tilt=nan", "tilt=-inf", "fnumber=1e300", "pitch=1e-300m", "sensor=1x1",
          "focus=1e300dpt", "focus=1mm"}) {
        INFO(bad);
        auto spec = parseSourceSpec(std::string("sim:") + bad);
        REQUIRE(spec.ok());
        auto c = parseSimOptions(spec->options);
        REQUIRE(!c.ok());
        REQUIRE(c.error().kind == ErrorKind::Usage);
        const std::string option(bad);
        REQUIRE_THAT(c.error().message, Catch::Contains(option));
    }
    // The largest seed is read exactly, not rounded to a double.
    auto spec = parseSourceSpec("sim:seed=18446744073709551615");
    REQUIRE(spec.ok());
    auto c = parseSimOptions(spec->options);
    REQUIRE(c.ok());
    REQUIRE(c->seed == UINT64_MAX);
}
