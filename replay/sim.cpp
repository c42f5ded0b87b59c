// SPDX-License-Identifier: MIT
// The simulated camera: scene textures, per-pixel depth, and disc-PSF rendering.
//
// Defocus model (lecture 5, thin lens): a point at depth z_o images to a uniform disc of
// diameter ΔX_i = A·|z_s(1/f − 1/z_o) − 1| with A = f/N and z_s the sensor distance for the focus
// setting (1/z_s = 1/f − 1/u). The disc is converted to output pixels with the pixel pitch and
// integrated over each pixel's area, so the rendered edge has the disc's 10–90 % rise of
// 0.68705·d (convolved with the 1-pixel box of the sensor).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <random>
#include <thread>

#include "infocus/sim.h"
#include "infocus/source.h"
#include "replay/playback.h"
#include "replay/replay_sources.h"

namespace infocus {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxLevel = static_cast<int>(kSimMaxDiameterPx / kSimDiameterStepPx);
// Texture padding so every disc tap stays inside the texture without bounds checks.
constexpr int kPad = static_cast<int>(kSimMaxDiameterPx / 2) + 2;

// A disc kernel split for the renderer: fully covered pixels of each row as runs summed with row
// prefix sums (one subtraction per row), partially covered pixels as individual taps.
struct Kernel {
    struct Run {
        int dy, a, b;  // columns a..b of row dy are fully inside the disc
    };
    struct Tap {
        int dy, dx;
        double w;
    };
    double fullWeight = 0.0;  // weight of a fully covered pixel (1 / disc area in pixels)
    std::vector<Run> runs;
    std::vector<Tap> taps;
};

// Fraction of the pixel square centred at (cx, cy) covered by the disc of radius r at the origin.
double pixelCoverage(double cx, double cy, double r) {
    const double nx = std::max(0.0, std::abs(cx) - 0.5), ny = std::max(0.0, std::abs(cy) - 0.5);
    if (nx * nx + ny * ny >= r * r) return 0.0;
    const double fx = std::abs(cx) + 0.5, fy = std::abs(cy) + 0.5;
    if (fx * fx + fy * fy <= r * r) return 1.0;
    // Boundary pixel: integrate the area numerically on a 64×64 grid of sub-pixel samples.
    constexpr int kSub = 64;
    int inside = 0;
    for (int j = 0; j < kSub; ++j) {
        const double y = cy - 0.5 + (j + 0.5) / kSub;
        for (int i = 0; i < kSub; ++i) {
            const double x = cx - 0.5 + (i + 0.5) / kSub;
            inside += x * x + y * y <= r * r;
        }
    }
    return static_cast<double>(inside) / (kSub * kSub);
}

Kernel makeKernel(double diameterPx) {
    Kernel k;
    const double r = diameterPx / 2;
    if (r < 1e-9) {
        k.taps.push_back({0, 0, 1.0});
        return k;
    }
    const int ext = static_cast<int>(std::ceil(r + 0.5));
    std::vector<double> cov((2 * ext + 1) * (2 * ext + 1));
    double total = 0.0;
    for (int dy = -ext; dy <= ext; ++dy)
        for (int dx = -ext; dx <= ext; ++dx) {
            const double c = pixelCoverage(dx, dy, r);
            cov[(dy + ext) * (2 * ext + 1) + dx + ext] = c;
            total += c;
        }
    k.fullWeight = 1.0 / total;
    for (int dy = -ext; dy <= ext; ++dy) {
        int a = INT32_MAX, b = INT32_MIN;
        for (int dx = -ext; dx <= ext; ++dx) {
            const double c = cov[(dy + ext) * (2 * ext + 1) + dx + ext];
            if (c >= 1.0) {
                a = std::min(a, dx);
                b = std::max(b, dx);
            } else if (c > 0.0) {
                k.taps.push_back({dy, dx, c / total});
            }
        }
        if (a <= b) k.runs.push_back({dy, a, b});
    }
    return k;
}

// Small deterministic generator (splitmix64) so scenes do not depend on the standard library's
// distribution implementations.
struct SplitMix {
    uint64_t s;
    uint64_t next() {
        uint64_t z = (s += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
};

}  // namespace

std::optional<double> simSensorDistanceM(const SimLens& lens, double focusDioptres) {
    const double inv = 1.0 / lens.focalLengthM - focusDioptres;
    if (inv <= 0) return std::nullopt;
    return 1.0 / inv;
}

std::optional<double> simBlurDiameterM(const SimLens& lens, double focusDioptres, double depthM) {
    auto zs = simSensorDistanceM(lens, focusDioptres);
    if (!zs || depthM <= 0) return std::nullopt;
    return lens.apertureM() * std::abs(*zs * (1.0 / lens.focalLengthM - 1.0 / depthM) - 1.0);
}

struct SimRenderer::Impl {
    int w = 0, h = 0, wp = 0, hp = 0;  // output and padded texture sizes
    std::vector<float> texture;        // padded, grey levels
    std::vector<double> prefix;        // per padded row: wp + 1 prefix sums
    std::vector<float> depth;          // per output pixel, metres
    std::vector<std::unique_ptr<Kernel>> kernels =
        std::vector<std::unique_ptr<Kernel>>(kMaxLevel + 1);

