// SPDX-License-Identifier: MIT
// The simulated camera's renderer: each output pixel gathers the texture through the PSF of its
// own depth.
//
// PSF: the thin-lens defocus disc (src/optics) of diameter ΔX_i = A·|z_s(1/f − 1/z_o) − 1|,
// A = f/N, z_s the sensor distance for the focus setting, convolved (not added in quadrature)
// with a Gaussian of σ = 0.42·λ·N, the usual fit to the Airy pattern's core (Airy disc
// diameter 2.44·λ·N, λ = 550 nm). The texture already holds each pixel's area average of the
// sharp scene (the sensor's integration), so it is blurred as a continuous image interpolated
// with a cubic that adds no blur of its own (synth::defocusGatherKernel): blur far below a pixel
// still changes the image, as through a real lens near focus.
#include <algorithm>
#include <cmath>

#include "renderer_impl.h"

namespace infocus {

using sim::kMaxLevel;

const synth::GatherKernel& SimRenderer::Impl::kernel(int level) {
    if (!kernels[level])
        kernels[level] = std::make_unique<synth::GatherKernel>(
            synth::defocusGatherKernel(level * kSimDiameterStepPx, sigmaPx));
    return *kernels[level];
}

Image<float> SimRenderer::render(double focusDioptres) {
    Impl& m = *impl_;
    Image<float> out(m.w, m.h);
    const double pitch = config_.lens.pixelPitchM(m.w);
    const ptrdiff_t wp = m.texture.width();
    const size_t pw = static_cast<size_t>(wp) + 1;
    // The level only changes where the depth does: recompute it only then.
    float lastDepth = -1.0f;
    int level = 0;
    for (int y = 0; y < m.h; ++y) {
        const float* depthRow = &m.depth[static_cast<size_t>(y) * m.w];
        float* o = out.row(y);
        const double* prow = &m.prefix[static_cast<size_t>(y + m.pad) * pw + m.pad];
        const float* trow = m.texture.row(y + m.pad) + m.pad;
        const synth::GatherKernel* k = nullptr;
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
                s += t.w * trow[static_cast<ptrdiff_t>(t.dy) * wp + x + t.dx];
            o[x] = static_cast<float>(s);
        }
    }
    return out;
}

}  // namespace infocus
