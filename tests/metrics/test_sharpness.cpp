// SPDX-License-Identifier: MIT
// Focus measure operators: monotonic in blur, independent of resolution and region size,
// invariant to gain, vectorised kernel equal to the reference one, and right on real focus stacks.
#include <catch2/catch.hpp>
#include <climits>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <string>
#include <vector>

#include "infocus/metrics.h"

using namespace infocus;

namespace {

const std::string kData = INFOCUS_DATA_DIR;

// Wraps an 8-bit OpenCV matrix (kept alive by the caller) as luma.
Luma8 view(const cv::Mat& m) {
    return Luma8{m.ptr<uint8_t>(), m.cols, m.rows, static_cast<ptrdiff_t>(m.step), nullptr};
}

// A texture of random-phase, random-orientation sinusoids whose frequencies are given in cycles
// per image width, rendered analytically so the same scene exists exactly at any resolution.
cv::Mat sinusoidScene(int w, int h, double fMin, double fMax, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(0, 1);
    struct Wave {
        double fx, fy, phase, amp;
    };
    std::vector<Wave> waves;
    for (int i = 0; i < 24; ++i) {
        const double f = fMin + (fMax - fMin) * uni(rng), th = M_PI * uni(rng);
        waves.push_back({f * std::cos(th), f * std::sin(th), 2 * M_PI * uni(rng), 1.0});
    }
    cv::Mat m(h, w, CV_8U);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            // Pixel centres in units of the image width, so both renders sample one scene.
            const double u = (x + 0.5) / w, v = (y + 0.5) / w;
            double s = 0;
            for (const auto& wv : waves)
                s += std::sin(2 * M_PI * (wv.fx * u + wv.fy * v) + wv.phase);
            m.at<uint8_t>(y, x) = cv::saturate_cast<uint8_t>(128 + 22 * s);
        }
    return m;
}

// Natural-like texture: white noise shaped to a 1/f amplitude spectrum by summing octaves.
cv::Mat octaveTexture(int w, int h, unsigned seed) {
    cv::Mat acc(h, w, CV_32F, cv::Scalar(0));
    cv::RNG rng(seed);
    for (int o = 0; o < 6; ++o) {
        const int cw = std::max(2, w >> o), ch = std::max(2, h >> o);
        cv::Mat n(ch, cw, CV_32F);
        rng.fill(n, cv::RNG::NORMAL, 0, 1);
        cv::Mat up;
        cv::resize(n, up, cv::Size(w, h), 0, 0, cv::INTER_CUBIC);
        acc += up;
    }
    cv::Mat out;
    cv::normalize(acc, acc, 20, 235, cv::NORM_MINMAX);
    acc.convertTo(out, CV_8U);
    return out;
}

cv::Mat checkerboard(int w, int h, int square) {
    cv::Mat m(h, w, CV_8U);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            m.at<uint8_t>(y, x) = ((x / square + y / square) & 1) ? 220 : 35;
    return m;
}

// The sharp centre of a real focus-stack frame (the switch top of depthmap/pcb_006).
cv::Mat realPhoto() {
    cv::Mat img = cv::imread(kData + "/focus-stack/depthmap/pcb_006.JPG", cv::IMREAD_GRAYSCALE);
    REQUIRE_FALSE(img.empty());
    return img(cv::Rect(624, 468, 800, 600)).clone();
}

cv::Mat gaussian(const cv::Mat& src, double sigma) {
    cv::Mat f, out;
    src.convertTo(f, CV_32F);
    cv::GaussianBlur(f, f, cv::Size(0, 0), sigma, sigma, cv::BORDER_REFLECT);
    f.convertTo(out, CV_8U);
    return out;
}

}  // namespace

