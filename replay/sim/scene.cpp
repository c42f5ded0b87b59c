// SPDX-License-Identifier: MIT
// The simulated camera's scenes: the sharp texture, the depth of every pixel, and the ground
// truth (depth, thin-lens blur diameter, in-focus distance) tests check measurements against.
#include <algorithm>
#include <cmath>
#include <cstring>
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
    // The widest kernel reaches the largest disc's radius plus the interpolation (2 px) and 5 σ.
    m.pad = std::max(kPad, static_cast<int>(std::ceil(kSimMaxDiameterPx / 2 + 2 + 5 * m.sigmaPx)));
    const int wp = m.w + 2 * m.pad, hp = m.h + 2 * m.pad;
    m.texture = Image<float>(wp, hp);
    if (config.scene == SimScene::Edges) {
        // Squares of a sixteenth of the width, the chart centred in the output image.
        const double period = std::max(16, 2 * (m.w / 16));
        synth::paintSlantedSquaresPixels(m.texture, period, config.edgeAngleDeg, m.pad + m.w / 2.0,
                                         m.pad + m.h / 2.0, 51.0f, 204.0f);
    } else {
        // Painted with the fixed margin (the texture does not depend on the lens), then widened
        // by repeating its border.
        Image<float> leaves(m.w + 2 * kPad, m.h + 2 * kPad);
        synth::paintDeadLeavesPixels(leaves, config.seed, std::max(1.5, m.w / 400.0), m.w / 20.0);
        const int extra = m.pad - kPad;
        for (int y = 0; y < hp; ++y) {
            const float* src = leaves.row(std::clamp(y - extra, 0, leaves.height() - 1));
            float* dst = m.texture.row(y);
            for (int x = 0; x < wp; ++x)
                dst[x] = src[std::clamp(x - extra, 0, leaves.width() - 1)];
        }
    }

    // Row prefix sums let a run of fully covered disc pixels be summed with one subtraction.
    m.prefix.resize(static_cast<size_t>(wp + 1) * hp);
    for (int y = 0; y < hp; ++y) {
        double* p = &m.prefix[static_cast<size_t>(y) * (wp + 1)];
        const float* t = m.texture.row(y);
        p[0] = 0;
        for (int x = 0; x < wp; ++x)
            p[x + 1] = p[x] + t[x];
    }

    // Depth per output pixel. The tilted plane Z = d + tanθ·Y is intersected with the pixel's
    // ray through the lens centre (Y = Z·v, v the sensor coordinate over f).
    m.depth.resize(static_cast<size_t>(m.w) * m.h);
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

double SimRenderer::diffractionSigmaPx() const {
    return impl_->sigmaPx;
}

double SimRenderer::airyDiameterPx() const {
    return optics::airyDiscDiameter(config_.lens.fNumber, kSimWavelengthM) /
           config_.lens.pixelPitchM(config_.size.width);
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
        std::memcpy(img.row(y), m.texture.row(y + m.pad) + m.pad, sizeof(float) * m.w);
    return img;
}

}  // namespace infocus