    const Kernel& kernel(int level) {
        if (!kernels[level])
            kernels[level] = std::make_unique<Kernel>(makeKernel(level * kSimDiameterStepPx));
        return *kernels[level];
    }
};

SimRenderer::~SimRenderer() = default;

double SimRenderer::inFocusDistanceM(double focusDioptres) {
    return focusDioptres > 0 ? 1.0 / focusDioptres : INFINITY;
}

namespace {

// Dead-leaves texture: overlapping discs with log-uniform radii and random grey levels; it has
// edges at every orientation and scale, like natural scenes.
void paintDeadLeaves(std::vector<float>& t, int wp, int hp, int outWidth, uint64_t seed) {
    SplitMix rng{seed};
    const double rMin = std::max(1.5, outWidth / 400.0), rMax = outWidth / 20.0;
    // Mean disc area of log-uniform radii: π (rMax² − rMin²) / (2 ln(rMax/rMin)); cover ~3×.
    const double meanArea = kPi * (rMax * rMax - rMin * rMin) / (2 * std::log(rMax / rMin));
    const int count = static_cast<int>(3.0 * wp * hp / meanArea) + 1;
    std::fill(t.begin(), t.end(), 128.0f);
    for (int n = 0; n < count; ++n) {
        const double r = rMin * std::pow(rMax / rMin, rng.uniform());
        const double cx = rng.uniform() * wp, cy = rng.uniform() * hp;
        const float grey = static_cast<float>(30.0 + 195.0 * rng.uniform());
        const int x0 = std::max(0, static_cast<int>(cx - r - 1));
        const int x1 = std::min(wp - 1, static_cast<int>(cx + r + 1));
        const int y0 = std::max(0, static_cast<int>(cy - r - 1));
        const int y1 = std::min(hp - 1, static_cast<int>(cy + r + 1));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const double dist = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
                // Coverage of the pixel by the disc edge, linear across one pixel.
                const double a = std::clamp(r + 0.5 - dist, 0.0, 1.0);
                if (a > 0) {
                    float& p = t[static_cast<size_t>(y) * wp + x];
                    p = static_cast<float>(p + a * (grey - p));
                }
            }
    }
}

// Slanted-edge chart: dark squares (side = half the period) on a light ground, rotated by
// @p angleDeg about the image centre. Coverage is the product of the per-axis coverages, exact
// for axis-aligned edges (angle 0, where edges fall on pixel boundaries).
void paintEdges(std::vector<float>& t, int wp, int hp, int pad, int outW, int outH,
                double angleDeg) {
    const double period = std::max(16, 2 * (outW / 16));
    const double half = period / 4;  // half the side of a square
    const double c = std::cos(angleDeg * kPi / 180), s = std::sin(angleDeg * kPi / 180);
    const double ox = pad + outW / 2.0, oy = pad + outH / 2.0;
    const float light = 204.0f, dark = 51.0f;
    for (int y = 0; y < hp; ++y)
        for (int x = 0; x < wp; ++x) {
            const double px = x + 0.5 - ox, py = y + 0.5 - oy;
            const double u = c * px + s * py, v = -s * px + c * py;
            // Position within the cell, centred on a square centre at (period/2, period/2).
            const double lu = u - period * std::floor(u / period) - period / 2;
            const double lv = v - period * std::floor(v / period) - period / 2;
            const double cu = std::clamp(half - std::abs(lu) + 0.5, 0.0, 1.0);
            const double cv = std::clamp(half - std::abs(lv) + 0.5, 0.0, 1.0);
            const double a = cu * cv;
            t[static_cast<size_t>(y) * wp + x] = static_cast<float>(light + a * (dark - light));
        }
}

}  // namespace

Result<std::unique_ptr<SimRenderer>> SimRenderer::create(const SimConfig& config) {
    const auto bad = [](const std::string& why) -> Error {
        return makeError(ErrorKind::Usage, "sim: " + why);
    };
    if (config.size.width < 16 || config.size.height < 16 || config.size.width > 8192 ||
        config.size.height > 8192)
        return bad("size must be between 16x16 and 8192x8192");
    if (config.distancesM.empty()) return bad("no scene distance given");
    for (double d : config.distancesM)
        if (!(d > config.lens.focalLengthM))
            return bad("scene distances must exceed the focal length");
    if (!(config.lens.focalLengthM > 0) || !(config.lens.fNumber > 0) ||
        !(config.lens.sensorPixelPitchM > 0))
        return bad("focal length, f-number and pixel pitch must be positive");
    if (std::abs(config.tiltDeg) >= 80) return bad("tilt must be within ±80 degrees");

    std::unique_ptr<SimRenderer> r(new SimRenderer);
    r->config_ = config;
    r->impl_ = std::make_unique<Impl>();
    Impl& m = *r->impl_;
    m.w = config.size.width;
    m.h = config.size.height;
    m.wp = m.w + 2 * kPad;
    m.hp = m.h + 2 * kPad;
    m.texture.resize(static_cast<size_t>(m.wp) * m.hp);
    if (config.scene == SimScene::Edges)
        paintEdges(m.texture, m.wp, m.hp, kPad, m.w, m.h, config.edgeAngleDeg);
    else
        paintDeadLeaves(m.texture, m.wp, m.hp, m.w, config.seed);

    // Row prefix sums let a run of fully covered disc pixels be summed with one subtraction.
    m.prefix.resize(static_cast<size_t>(m.wp + 1) * m.hp);
    for (int y = 0; y < m.hp; ++y) {
        double* p = &m.prefix[static_cast<size_t>(y) * (m.wp + 1)];
        const float* t = &m.texture[static_cast<size_t>(y) * m.wp];
        p[0] = 0;
        for (int x = 0; x < m.wp; ++x)
            p[x + 1] = p[x] + t[x];
    }

    // Depth per output pixel. The tilted plane Z = d + tanθ·Y is intersected with the pixel's
    // ray through the lens centre (Y = Z·v, v the sensor coordinate over f).
    m.depth.resize(static_cast<size_t>(m.w) * m.h);
    const double pitch = config.lens.pixelPitchM(m.w);
    const double tanT = std::tan(config.tiltDeg * kPi / 180);
    const size_t bands = config.distancesM.size();
    for (int y = 0; y < m.h; ++y)
        for (int x = 0; x < m.w; ++x) {
            double z = config.distancesM[0];
            switch (config.scene) {
                case SimScene::Plane:
                case SimScene::Edges:
                    break;
                case SimScene::Steps:
                    z = config
                            .distancesM[std::min(bands - 1, static_cast<size_t>(x) * bands / m.w)];
                    break;
                case SimScene::Tilted: {
                    const double s = config.tiltAxis == SimAxis::X ? (y + 0.5 - m.h / 2.0)
                                                                   : (x + 0.5 - m.w / 2.0);
                    const double v = s * pitch / config.lens.focalLengthM;
                    // Beyond the plane's horizon the ray never meets it: clamp far away.
                    const double den = std::max(0.02, 1.0 - tanT * v);
                    z = config.distancesM[0] / den;
                    break;
                }
            }
            m.depth[static_cast<size_t>(y) * m.w + x] = static_cast<float>(z);
        }
    return r;
}

double SimRenderer::depthAtM(int x, int y) const {
    return impl_->depth[static_cast<size_t>(y) * impl_->w + x];
}

double SimRenderer::blurDiameterPxAt(int x, int y, double focusDioptres) const {
    auto d = simBlurDiameterM(config_.lens, focusDioptres, depthAtM(x, y));
    return d ? *d / config_.lens.pixelPitchM(config_.size.width) : kSimMaxDiameterPx;
}

double SimRenderer::renderedDiameterPxAt(int x, int y, double focusDioptres) const {
    const double d = blurDiameterPxAt(x, y, focusDioptres);
    const long level = std::min<long>(kMaxLevel, std::lround(d / kSimDiameterStepPx));
    return level * kSimDiameterStepPx;
}

std::vector<SimRegion> SimRenderer::regions(double focusDioptres) const {
    std::vector<SimRegion> out;
    const int w = config_.size.width, h = config_.size.height;
    const auto add = [&](Rect r) {
        const int cx = r.x + r.w / 2, cy = r.y + r.h / 2;
        out.push_back({r, depthAtM(cx, cy), blurDiameterPxAt(cx, cy, focusDioptres)});
    };
    switch (config_.scene) {
        case SimScene::Plane:
        case SimScene::Edges:
            add({0, 0, w, h});
            break;
        case SimScene::Steps: {
            const size_t n = config_.distancesM.size();
            for (size_t i = 0; i < n; ++i) {
                // Same band boundaries as the depth map: x·n/w selects band i.
                const int x0 = static_cast<int>((i * w + n - 1) / n);
                const int x1 = static_cast<int>(((i + 1) * w + n - 1) / n);
                add({x0, 0, x1 - x0, h});
            }
            break;
        }
        case SimScene::Tilted:
            for (int row = 0; row < 9; ++row)
                for (int col = 0; col < 16; ++col) {
                    const int x0 = col * w / 16, x1 = (col + 1) * w / 16;
                    const int y0 = row * h / 9, y1 = (row + 1) * h / 9;
                    add({x0, y0, x1 - x0, y1 - y0});
                }
            break;
    }
    return out;
}

Image<float> SimRenderer::sharpImage() const {
    const Impl& m = *impl_;
    Image<float> img(m.w, m.h);
    for (int y = 0; y < m.h; ++y)
        std::memcpy(img.row(y), &m.texture[static_cast<size_t>(y + kPad) * m.wp + kPad],
                    sizeof(float) * m.w);
    return img;
}

Image<float> SimRenderer::render(double focusDioptres) {
    Impl& m = *impl_;
    Image<float> out(m.w, m.h);
    const double pitch = config_.lens.pixelPitchM(m.w);
    const size_t pw = static_cast<size_t>(m.wp) + 1;
    // The level only changes where the depth does: recompute it only then.
    float lastDepth = -1.0f;
    int level = 0;
    for (int y = 0; y < m.h; ++y) {
        const float* depthRow = &m.depth[static_cast<size_t>(y) * m.w];
        float* o = out.row(y);
        const double* prow = &m.prefix[static_cast<size_t>(y + kPad) * pw + kPad];
        const float* trow = &m.texture[static_cast<size_t>(y + kPad) * m.wp + kPad];
        const Kernel* k = nullptr;
        for (int x = 0; x < m.w; ++x) {
            if (depthRow[x] != lastDepth || !k) {
                lastDepth = depthRow[x];
                auto d = simBlurDiameterM(config_.lens, focusDioptres, lastDepth);
                const double px = d ? *d / pitch : kSimMaxDiameterPx;
                level = static_cast<int>(
                    std::min<long>(kMaxLevel, std::lround(px / kSimDiameterStepPx)));
                k = &m.kernel(level);
            }
            double runs = 0.0;
            for (const auto& r : k->runs) {
                const double* p = prow + static_cast<ptrdiff_t>(r.dy) * static_cast<ptrdiff_t>(pw);
                runs += p[x + r.b + 1] - p[x + r.a];
            }
            double s = runs * k->fullWeight;
            for (const auto& t : k->taps)
                s += t.w * trow[static_cast<ptrdiff_t>(t.dy) * m.wp + x + t.dx];
            o[x] = static_cast<float>(s);
        }
    }
    return out;
}

Result<SimConfig> parseSimOptions(const std::map<std::string, std::string>& options) {
    SimConfig c;
    const auto bad = [](const std::string& key, const std::string& value,
                        const std::string& want) -> Error {
        return makeError(ErrorKind::Usage, "sim: option " + key + "=" + value + ": " + want);
    };
    // A length with a unit: m, cm, mm or um. A bare number is ambiguous and refused.
    const auto length = [](const std::string& v) -> std::optional<double> {
        static const std::pair<const char*, double> kUnits[] = {
            {"mm", 1e-3}, {"cm", 1e-2}, {"um", 1e-6}, {"m", 1.0}};
        for (const auto& [unit, scale] : kUnits) {
            const size_t n = std::strlen(unit);
            if (v.size() > n && v.compare(v.size() - n, n, unit) == 0) {
                auto num = replay::parseNumber(v.substr(0, v.size() - n));
                if (num && *num > 0) return *num * scale;
                return std::nullopt;
            }
        }
        return std::nullopt;
    };
    const auto sizeOf = [](const std::string& v) -> std::optional<Size> {
        int w = 0, h = 0;
        char x = 0;
        if (std::sscanf(v.c_str(), "%d%c%d", &w, &x, &h) != 3 || (x != 'x' && x != 'X') || w <= 0 ||
            h <= 0)
            return std::nullopt;
        return Size{w, h};
    };
    for (const auto& [key, value] : options) {
        if (key == "scene") {
            if (value == "plane")
                c.scene = SimScene::Plane;
            else if (value == "steps")
                c.scene = SimScene::Steps;
            else if (value == "tilted")
                c.scene = SimScene::Tilted;
            else if (value == "edges")
                c.scene = SimScene::Edges;
            else
                return bad(key, value, "use plane, steps, tilted or edges");
        } else if (key == "focus") {
            if (value == "inf") {
                c.focusDioptres = 0;
            } else if (value.size() > 3 && value.compare(value.size() - 3, 3, "dpt") == 0) {
                auto d = replay::parseNumber(value.substr(0, value.size() - 3));
                if (!d) return bad(key, value, "dioptres must be a number ≥ 0, e.g. 0.8dpt");
                c.focusDioptres = *d;
            } else if (auto m = length(value)) {
                c.focusDioptres = 1.0 / *m;
            } else {
                return bad(key, value, "give a distance with a unit (1.2m) or dioptres (0.8dpt)");
            }
        } else if (key == "distance") {
            auto m = length(value);
            if (!m) return bad(key, value, "give a distance with a unit, e.g. 1m or 80cm");
            c.distancesM = {*m};
        } else if (key == "distances") {
            c.distancesM.clear();
            size_t start = 0;
            while (start <= value.size()) {
                const size_t end = std::min(value.find(':', start), value.size());
                auto m = length(value.substr(start, end - start));
                if (!m) return bad(key, value, "give distances with units separated by ':'");
                c.distancesM.push_back(*m);
                start = end + 1;
            }
        } else if (key == "tilt" || key == "angle") {
            std::string v = value;
            if (v.size() > 3 && v.compare(v.size() - 3, 3, "deg") == 0) v.resize(v.size() - 3);
            char* end = nullptr;
            const double d = std::strtod(v.c_str(), &end);
            if (v.empty() || *end) return bad(key, value, "give an angle in degrees, e.g. 30");
            (key == "tilt" ? c.tiltDeg : c.edgeAngleDeg) = d;
        } else if (key == "axis") {
            if (value == "x")
                c.tiltAxis = SimAxis::X;
            else if (value == "y")
                c.tiltAxis = SimAxis::Y;
            else
                return bad(key, value, "use x or y");
        } else if (key == "size" || key == "sensor") {
            auto s = sizeOf(value);
            if (!s) return bad(key, value, "give WIDTHxHEIGHT, e.g. 1280x720");
            (key == "size" ? c.size : c.lens.sensorSize) = *s;
        } else if (key == "fps") {
            auto v = replay::parseNumber(value);
            if (!v || !(*v >= replay::kMinFps && *v <= replay::kMaxFps))
                return bad(key, value, "give a frame rate from 0.000001 to 1000000");
            c.fps = *v;
        } else if (key == "noise") {
            auto v = replay::parseNumber(value);
            if (!v || *v > 1) return bad(key, value, "give σ as a fraction of full scale, 0..1");
            c.noise = *v;
        } else if (key == "seed") {
            auto v = replay::parseNumber(value);
            if (!v || std::floor(*v) != *v) return bad(key, value, "give a non-negative integer");
            c.seed = static_cast<uint64_t>(*v);
        } else if (key == "format") {
            if (value == "GREY" || value == "grey")
                c.format = PixelFormat::GREY;
            else if (value == "YUYV" || value == "yuyv")
                c.format = PixelFormat::YUYV;
            else
                return bad(key, value, "use GREY or YUYV");
        } else if (key == "pace") {
            if (value == "camera")
                c.paced = true;
            else if (value == "fast")
                c.paced = false;
            else
                return bad(key, value, "use camera (real time at fps) or fast");
        } else if (key == "focal") {
            auto m = length(value);
            if (!m) return bad(key, value, "give a focal length with a unit, e.g. 4.74mm");
            c.lens.focalLengthM = *m;
        } else if (key == "fnumber") {
            auto v = replay::parseNumber(value);
            if (!v || *v <= 0) return bad(key, value, "give a positive f-number, e.g. 1.8");
            c.lens.fNumber = *v;
        } else if (key == "pitch") {
            auto m = length(value);
            if (!m) return bad(key, value, "give the sensor pixel pitch with a unit, e.g. 1.4um");
            c.lens.sensorPixelPitchM = *m;
        } else {
            return makeError(ErrorKind::Usage,
                             "sim: unknown option '" + key +
                                 "'; sim: takes scene, focus, distance, distances, tilt, axis, "
                                 "angle, size, fps, noise, seed, format, pace, focal, fnumber, "
                                 "pitch, sensor");
        }
    }
    if (c.scene == SimScene::Steps && !options.count("distances"))
        c.distancesM = {0.3, 0.6, 1.2, 2.4, 4.8};
    if (c.format == PixelFormat::YUYV && c.size.width % 2)
        return makeError(ErrorKind::Usage, "sim: format=YUYV needs an even width");
    return c;
}

namespace replay {

namespace {

constexpr double kSimMaxDioptres = 10.0;  // closest focus 10 cm, like small camera modules

// Lens control of the simulated camera, in dioptres. A move shows from the second frame after
// it (one settle frame, as a real lens needs time to move).
class SimFocus final : public FocusControl {
public:
    explicit SimFocus(double initial) : target_(initial), current_(initial) {}
    FocusRange range() const override {
        return FocusRange{0.0, kSimMaxDioptres, 0.0, initial(), "dioptre"};
    }
    Result<LensPosition> get() override { return LensPosition{target_, "dioptre", target_}; }
    Status set(double value) override {
        if (!std::isfinite(value))
            return makeError(ErrorKind::Usage, "sim: focus value must be a finite number");
        target_ = std::clamp(value, 0.0, kSimMaxDioptres);
        applyAt_ = nextSequence_ + 1;
        return {};
    }
    int settleFrames() const override { return 1; }