TEST_CASE("operator names parse and unknown names are usage errors", "[sharpness]") {
    for (FocusOperator op : allOperators()) {
        auto p = parseOperator(operatorName(op));
        REQUIRE(p.ok());
        CHECK(*p == op);
    }
    CHECK(*parseOperator("LAPV") == FocusOperator::Lapv);
    auto bad = parseOperator("sobelish");
    REQUIRE_FALSE(bad.ok());
    CHECK(bad.error().kind == ErrorKind::Usage);
    CHECK(bad.error().message.find("lapv") != std::string::npos);
}

TEST_CASE("a region reaching past INT_MAX is clipped to the image, not wrapped", "[sharpness]") {
    // x + w of such a rectangle overflowed and the region came out empty (or worse).
    const cv::Mat img = checkerboard(320, 240, 12);
    const Luma8 v = view(img);
    for (FocusOperator op : allOperators()) {
        INFO(operatorName(op));
        SharpnessParams p;
        p.op = op;
        const double far = regionSharpness(v, Rect{100, 50, INT_MAX, INT_MAX}, p);
        const double clipped = regionSharpness(v, Rect{100, 50, 220, 190}, p);
        CHECK(clipped > 0.0);
        CHECK(far == clipped);
    }
}

TEST_CASE("grid regions tile the image exactly", "[sharpness]") {
    const auto g = gridRegions(1921, 1081, 16, 9);
    REQUIRE(g.size() == 144u);
    long area = 0;
    for (const Rect& r : g) {
        area += long(r.w) * r.h;
        CHECK(r.w >= 120);
        CHECK(r.w <= 121);
    }
    CHECK(area == 1921L * 1081);
    CHECK(g.back().x + g.back().w == 1921);
    CHECK(gridRegions(10, 10, 0, 3).empty());
    CHECK(gridRegions(10, 10, 11, 3).empty());
}

TEST_CASE("every operator falls strictly as Gaussian blur grows (σ 0.5 to 8 px)", "[sharpness]") {
    const std::vector<double> sigmas = {0.5, 0.75, 1, 1.5, 2, 3, 4, 5.5, 8};
    struct Texture {
        const char* name;
        cv::Mat img;
    };
    const std::vector<Texture> textures = {{"1/f texture", octaveTexture(640, 480, 7)},
                                           {"checkerboard", checkerboard(640, 480, 37)},
                                           {"real photograph", realPhoto()}};
    for (const auto& t : textures) {
        for (FocusOperator op : allOperators()) {
            INFO(t.name << ", " << operatorName(op));
            SharpnessParams p;
            p.op = op;
            // The renders are rounded to 8 bits (uniform noise, variance 1/12). DCTR is a ratio
            // whose high band that noise takes over at large blur, so it is told the noise; the
            // others are tested raw (with it, LAPV of the photograph reaches its floor 0 at σ 4).
            if (op == FocusOperator::Dctr) p.noiseSigma = std::sqrt(1.0 / 12);
            // The region stays clear of the border, where blur sees the reflected edge.
            const Rect roi{40, 40, t.img.cols - 80, t.img.rows - 80};
            double previous = INFINITY;
            for (double s : sigmas) {
                const cv::Mat b = gaussian(t.img, s);
                const double v = regionSharpness(view(b), roi, p);
                INFO("sigma " << s << ": " << v << " (previous " << previous << ")");
                CHECK(v < previous);
                CHECK(v >= 0.0);
                previous = v;
            }
        }
    }
}

