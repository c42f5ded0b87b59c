// SPDX-License-Identifier: MIT
// The simulated camera's scenes: the sharp texture, the depth of every pixel, and the ground
// truth (depth, thin-lens blur diameter, in-focus distance) tests check measurements against.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <numbers>

#include "infocus/optics.h"
#include "renderer_impl.h"

namespace infocus {

using sim::kMaxLevel;
using sim::kPad;

std::optional<double> simBlurDiameterM(const SimLens& lens, double focusDioptres, double depthM) {
    if (!(depthM > 0)) return std::nullopt;
    auto zs = optics::sensorDistanceForFocus(lens.focalLengthM,
                                             SimRenderer::inFocusDistanceM(focusDioptres));
    if (!zs) return std::nullopt;
    return optics::blurWidth(lens.thinLens(), *zs, depthM);
}

SimRenderer::~SimRenderer() = default;

double SimRenderer::inFocusDistanceM(double focusDioptres) {
    return optics::distanceFromDioptres(focusDioptres);
}

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
    if (config.moveToM) {
        if (config.scene == SimScene::Steps)
            return bad("move= moves the plane of scene=plane, tilted or edges, not steps");
        if (!(*config.moveToM > config.lens.focalLengthM) || !(config.moveS > 0))
            return bad("move= needs a distance beyond the focal length and a time above 0");
    }

    std::unique_ptr<SimRenderer> r(new SimRenderer);
    r->config_ = config;
    r->impl_ = std::make_unique<Impl>();
    Impl& m = *r->impl_;
    m.w = config.size.width;
    m.h = config.size.height;
    const double pitch = config.lens.pixelPitchM(m.w);
    // Airy core as a Gaussian: σ = 0.42 λN = (0.42 / 2.44) × the Airy disc's diameter.
    m.sigmaPx =
        0.42 / 2.44 * optics::airyDiscDiameter(config.lens.fNumber, kSimWavelengthM) / pitch;
    // The widest kernel reaches the largest disc's radius plus the interpolation (2 px) and 5 σ,
    // at every scale of the fast render, with one grid point more for its interpolation; a
    // multiple of the largest scale, so that every scale's grid lines up with the output's.
    int reach = kPad;
    for (int k = 0; k < sim::kScales; ++k) {
        const int s = 1 << k;
        const int levelReach =
            static_cast<int>(std::ceil((kSimMaxDiameterPx / 2 + 5 * m.sigmaPx) / s)) + 2 + 2;
        reach = std::max(reach, levelReach * s);
    }
    m.pad = (reach + sim::kMaxScale - 1) / sim::kMaxScale * sim::kMaxScale;
    const int wp = m.w + 2 * m.pad, hp = m.h + 2 * m.pad;
    Image<float> texture(wp, hp);
    if (config.scene == SimScene::Edges) {
        // Squares of a sixteenth of the width, the chart centred in the output image.
        const double period = std::max(16, 2 * (m.w / 16));
        synth::paintSlantedSquaresPixels(texture, period, config.edgeAngleDeg, m.pad + m.w / 2.0,
                                         m.pad + m.h / 2.0, 51.0f, 204.0f);
    } else {
        // Painted with the fixed margin (the texture does not depend on the lens), then widened
        // by repeating its border.
        Image<float> leaves(m.w + 2 * kPad, m.h + 2 * kPad);
        synth::paintDeadLeavesPixels(leaves, config.seed, std::max(1.5, m.w / 400.0), m.w / 20.0);
        const int extra = m.pad - kPad;
        for (int y = 0; y < hp; ++y) {
            const float* src = leaves.row(std::clamp(y - extra, 0, leaves.height() - 1));
            float* dst = texture.row(y);
            for (int x = 0; x < wp; ++x)
                dst[x] = src[std::clamp(x - extra, 0, leaves.width() - 1)];
        }
    }

