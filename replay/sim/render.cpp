// SPDX-License-Identifier: MIT
// The simulated camera's renderer: each output pixel gathers the texture through the defocus
// PSF of its own depth.
//
// Defocus model (thin lens, src/optics): a point at depth z_o images to a uniform disc of
// diameter ΔX_i = A·|z_s(1/f − 1/z_o) − 1| with A = f/N and z_s the sensor distance for the
// focus setting. The disc is converted to output pixels with the pixel pitch and integrated over
// each pixel's area (synth::discGatherKernel), so the rendered edge has the disc's 10–90 % rise
// of 0.68705·d (convolved with the 1-pixel box of the sensor).
#include <algorithm>
#include <cmath>

#include "renderer_impl.h"

namespace infocus {

using sim::kMaxLevel;
using sim::kPad;

const synth::GatherKernel& SimRenderer::Impl::kernel(int level) {
    if (!kernels[level])
        kernels[level] = std::make_unique<synth::GatherKernel>(
            synth::discGatherKernel(level * kSimDiameterStepPx));
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
        const double* prow = &m.prefix[static_cast<size_t>(y + kPad) * pw + kPad];
        const float* trow = m.texture.row(y + kPad) + kPad;
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
