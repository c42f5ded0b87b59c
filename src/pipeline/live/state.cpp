// SPDX-License-Identifier: MIT
#include "src/pipeline/live/state.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "infocus/blur.h"
#include "infocus/dof.h"
#include "infocus/plane_fit.h"
#include "src/pipeline/live/meter.h"

namespace infocus::live_detail {

namespace {

// Blur readings below the engine's own cut are shown greyed and left out of the frame's median.
constexpr double kConfident = kLowBlurConfidence;
// Regions with a blur reading needed before the in-focus line and tilt are shown: three points
// define any plane, so a handful more keep one stray edge from tilting it.
constexpr int kMinRegionsForPlane = 6;
// LMedS triples the live in-focus line is fitted with (the depth map's 2000 take 6 ms a frame
// on 1080p's ~140 regions): with half the regions outliers, 150 triples all miss a clean one
// with odds of 0.875^150 ≈ 2e-9, once in 100 days of frames at 60 fps.
constexpr int kLivePlaneHypotheses = 150;
// Wavelength for the diffraction floor: green, where a sensor's luma is most sensitive.
constexpr double kWavelengthM = 550e-9;

}  // namespace

void fillRegionsAndOptics(const FrameAnalysis& a, const LiveOptions& o,
                          std::optional<double> focusDistanceM, LiveState& s) {
    s.regions.clear();
    s.regions.reserve(a.regions.size());
    int cols = 0, rows = 0;
    std::vector<double> blurs;
    for (const RegionResult& r : a.regions) {
        LiveRegion lr;
        lr.col = r.col;
        lr.row = r.row;
        lr.rect = r.rect;
        lr.sharpness = r.sharpness;
        lr.blurPx = r.blurWidthPx;
        lr.confidence = r.confidence;
        lr.mtf50CyPx = r.mtf50CyPx, lr.mtf50pCyPx = r.mtf50pCyPx;
        lr.status = r.status;
        cols = std::max(cols, r.col + 1);
        rows = std::max(rows, r.row + 1);
        if (r.blurWidthPx && r.confidence >= kConfident) blurs.push_back(*r.blurWidthPx);
        s.regions.push_back(lr);
    }
    s.cols = cols;
    s.rows = rows;
    s.regionsWithBlur = static_cast<int>(blurs.size());
    if (!blurs.empty()) s.blurPx = quantile(blurs, 0.5);

    const LiveLens& L = o.lens;
    const auto pitch = L.pixelPitchM;
    if (s.blurPx && pitch) s.blurUm = *s.blurPx * *pitch * 1e6;
    s.cocFromLens = L.cocM && pitch;
    s.cocPx = s.cocFromLens ? *L.cocM / *pitch : o.defaultCocPx;
    if (L.lens && pitch) s.diffractionPx = 2.44 * kWavelengthM * L.lens->fNumber / *pitch;
    s.regionsInCoc = static_cast<int>(
        std::count_if(blurs.begin(), blurs.end(), [&](double b) { return b <= s.cocPx; }));
    // Each confident region's two candidate distances, the diffraction blur removed as the
    // in-focus floor.
    if (L.lens && pitch && focusDistanceM)
        for (LiveRegion& r : s.regions) {
            if (!r.blurPx || r.confidence < kConfident) continue;
            const double floor = s.diffractionPx ? *s.diffractionPx * *pitch : 0.0;
            if (auto roots =
                    optics::depthFromBlur(*L.lens, *focusDistanceM, *r.blurPx * *pitch, floor)) {
                r.depthNearM = roots->nearRoot;
                r.depthFarM = roots->farRoot;
            }
        }

    // Without a circle of confusion of its own, the depth of field is that of the default one
    // in pixels (cocFromLens says which).
    const std::optional<double> cocM = L.cocM  ? L.cocM
                                       : pitch ? std::optional<double>(s.cocPx * *pitch)
                                               : std::nullopt;
    if (L.lens && cocM && focusDistanceM) {
        if (auto dof = optics::exactLimits(*L.lens, *focusDistanceM, *cocM)) {
            s.dofNearM = dof->nearLimit;
            s.dofFarM = dof->farLimit;
        }
    }
    if (s.regionsWithBlur >= kMinRegionsForPlane) {
        std::optional<optics::CameraGeometry> camera;
        if (L.lens && pitch && focusDistanceM)
            camera = optics::CameraGeometry{*L.lens, *focusDistanceM, *pitch, a.width / 2.0,
                                            a.height / 2.0};
        // The plane fit as the depth map makes it, with the confident regions, but with fewer
        // LMedS hypotheses: the line is redrawn every frame.
        std::vector<optics::BlurSample> samples;
        for (const RegionResult& r : a.regions)
            if (r.blurWidthPx && r.confidence >= kConfident)
                samples.push_back({r.rect.x + 0.5 * r.rect.w, r.rect.y + 0.5 * r.rect.h,
                                   *r.blurWidthPx, r.confidence});
        optics::PlaneFitOptions fit;
        fit.hypotheses = kLivePlaneHypotheses;
        if (const auto plane = optics::fitBlurPlane(samples, a.width, a.height, fit)) {
            s.inFocusLine = plane->inFocusLine;
            if (camera)
                if (const auto scenes = optics::scenePlanes(*plane, *camera))
                    s.tiltDeg = (*scenes)[0].tiltDeg;
        }
    }
}

namespace {

// Row @p y of a preview F times smaller than @p luma: each pixel the rounded mean of the F × F
// pixels it covers. With F a constant the sums stay in 16 bits and the division is a multiply:
// vector work, where a division a pixel cost more than the rest of the preview.
template <int F>
void boxRow(const Luma8& luma, int y, int pw, uint16_t* __restrict sums, uint8_t* __restrict out) {
    const int n = pw * F;
    const uint8_t* __restrict first = luma.row(y * F);
    for (int x = 0; x < n; ++x)
        sums[x] = first[x];
    for (int dy = 1; dy < F; ++dy) {
        const uint8_t* __restrict in = luma.row(y * F + dy);
        for (int x = 0; x < n; ++x)
            sums[x] = static_cast<uint16_t>(sums[x] + in[x]);
    }
    constexpr unsigned kArea = F * F;
    for (int x = 0; x < pw; ++x) {
        unsigned sum = 0;
        for (int dx = 0; dx < F; ++dx)
            sum += sums[x * F + dx];
        out[x] = static_cast<uint8_t>((sum + kArea / 2) / kArea);
    }
}

}  // namespace

void fillPictures(const Luma8& luma, const LiveOptions& o, PeakingMode mode, LiveState& s) {
    if (o.previewLongSide <= 0 || luma.empty()) return;
    const int longSide = std::max(luma.width, luma.height);
    const int f = std::max(1, (longSide + o.previewLongSide - 1) / o.previewLongSide);
    const int pw = luma.width / f, ph = luma.height / f;
    if (pw < 3 || ph < 3) return;
    auto preview = std::make_shared<Image<uint8_t>>(pw, ph);
    // A box average: each preview pixel is the mean of the f × f frame pixels it covers. Beyond
    // boxRow's factors the f rows are summed first, a loop the compiler vectorises, then each f
    // columns of the sums, their rounded mean looked up.
    const int area = f * f;
    const bool general = f > 4;
    std::vector<int> columns(general ? static_cast<size_t>(pw) * f : 0);
    std::vector<uint8_t> mean(general ? static_cast<size_t>(255 * area + 1) : 0);
    for (size_t sum = 0; sum < mean.size(); ++sum)
        mean[sum] = static_cast<uint8_t>((static_cast<int>(sum) + area / 2) / area);
    // At full size (the window face) a copy: the average's division per pixel cost 15 ms a
    // 1080p frame.
    for (int y = 0; f == 1 && y < ph; ++y)
        std::copy_n(luma.row(y), pw, preview->row(y));
    if (f == 2 || f == 3 || f == 4) {
        std::vector<uint16_t> sums(static_cast<size_t>(pw) * f);
        for (int y = 0; y < ph; ++y) {
            if (f == 2) boxRow<2>(luma, y, pw, sums.data(), preview->row(y));
            if (f == 3) boxRow<3>(luma, y, pw, sums.data(), preview->row(y));
            if (f == 4) boxRow<4>(luma, y, pw, sums.data(), preview->row(y));
        }
    }
    for (int y = 0; general && y < ph; ++y) {
        std::fill(columns.begin(), columns.end(), 0);
        for (int dy = 0; dy < f; ++dy) {
            const uint8_t* in = luma.row(y * f + dy);
            for (size_t x = 0; x < columns.size(); ++x)
                columns[x] += in[x];
        }
        uint8_t* out = preview->row(y);
        for (int x = 0; x < pw; ++x) {
            int sum = 0;
            for (int dx = 0; dx < f; ++dx)
                sum += columns[static_cast<size_t>(x) * f + dx];
            out[x] = mean[static_cast<size_t>(sum)];
        }
    }
    s.preview = preview;
    if (mode == PeakingMode::Off) return;

    // Edge strength on the preview: the sum of absolute central differences (0–510), and how
    // many pixels have each strength above 8, from which the threshold is read.
    // Four counts, one for each x mod 4, so that a run of equal strengths (flat parts: 0) does
    // not wait on one counter.
    std::vector<uint16_t> g(static_cast<size_t>(pw) * ph, 0);
    std::array<std::array<uint32_t, 511>, 4> parts{};
    for (int y = 1; y + 1 < ph; ++y) {
        // Not aliased: the strengths of a row are vector work, apart from the counting.
        const uint8_t* __restrict up = preview->row(y - 1);
        const uint8_t* __restrict mid = preview->row(y);
        const uint8_t* __restrict dn = preview->row(y + 1);
        uint16_t* __restrict gy = g.data() + static_cast<size_t>(y) * pw;
        for (int x = 1; x + 1 < pw; ++x)
            gy[x] =
                static_cast<uint16_t>(std::abs(mid[x + 1] - mid[x - 1]) + std::abs(dn[x] - up[x]));
        for (int x = 1; x + 1 < pw; ++x)
            ++parts[static_cast<size_t>(x & 3)][gy[x]];
    }
    std::array<uint32_t, 511> counts{};
    for (size_t v = 0; v < counts.size(); ++v)
        counts[v] = parts[0][v] + parts[1][v] + parts[2][v] + parts[3][v];
    size_t strong = 0;
    for (size_t v = 9; v < counts.size(); ++v)
        strong += counts[v];
    auto mask = std::make_shared<Image<uint8_t>>(pw, ph);
    if (strong > 0) {
        // Percentile: the strongest edges of the frame, as Magic Lantern's peaking marks them.
        // CoC: the edges (above the median edge strength) of regions whose blur is within the
        // circle of confusion. The threshold is the k-th weakest strength above 8.
        const double q = mode == PeakingMode::Percentile ? o.peakingPercentile : 0.5;
        const auto k = std::min(strong - 1, static_cast<size_t>(q * strong));
        size_t below = 0, v = 9;
        while (below + counts[v] <= k)
            below += counts[v++];
        const int threshold = std::max<int>(static_cast<int>(v), 9);
        std::vector<uint8_t> sharpRegion;
        if (mode == PeakingMode::Coc)
            for (const LiveRegion& r : s.regions)
                sharpRegion.push_back(r.blurPx && r.confidence >= kConfident &&
                                      *r.blurPx <= s.cocPx);
        const auto t = static_cast<uint16_t>(threshold);
        for (int y = 0; mode != PeakingMode::Coc && y < ph; ++y) {
            uint8_t* __restrict out = mask->row(y);
            const uint16_t* __restrict gy = g.data() + static_cast<size_t>(y) * pw;
            for (int x = 0; x < pw; ++x)
                out[x] = gy[x] >= t ? 255 : 0;
        }
        for (int y = 0; mode == PeakingMode::Coc && y < ph; ++y) {
            uint8_t* out = mask->row(y);
            for (int x = 0; x < pw; ++x) {
                if (g[static_cast<size_t>(y) * pw + x] < threshold) continue;
                const int fx = x * f + f / 2, fy = y * f + f / 2;
                bool inSharp = false;
                for (size_t i = 0; i < s.regions.size() && !inSharp; ++i) {
                    const Rect& r = s.regions[i].rect;
                    inSharp = sharpRegion[i] && fx >= r.x && fx < r.x + r.w && fy >= r.y &&
                              fy < r.y + r.h;
                }
                if (inSharp) out[x] = 255;
            }
        }
    }
    s.peakingMask = mask;
}

Magnifier magnify(const Luma8& luma, int x, int y, int zoom, int side) {
    Magnifier m;
    m.zoom = zoom == 2 ? 2 : 1;
    const int src = std::min({side / m.zoom, luma.width, luma.height});
    m.x = std::clamp(x, 0, std::max(0, luma.width - 1));
    m.y = std::clamp(y, 0, std::max(0, luma.height - 1));
    const int x0 = std::clamp(m.x - src / 2, 0, luma.width - src);
    const int y0 = std::clamp(m.y - src / 2, 0, luma.height - src);
    m.source = Rect{x0, y0, src, src};
    m.crop = Image<uint8_t>(src * m.zoom, src * m.zoom);
    for (int yy = 0; yy < src * m.zoom; ++yy) {
        const uint8_t* in = luma.row(y0 + yy / m.zoom) + x0;
        uint8_t* out = m.crop.row(yy);
        for (int xx = 0; xx < src * m.zoom; ++xx)
            out[xx] = in[xx / m.zoom];
    }
    return m;
}

}  // namespace infocus::live_detail