    // The focus for the frame numbered @p sequence; called once per frame in order.
    double forFrame(uint64_t sequence) {
        if (sequence >= applyAt_) current_ = target_;
        nextSequence_ = sequence + 1;
        return current_;
    }
    double initial() const { return initial_; }
    void setInitial(double v) { initial_ = v; }

private:
    double target_, current_, initial_ = 0;
    uint64_t applyAt_ = 0, nextSequence_ = 0;
};

class SimSource final : public FrameSource {
public:
    SimSource(std::unique_ptr<SimRenderer> renderer, std::string text)
        : renderer_(std::move(renderer)),
          text_(std::move(text)),
          focus_(renderer_->config().focusDioptres) {
        focus_.setInitial(renderer_->config().focusDioptres);
        const SimConfig& c = renderer_->config();
        if (c.noise > 0) {
            // A table of unit Gaussian samples indexed by a per-frame random stream: cheap per
            // pixel and deterministic for a seed (Box–Muller from splitmix64).
            SplitMix rng{c.seed ^ 0x5eedull};
            noise_.resize(1 << 16);
            for (float& n : noise_) {
                const double u1 = std::max(rng.uniform(), 1e-300), u2 = rng.uniform();
                n = static_cast<float>(std::sqrt(-2 * std::log(u1)) * std::cos(2 * kPi * u2) *
                                       c.noise * 255.0);
            }
        }
    }