TEST_CASE("scores do not depend on resolution or region size", "[sharpness]") {
    // One scene at 1280x720 and 640x360: content from 8 to 40 cycles per image width, i.e. at
    // most 0.0625 cycles/px at the lower resolution, where the discrete operators still follow
    // the continuous derivatives.
    const cv::Mat hi = sinusoidScene(1280, 720, 8, 40, 3);
    const cv::Mat lo = sinusoidScene(640, 360, 8, 40, 3);
    const auto gHi = gridRegions(1280, 720, 4, 3), gLo = gridRegions(640, 360, 4, 3);
    // First-derivative and variance operators only: at the higher resolution a Laplacian's signal
    // falls 16-fold per pixel while 8-bit rounding noise does not, so LAPV, LAPM and TENV are
    // resolution-normalised in expectation but not to 5 % in 8 bits (see metrics.h).
    for (FocusOperator op : {FocusOperator::Teng, FocusOperator::Brenner, FocusOperator::Glvn}) {
        SharpnessParams p;
        p.op = op;
        // 8-bit rounding adds uniform noise of variance 1/12 at both resolutions.
        p.noiseSigma = std::sqrt(1.0 / 12);
        std::vector<double> a(gHi.size()), b(gLo.size());
        sharpness(view(hi), gHi, p, a);
        sharpness(view(lo), gLo, p, b);
        for (size_t i = 0; i < a.size(); ++i) {
            INFO(operatorName(op) << " region " << i << ": " << a[i] << " vs " << b[i]);
            CHECK(a[i] > 0);
            CHECK(std::abs(a[i] - b[i]) <= 0.05 * std::max(a[i], b[i]));
        }
    }
    // Region size: a 2x2 grid's scores average to the same as the whole frame within 5 % on a
    // homogeneous texture (a mean, not a sum).
    SharpnessParams p;
    const double whole = regionSharpness(view(hi), {0, 0, 1280, 720}, p);
    const auto g2 = gridRegions(1280, 720, 2, 2);
    std::vector<double> q(4);
    sharpness(view(hi), g2, p, q);
    CHECK(std::abs((q[0] + q[1] + q[2] + q[3]) / 4 - whole) <= 0.05 * whole);
}

TEST_CASE("scores are invariant to a gain on the signal", "[sharpness]") {
    const cv::Mat base = octaveTexture(320, 240, 11);
    cv::Mat dim;
    base.convertTo(dim, CV_8U, 0.5);  // half the exposure
    for (FocusOperator op : allOperators()) {
        SharpnessParams p;
        p.op = op;
        const Rect roi{0, 0, 320, 240};
        const double a = regionSharpness(view(base), roi, p);
        const double b = regionSharpness(view(dim), roi, p);
        INFO(operatorName(op) << ": " << a << " vs " << b);
        // Rounding the halved image to 8 bits costs a few per cent on derivative operators.
        CHECK(std::abs(a - b) <= 0.08 * a);
    }
}

TEST_CASE("the AVX2 kernels equal the reference implementation", "[sharpness][simd]") {
    std::vector<cv::Mat> images = {octaveTexture(1920, 1080, 5), realPhoto()};
    cv::Mat noise(333, 517, CV_8U);
    cv::randu(noise, 0, 256);
    images.push_back(noise);
    for (const cv::Mat& img : images) {
        const auto grid = gridRegions(img.cols, img.rows, 16, 9);
        std::vector<Rect> regions(grid.begin(), grid.end());
        regions.push_back({0, 0, img.cols, img.rows});  // touches every border
        regions.push_back({3, 5, 37, 2});               // narrower than a vector
        regions.push_back({img.cols - 50, 0, 80, 30});  // partly outside
        // Every strip combination: 32 + 16, 16 + masked 16, masked 16 alone, below 16 columns.
        for (int w : {48, 20, 17, 15})
            regions.push_back({101, 7, w, 300});
        for (FocusOperator op : allOperators())
            for (double noiseSigma : {0.0, 1.5}) {
                SharpnessParams simd, plain;
                simd.op = plain.op = op;
                simd.noiseSigma = plain.noiseSigma = noiseSigma;
                plain.simd = false;
                for (const Rect& r : regions) {
                    const double a = regionSharpness(view(img), r, simd);
                    const double b = regionSharpness(view(img), r, plain);
                    INFO(r.x << "," << r.y << " " << r.w << "x" << r.h << ": " << a << " vs " << b);
                    // Integer pixel sums: equal to double rounding. DCTR transforms its nine
                    // low-frequency coefficients in float (rounding 6e-8 of their energy), which
                    // can be up to ~100× the high-frequency energy in a smooth region: 1e-5.
                    // TENV squares G in float (6e-8 each, 16 float additions before doubles),
                    // and its variance can be a few times smaller than E[G²]: 1e-6.
                    const double tol = op == FocusOperator::Dctr   ? 1e-5
                                       : op == FocusOperator::Tenv ? 1e-6
                                                                   : 1e-9;
                    CHECK(a == Approx(b).epsilon(tol).margin(1e-15));
                }
            }
    }
}

