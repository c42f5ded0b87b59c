// SPDX-License-Identifier: MIT
// The simulated camera's renderer state, shared by the scene builder and the renderer.
#pragma once

#include <memory>
#include <vector>

#include "infocus/image.h"
#include "infocus/sim.h"
#include "infocus/synth.h"

namespace infocus {

namespace sim {

// Number of quantised disc diameters, 0..kSimMaxDiameterPx in kSimDiameterStepPx.
constexpr int kMaxLevel = static_cast<int>(kSimMaxDiameterPx / kSimDiameterStepPx);
// Padding the texture is painted with; a wide diffraction core pads further by replication.
constexpr int kPad = static_cast<int>(kSimMaxDiameterPx / 2) + 2;

}  // namespace sim

struct SimRenderer::Impl {
    int w = 0, h = 0;            // output size
    int pad = 0;                 // texture margin: every kernel tap stays inside it
    double sigmaPx = 0.0;        // diffraction core σ, output pixels
    Image<float> texture;        // padded by pad on every side, grey levels
    std::vector<double> prefix;  // per padded row: width + 1 prefix sums
    std::vector<float> depth;    // per output pixel, metres
    std::vector<std::unique_ptr<synth::GatherKernel>> kernels =
        std::vector<std::unique_ptr<synth::GatherKernel>>(sim::kMaxLevel + 1);

    // The kernel of a quantised diameter level, built on first use.
    const synth::GatherKernel& kernel(int level);
};

}  // namespace infocus