    // The reduced textures: each pixel the mean of a block of the full one (what a sensor of
    // larger pixels would integrate). Blocks past the padded texture repeat its border.
    for (int k = 0; k < sim::kScales; ++k) {
        Impl::Level& L = m.levels[k];
        const int s = 1 << k;
        L.scale = s;
        L.gw = (m.w + s - 1) / s;
        L.gh = (m.h + s - 1) / s;
        L.pad = m.pad / s;
        L.sigmaPx = m.sigmaPx / s;
        if (k == 0) {
            L.texture = std::move(texture);
        } else {
            const Image<float>& full = m.levels[0].texture;
            L.texture = Image<float>(L.gw + 2 * L.pad, L.gh + 2 * L.pad);
            const float norm = 1.0f / static_cast<float>(s * s);
            for (int y = 0; y < L.texture.height(); ++y) {
                float* dst = L.texture.row(y);
                for (int x = 0; x < L.texture.width(); ++x) {
                    float sum = 0;
                    for (int by = 0; by < s; ++by) {
                        const float* src = full.row(std::min(y * s + by, full.height() - 1));
                        for (int bx = 0; bx < s; ++bx)
                            sum += src[std::min(x * s + bx, full.width() - 1)];
                    }
                    dst[x] = sum * norm;
                }
            }
        }
        // Row prefix sums let a run of fully covered disc pixels be summed with one subtraction.
        const int tw = L.texture.width(), th = L.texture.height();
        L.prefix.resize(static_cast<size_t>(tw + 1) * th);
        for (int y = 0; y < th; ++y) {
            double* p = &L.prefix[static_cast<size_t>(y) * (tw + 1)];
            const float* t = L.texture.row(y);
            p[0] = 0;
            for (int x = 0; x < tw; ++x)
                p[x + 1] = p[x] + t[x];
        }
    }

    // Depth per output pixel. The tilted plane Z = d + tanθ·Y is intersected with the pixel's
    // ray through the lens centre (Y = Z·v, v the sensor coordinate over f).
    m.depthIndex.resize(static_cast<size_t>(m.w) * m.h);
    std::map<float, uint16_t> seen;
    float lastZ = -1;
    uint16_t lastIndex = 0;
    const double tanT = std::tan(config.tiltDeg * std::numbers::pi / 180);
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
            const auto zf = static_cast<float>(z);
            if (zf != lastZ) {
                // At most one depth per row or column: far fewer than 65536.
                auto [it, added] = seen.emplace(zf, static_cast<uint16_t>(m.depths.size()));
                if (added) m.depths.push_back(zf);
                lastZ = zf;
                lastIndex = it->second;
            }
            m.depthIndex[static_cast<size_t>(y) * m.w + x] = lastIndex;
        }
    return r;
}

double simDistanceAtM(const SimConfig& config, double timeS) {
    const double from = config.distancesM.empty() ? 0.0 : config.distancesM[0];
    if (!config.moveToM) return from;
    if (!(config.moveS > 0) || timeS >= config.moveS) return *config.moveToM;
    const double u = std::max(0.0, timeS) / config.moveS;
    return from + (*config.moveToM - from) * u;
}

double SimRenderer::depthScaleAt(double timeS) const {
    return simDistanceAtM(config_, timeS) / config_.distancesM[0];
}

double SimRenderer::depthAtM(int x, int y, double timeS) const {
    return impl_->depths[impl_->depthIndex[static_cast<size_t>(y) * impl_->w + x]] *
           depthScaleAt(timeS);
}

double SimRenderer::blurDiameterPxAt(int x, int y, double focusDioptres, double timeS) const {
    auto d = simBlurDiameterM(config_.lens, focusDioptres, depthAtM(x, y, timeS));
    return d ? *d / config_.lens.pixelPitchM(config_.size.width) : kSimMaxDiameterPx;
}

double SimRenderer::renderedDiameterPxAt(int x, int y, double focusDioptres) const {
    const double d = blurDiameterPxAt(x, y, focusDioptres);
    const long level = std::min<long>(kMaxLevel, std::lround(d / kSimDiameterStepPx));
    return level * kSimDiameterStepPx;
}

double SimRenderer::diffractionSigmaPx() const {
    return impl_->sigmaPx;
}

double SimRenderer::airyDiameterPx() const {
    return optics::airyDiscDiameter(config_.lens.fNumber, kSimWavelengthM) /
           config_.lens.pixelPitchM(config_.size.width);
}

std::vector<SimRegion> SimRenderer::regions(double focusDioptres, double timeS) const {
    std::vector<SimRegion> out;
    const int w = config_.size.width, h = config_.size.height;
    const auto add = [&](Rect r) {
        const int cx = r.x + r.w / 2, cy = r.y + r.h / 2;
        out.push_back({r, depthAtM(cx, cy, timeS), blurDiameterPxAt(cx, cy, focusDioptres, timeS)});
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
        std::memcpy(img.row(y), m.levels[0].texture.row(y + m.pad) + m.pad, sizeof(float) * m.w);
    return img;
}

}  // namespace infocus
