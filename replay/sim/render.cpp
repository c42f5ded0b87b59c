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
//
// The fast render gathers a wide disc on a reduced texture (1/2 to 1/8 of the output, each pixel
// a block mean) and interpolates it bilinearly back: the gather's cost falls with the cube of the
// scale. The block mean and the bilinear interpolation add a variance of s²/12 + s²/6 = s²/4
// per axis (s the scale), so the disc rendered there is narrowed to keep the PSF's variance,
// (D/s)²/16 + 1/4 = (d/s)²/16: D = √(d² − 4s²). Narrower discs are filtered at full resolution
// with the same kernel as the gather, made dense.
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <climits>
#include <cmath>
#include <map>

#include "renderer_impl.h"

namespace infocus {

using sim::kMaxLevel;

namespace {

// The quantised diameter index of @p px pixels.
int quantise(double px) {
    return static_cast<int>(std::clamp<long>(std::lround(px / kSimDiameterStepPx), 0, kMaxLevel));
}

// The reduced scale a disc of @p diameterPx output pixels renders at: the coarsest that leaves
// it kSimFastMinDiscPx wide or more (kSimFastMinHalfDiscPx at half resolution, whose block
// mean and interpolation blur least). 0: full resolution.
int levelFor(double diameterPx) {
    int k = 0;
    while (k + 1 < sim::kScales &&
           diameterPx / (1 << (k + 1)) >= (k == 0 ? kSimFastMinHalfDiscPx : kSimFastMinDiscPx))
        ++k;
    return k;
}

// The disc to gather at scale 2^k for @p diameterPx output pixels (see the file's comment).
double reducedDiameter(double diameterPx, int k) {
    const double s = 1 << k;
    return std::sqrt(std::max(0.0, diameterPx * diameterPx - 4 * s * s)) / s;
}

}  // namespace

const synth::GatherKernel& SimRenderer::Impl::Level::kernel(int quantised) {
    if (!kernels[quantised])
        kernels[quantised] = std::make_unique<synth::GatherKernel>(
            synth::defocusGatherKernel(quantised * kSimDiameterStepPx, sigmaPx));
    return *kernels[quantised];
}

double SimRenderer::Impl::Level::gather(int x, int y, const synth::GatherKernel& k) const {
    const ptrdiff_t wp = texture.width();
    const auto pw = static_cast<ptrdiff_t>(wp) + 1;
    const double* prow = &prefix[static_cast<size_t>(y + pad) * pw + pad];
    const float* trow = texture.row(y + pad) + pad;
    double runs = 0.0;
    for (const auto& r : k.runs) {
        const double* p = prow + static_cast<ptrdiff_t>(r.dy) * pw;
        runs += p[x + r.b + 1] - p[x + r.a];
    }
    double s = runs * k.fullWeight;
    for (const auto& t : k.taps)
        s += t.w * trow[static_cast<ptrdiff_t>(t.dy) * wp + x + t.dx];
    return s;
}

Image<float> SimRenderer::Impl::render(const SimConfig& config, double focusDioptres,
                                       double depthScale, bool exact) {
    Image<float> out(w, h);
    const double pitch = config.lens.pixelPitchM(w);
    // One blur per depth: its diameter, the scale it renders at and its full-resolution kernel.
    const size_t n = depths.size();
    std::vector<double> diameter(n);
    std::vector<int> level(n);
    std::vector<const synth::GatherKernel*> full(n, nullptr);
    bool reduced[sim::kScales] = {};
    for (size_t i = 0; i < n; ++i) {
        auto d = simBlurDiameterM(config.lens, focusDioptres, depths[i] * depthScale);
        diameter[i] = std::min(d ? *d / pitch : kSimMaxDiameterPx, kSimMaxDiameterPx);
        level[i] = exact ? 0 : levelFor(diameter[i]);
        reduced[level[i]] = true;
        if (level[i] == 0) full[i] = &levels[0].kernel(quantise(diameter[i]));
    }

    // Each reduced scale in use: its grid, one point beyond the output on every side for the
    // interpolation, gathered where an output pixel of that scale reads it.
    std::vector<float> grids[sim::kScales];
    for (int k = 1; k < sim::kScales; ++k) {
        if (!reduced[k]) continue;
        Level& L = levels[k];
        const int s = L.scale;
        const int gw = L.gw + 2, gh = L.gh + 2;
        std::vector<uint8_t> need(static_cast<size_t>(gw) * gh, 0);
        bool all = true;
        for (size_t i = 0; i < n && all; ++i)
            all = level[i] == k;
        if (all) {
            std::fill(need.begin(), need.end(), 1);
        } else {
            for (int y = 0; y < h; ++y) {
                const int j = static_cast<int>(std::floor((y + 0.5) / s - 0.5)) + 1;
                const uint16_t* idx = &depthIndex[static_cast<size_t>(y) * w];
                for (int x = 0; x < w; ++x) {
                    if (level[idx[x]] != k) continue;
                    const int i = static_cast<int>(std::floor((x + 0.5) / s - 0.5)) + 1;
                    uint8_t* p = &need[static_cast<size_t>(j) * gw + i];
                    p[0] = p[1] = p[gw] = p[gw + 1] = 1;
                }
            }
        }
        std::vector<float>& g = grids[k];
        g.assign(static_cast<size_t>(gw) * gh, 0.0f);
        for (int j = 0; j < gh; ++j)
            for (int i = 0; i < gw; ++i) {
                const size_t at = static_cast<size_t>(j) * gw + i;
                if (!need[at]) continue;
                // The grid point's own depth: that of the output pixel at its centre.
                const int x = std::clamp((i - 1) * s + s / 2, 0, w - 1);
                const int y = std::clamp((j - 1) * s + s / 2, 0, h - 1);
                const double d = diameter[depthIndex[static_cast<size_t>(y) * w + x]];
                const auto& kern = L.kernel(quantise(reducedDiameter(d, k)));
                g[at] = static_cast<float>(L.gather(i - 1, j - 1, kern));
            }
    }

    // Bilinear weights of each output column and row at every reduced scale.
    std::vector<int> ix[sim::kScales];
    std::vector<float> fx[sim::kScales];
    for (int k = 1; k < sim::kScales; ++k) {
        if (!reduced[k]) continue;
        const double s = 1 << k;
        ix[k].resize(w);
        fx[k].resize(w);
        for (int x = 0; x < w; ++x) {
            const double u = (x + 0.5) / s - 0.5;
            const double f = std::floor(u);
            ix[k][x] = static_cast<int>(f) + 1;
            fx[k][x] = static_cast<float>(u - f);
        }
    }

    // Full-resolution pixels of the fast render: each kernel as a dense filter (OpenCV's
    // vectorised correlation) over the bounding box of the pixels that use it.
    if (!exact && reduced[0]) filterFull(full, out);

    for (int y = 0; y < h; ++y) {
        const uint16_t* idx = &depthIndex[static_cast<size_t>(y) * w];
        float* o = out.row(y);
        const float* rows[sim::kScales][2] = {};
        float fy[sim::kScales] = {};
        for (int k = 1; k < sim::kScales; ++k) {
            if (!reduced[k]) continue;
            const double v = (y + 0.5) / (1 << k) - 0.5;
            const double f = std::floor(v);
            const int j = static_cast<int>(f) + 1;
            const size_t gw = static_cast<size_t>(levels[k].gw) + 2;
            rows[k][0] = &grids[k][j * gw];
            rows[k][1] = &grids[k][(j + 1) * gw];
            fy[k] = static_cast<float>(v - f);
        }
        for (int x = 0; x < w; ++x) {
            const int k = level[idx[x]];
            if (k == 0) {
                if (exact) o[x] = static_cast<float>(levels[0].gather(x, y, *full[idx[x]]));
                continue;
            }
            const int i = ix[k][x];
            const float a = fx[k][x];
            const float top = rows[k][0][i] + a * (rows[k][0][i + 1] - rows[k][0][i]);
            const float bottom = rows[k][1][i] + a * (rows[k][1][i + 1] - rows[k][1][i]);
            o[x] = top + fy[k] * (bottom - top);
        }
    }
    return out;
}

void SimRenderer::Impl::filterFull(const std::vector<const synth::GatherKernel*>& full,
                                   Image<float>& out) {
    // The pixels of each kernel: their bounding box.
    struct Box {
        int x0 = INT_MAX, y0 = INT_MAX, x1 = -1, y1 = -1;
    };
    std::map<const synth::GatherKernel*, Box> boxes;
    for (const auto* k : full)
        if (k) boxes[k];
    if (boxes.empty()) return;
    for (int y = 0; y < h; ++y) {
        const uint16_t* idx = &depthIndex[static_cast<size_t>(y) * w];
        const synth::GatherKernel* last = nullptr;
        Box* box = nullptr;
        for (int x = 0; x < w; ++x) {
            const synth::GatherKernel* k = full[idx[x]];
            if (!k) continue;
            if (k != last) {
                last = k;
                box = &boxes[k];
                box->y0 = std::min(box->y0, y);
                box->y1 = std::max(box->y1, y);
            }
            box->x0 = std::min(box->x0, x);
            box->x1 = std::max(box->x1, x);
        }
    }
    const Level& L = levels[0];
    const cv::Mat texture(L.texture.height(), L.texture.width(), CV_32F,
                          const_cast<float*>(L.texture.data()));
    cv::Mat result;
    for (const auto& [k, b] : boxes) {
        // The kernel as a dense square: runs of full weight and the rim's taps.
        int r = 0;
        for (const auto& run : k->runs)
            r = std::max({r, std::abs(run.dy), std::abs(run.a), std::abs(run.b)});
        for (const auto& t : k->taps)
            r = std::max({r, std::abs(t.dy), std::abs(t.dx)});
        cv::Mat dense = cv::Mat::zeros(2 * r + 1, 2 * r + 1, CV_32F);
        for (const auto& run : k->runs)
            for (int x = run.a; x <= run.b; ++x)
                dense.at<float>(run.dy + r, x + r) += static_cast<float>(k->fullWeight);
        for (const auto& t : k->taps)
            dense.at<float>(t.dy + r, t.dx + r) += static_cast<float>(t.w);
        // The box with the kernel's reach around it, inside the padded texture.
        const cv::Rect area(b.x0 + pad - r, b.y0 + pad - r, b.x1 - b.x0 + 1 + 2 * r,
                            b.y1 - b.y0 + 1 + 2 * r);
        cv::filter2D(texture(area), result, CV_32F, dense, cv::Point(-1, -1), 0,
                     cv::BORDER_ISOLATED);
        for (int y = b.y0; y <= b.y1; ++y) {
            const uint16_t* idx = &depthIndex[static_cast<size_t>(y) * w];
            const float* src = result.ptr<float>(y - b.y0 + r) + r - b.x0;
            float* o = out.row(y);
            for (int x = b.x0; x <= b.x1; ++x)
                if (full[idx[x]] == k) o[x] = src[x];
        }
    }
}

Image<float> SimRenderer::render(double focusDioptres, double timeS) {
    return impl_->render(config_, focusDioptres, depthScaleAt(timeS), false);
}

Image<float> SimRenderer::renderExact(double focusDioptres, double timeS) {
    return impl_->render(config_, focusDioptres, depthScaleAt(timeS), true);
}

}  // namespace infocus