TEST_CASE("noise estimate recovers added white noise", "[sharpness][noise]") {
    // A smooth 1/f scene with Gaussian noise of known σ: estimate within 15 %.
    const cv::Mat base = gaussian(octaveTexture(960, 540, 2), 2.0);
    for (double sigma : {2.0, 5.0}) {
        cv::Mat f, noisy;
        base.convertTo(f, CV_32F);
        cv::Mat n(f.size(), CV_32F);
        cv::randn(n, 0, sigma);
        f += n;
        f.convertTo(noisy, CV_8U);
        const double est = estimateNoiseSigma(view(noisy)).value_or(0.0);
        INFO("true " << sigma << " estimated " << est);
        CHECK(est == Approx(sigma).epsilon(0.15));
        // The vectorised sums are exact integers: the same estimate to double rounding, also on
        // a frame whose grid regions end in a partial vector (930 / 16 = 58.1 px).
        CHECK(est == Approx(estimateNoiseSigma(view(noisy), false).value_or(-1)).epsilon(1e-12));
        const cv::Mat odd = noisy(cv::Rect(3, 1, 930, 533)).clone();
        CHECK(estimateNoiseSigma(view(odd)).value_or(0.0) ==
              Approx(estimateNoiseSigma(view(odd), false).value_or(-1)).epsilon(1e-12));
    }
    // Noise compensation: LAPV of noisy and clean frames agree far better with it than without.
    cv::Mat f, noisy;
    base.convertTo(f, CV_32F);
    cv::Mat n(f.size(), CV_32F);
    cv::randn(n, 0, 3.0);
    f += n;
    f.convertTo(noisy, CV_8U);
    SharpnessParams clean, raw, comp;
    clean.op = raw.op = comp.op = FocusOperator::Lapv;
    comp.noiseSigma = estimateNoiseSigma(view(noisy)).value_or(0.0);
    const Rect roi{0, 0, 960, 540};
    const double truth = regionSharpness(view(base), roi, clean);
    const double without = regionSharpness(view(noisy), roi, raw);
    const double with = regionSharpness(view(noisy), roi, comp);
    INFO("clean " << truth << " noisy " << without << " compensated " << with);
    CHECK(std::abs(with - truth) < 0.25 * std::abs(without - truth));
}

TEST_CASE("whole-frame score: area mean, and centre weighting favours a sharp centre",
          "[sharpness]") {
    // Sharp texture in the middle third, the same texture blurred (σ 4) around it.
    const cv::Mat sharp = octaveTexture(960, 540, 21);
    cv::Mat img = gaussian(sharp, 4.0);
    const cv::Rect centre(320, 180, 320, 180);
    sharp(centre).copyTo(img(centre));
    SharpnessParams p;
    const auto regions = gridRegions(960, 540, 3, 3);
    std::vector<double> s(regions.size());
    sharpness(view(img), regions, p, s);
    double mean = 0;
    for (double v : s)
        mean += v / 9;  // equal areas: the area mean is the plain mean
    CHECK(combineScores(regions, s, 960, 540, false) == Approx(mean).epsilon(1e-12));
    const double weighted = combineScores(regions, s, 960, 540, true);
    CHECK(weighted > 1.2 * mean);
    CHECK(weighted < s[4]);
    CHECK(frameSharpness(view(img), p, true) > frameSharpness(view(img), p, false));
    CHECK(combineScores({}, {}, 960, 540, true) == 0.0);
}
