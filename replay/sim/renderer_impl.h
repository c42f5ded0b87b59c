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
// Reduced resolutions of the fast render: 1/2, 1/4 and 1/8 of the output.
constexpr int kScales = 4;
// The largest scale; the full-resolution padding is a multiple of it.
constexpr int kMaxScale = 1 << (kScales - 1);

}  // namespace sim

struct SimRenderer::Impl {
    // The texture at one resolution: the full one (scale 1) or the output's 1/scale, each
    // pixel the area average of scale × scale full-resolution pixels.
    struct Level {
        int scale = 1;
        int gw = 0, gh = 0;          // grid points covering the output: ceil(w / scale)
        int pad = 0;                 // texture margin, grid points
        double sigmaPx = 0.0;        // diffraction core σ at this scale
        Image<float> texture;        // (gw + 2 pad) × (gh + 2 pad)
        std::vector<double> prefix;  // per padded row: width + 1 prefix sums
        std::vector<std::unique_ptr<synth::GatherKernel>> kernels =
            std::vector<std::unique_ptr<synth::GatherKernel>>(sim::kMaxLevel + 1);

        // The kernel of a quantised diameter (in this level's pixels), built on first use.
        const synth::GatherKernel& kernel(int quantised);
        // The texture blurred by @p k at grid point (x, y).
        double gather(int x, int y, const synth::GatherKernel& k) const;
    };

    int w = 0, h = 0;    // output size
    int pad = 0;         // full-resolution texture margin: every kernel tap stays inside it
    double sigmaPx = 0;  // diffraction core σ, output pixels
    Level levels[sim::kScales];
    // The scene's depths at time 0, each once (a tilted plane has one per row or column), and
    // each output pixel's index into them: a frame computes one blur per depth.
    std::vector<float> depths;
    std::vector<uint16_t> depthIndex;

    // Renders with every depth's blur multiplied through @p depthScale (the moving plane);
    // @p exact: every pixel gathered at full resolution.
    Image<float> render(const SimConfig& config, double focusDioptres, double depthScale,
                        bool exact);
    // Writes the output pixels whose kernel in @p full (per depth; null: a reduced scale) is
    // set, filtering the full-resolution texture with each kernel made dense.
    void filterFull(const std::vector<const synth::GatherKernel*>& full, Image<float>& out);
};

}  // namespace infocus