    SourceInfo info() const override {
        const SimConfig& c = renderer_->config();
        SourceInfo i;
        i.sourceString = text_;
        i.device = "sim";
        i.driver = "sim";
        i.format = c.format;
        i.size = c.size;
        i.fps = c.fps;
        i.transfer = {TransferFunction::Linear, "the simulated camera renders linear light"};
        return i;
    }
    Status start() override {
        started_ = true;
        wallStart_ = std::chrono::steady_clock::now();
        startSeq_ = sequence_;
        return {};
    }
    Result<Frame> next() override {
        if (!started_) return makeError(ErrorKind::Usage, "sim: next() called before start()");
        const SimConfig& c = renderer_->config();
        const uint64_t seq = sequence_++;
        const double dioptres = focus_.forFrame(seq);
        if (!cached_ || cachedFocus_ != dioptres) {
            cachedImage_ = renderer_->render(dioptres);
            cachedFocus_ = dioptres;
            cached_ = true;
        }
        auto frame = allocateFrame(c.format, c.size);
        if (!frame) return frame.error();
        uint64_t state = c.seed * 0x9E3779B97F4A7C15ull + seq * 0xD1B54A32D192ED03ull + 1;
        const bool yuyv = c.format == PixelFormat::YUYV;
        for (int y = 0; y < c.size.height; ++y) {
            const float* in = cachedImage_.row(y);
            uint8_t* out = mutablePlane(*frame, 0) + y * frame->planes[0].stride;
            for (int x = 0; x < c.size.width; ++x) {
                float v = in[x];
                if (!noise_.empty()) {
                    // xorshift64 picks the next table entry.
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    v += noise_[state >> 48];
                }
                const auto q = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
                if (yuyv) {
                    out[2 * x] = q;
                    out[2 * x + 1] = 128;
                } else {
                    out[x] = q;
                }
            }
        }
        frame->sequence = seq;
        frame->timestampNs = replay::saturatedNs(static_cast<double>(seq) * 1e9 / c.fps);
        frame->lens = LensPosition{dioptres, "dioptre", dioptres};
        if (c.paced) {
            const auto due =
                wallStart_ +
                std::chrono::nanoseconds(static_cast<int64_t>((seq - startSeq_) * 1e9 / c.fps));
            std::this_thread::sleep_until(due);
        }
        ++stats_.delivered;
        return frame;
    }
    void stop() override { started_ = false; }
    SourceStats stats() const override { return stats_; }
    FocusControl* focusControl() override { return &focus_; }

private:
    std::unique_ptr<SimRenderer> renderer_;
    std::string text_;
    SimFocus focus_;
    std::vector<float> noise_;
    bool started_ = false;
    uint64_t sequence_ = 0, startSeq_ = 0;
    std::chrono::steady_clock::time_point wallStart_;
    bool cached_ = false;
    double cachedFocus_ = 0;
    Image<float> cachedImage_;
    SourceStats stats_;
};

}  // namespace

Result<std::unique_ptr<FrameSource>> openSimSource(const SourceSpec& spec) {
    auto config = parseSimOptions(spec.options);
    if (!config) return config.error();
    auto renderer = SimRenderer::create(*config);
    if (!renderer) return renderer.error();
    return std::unique_ptr<FrameSource>(
        std::make_unique<SimSource>(std::move(*renderer), spec.text));
}

}  // namespace replay

}  // namespace infocus
