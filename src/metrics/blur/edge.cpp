// SPDX-License-Identifier: MIT
// One edge measured: a segment's ESF sampled, widened and refitted where it needs it, and turned
// into an EdgeMeasurement; an edge found before measured again where it was (BlurTracker).
#include <numbers>

#include "infocus/sfr.h"
#include "internal.h"

namespace infocus::blur_detail {

namespace {

// Plateau levels (grey) at which an edge counts as clipped by the sensor or the encoder.
constexpr double kClipLow = 3.0, kClipHigh = 252.0;

// The measurement of the edge on @p patch from its ESF fit @p f of @p bins.
EdgeMeasurement makeMeasurement(const Patch& patch, const EsfFit& f, const BinList& bins,
                                double straight, const BlurOptions& o) {
    EdgeMeasurement m;
    m.cx = patch.cx + f.mean * patch.nx;
    m.cy = patch.cy + f.mean * patch.ny;
    m.angleDeg = std::atan2(patch.ny, patch.nx) * 180.0 / std::numbers::pi;
    m.contrast = f.contrast;
    m.noise = f.noise;
    m.sigmaPx = std::sqrt(std::max(0.0, f.varCore - kPixelVariance));
    m.riseRawPx = f.rise;
    // The sampled rise includes the pixel area and the bins' own spread; remove them as Gaussian
    // shares in quadrature (exact for a Gaussian PSF, close for a disc, whose rise per σ is 2.7482
    // rather than 2.5631). Near 0° and 45° the ESF is sampled at whole-pixel spacing, too coarse
    // to interpolate a crossing: there the Gaussian model's rise of the measured σ stands in.
    const double floorRise2 =
        kGaussianRisePerSigma * kGaussianRisePerSigma * (kPixelVariance + f.binVar);
    const bool dense = f.binVar <= 2.0 * o.binPx * o.binPx / 6.0;
    m.edgeWidthPx = dense ? std::sqrt(std::max(0.0, f.rise * f.rise - floorRise2))
                          : kGaussianRisePerSigma * m.sigmaPx;
    m.riseMeasured = dense;
    m.straightnessPx = straight;
    // Halos only where a region may count them (blurFromEdges): a clean, sharp edge.
    if (m.sigmaPx <= kHaloSigmaPx && f.contrast >= kCleanCnr * std::max(f.noise, 0.5))
        m.haloFraction = esfHalo(bins, f.mean, std::sqrt(std::max(f.varLsf, 0.0)));
    const double sd = std::sqrt(std::max(f.varLsf, kPixelVariance));
    const double cnr = f.contrast / std::max(f.noise, 0.5);
    const double bend = relativeBend(straight, sd);
    const double over = f.overshoot / 0.25;
    m.quality = (1.0 - std::exp(-cnr / 5.0)) * std::exp(-bend * bend - over * over);
    if (o.sfr && m.quality > kUsableQuality) {
        // The line spread for the SFR from the same bins, in light, about the fit's centroid
        // and between its plateaus; the window is sized by the wide window's spread, so flare
        // lowers the SFR. Its transform is taken only if the edge sets its region's blur, which
        // an edge of too low a quality never does (blurFromEdges).
        const EsfProfile p{{bins.pos.data(), bins.size},
                           {bins.value.data(), bins.size},
                           {bins.withinVar.data(), bins.size},
                           f.mean,
                           sd,
                           f.profileLo,
                           f.profileLo + f.profileContrast,
                           o.binPx,
                           0.5 * o.binPx - patch.hw};
        if (auto l = lineSpreadOf(p))
            m.lineSpread = std::make_shared<const LineSpread>(std::move(*l));
    }
    return m;
}

// The largest σ a guessed σ @p sd allows: a Gaussian's, whose thresholded derivative is the
// narrowest for its σ (the guess is 1.2 × 0.72 σ for it, 1.2 × 0.95 σ for a disc).
double largestSigma(double sd) {
    return sd / (1.2 * 0.72);
}

// The line of the edge in @p patch fitted again in the patch's own slab (@p slices slices along
// it, derivative above @p threshold), and the patch moved onto it; empty when too few slices
// hold an edge.
std::optional<LineFit> refitOnto(const Luma8& img, const Bounds& b, const Kernels& k, Patch& patch,
                                 double threshold, int slices) {
    thread_local std::vector<Slice> sl;
    sl.resize(slices);
    geometrySlices(img, b, k, patch, threshold, slices, sl.data());
    const LineFit line = fitLine(sl.data(), slices);
    if (!line.ok) return std::nullopt;
    moveOnto(patch, line);
    return line;
}

// The ESF fit of @p bins over the whole patch and, when that gives no usable edge and
// @p narrowStart is above 0, the fit of the same bins from a window of ±narrowStart about the
// line (measureSegment says why), kept only where it gives one.
EsfFit fitWithSecondStart(const BinList& bins, PairTerms& terms, double halfWidth,
                          double minContrast, double narrowStart, const Decoding& dec) {
    const EsfFit f = fitEsf(bins, terms, halfWidth, minContrast, dec);
    if (usable(f) || narrowStart <= 0.0) return f;
    const EsfFit g = fitEsf(bins, terms, halfWidth, minContrast, dec, narrowStart);
    return usable(g) ? g : f;
}

// The half-width a patch of half-width @p hw is widened to when the line spread of fit @p f does
// not fit in it: 1.6 × as wide, and at least 4 σ + 4 px of that spread, up to maxHalfWidthPx.
double widerHalfWidth(const EsfFit& f, double hw, const BlurOptions& o) {
    const double sd = std::sqrt(std::max(f.varLsf, 0.1));
    return std::min(o.maxHalfWidthPx, std::max(1.6 * hw, 4.0 * sd + 4.0));
}

}  // namespace

double relativeBend(double straightPx, double sigmaPx) {
    return straightPx / (0.3 + 0.25 * sigmaPx);
}

double guessSigma(const LineFit& f) {
    return 1.2 * std::sqrt(f.spread2);
}

bool usable(const EsfFit& f) {
    return f.ok && f.lo > kClipLow && f.lo + f.contrast < kClipHigh &&
           f.varLsf >= 0.5 * kPixelVariance && f.plateauPixels > 0;
}

std::optional<EdgeMeasurement> measureSegment(const Luma8& img, const Bounds& b,
                                              const BlurOptions& o, const Kernels& k, Patch& patch,
                                              double threshold, LineFit line, int slices,
                                              EdgeTrack& track) {
    const double sd0 = guessSigma(line);
    patch.hw = std::clamp(4.5 * sd0 + 3.5, kProbeHalfWidthPx, o.maxHalfWidthPx);
    // The probe's slab (±kProbeHalfWidthPx about the seed) cut the derivative where the line,
    // at its furthest from the seed along the segment, plus 3 σ of the guessed spread reaches
    // the slab's side: then the line is fitted again in the patch's own slab. Otherwise every
    // slice held its derivative and the probe's centroids stand.
    const bool cut =
        std::abs(line.a) + std::abs(line.slope) * patch.hl + 3.0 * sd0 > kProbeHalfWidthPx;
    bool refit = cut;
    const Decoding dec = decodingFor(o.transfer);
    thread_local BinList bins;
    for (int pass = 0; pass < 6; ++pass) {
        if (refit) {
            const auto fitted = refitOnto(img, b, k, patch, threshold, slices);
            if (!fitted) return std::nullopt;
            line = *fitted;
        }
        sampleEsf(img, b, k, patch, o.binPx, dec, bins);
        // The bin-pair terms at most once per ESF: every fit of these bins that gets past its
        // first window reads them.
        thread_local PairTerms terms;
        terms.defer(bins, k);
        // The window started over the whole patch takes in, on crowded texture, the edges beside
        // this one, and may wander off it or lose its contrast. Where the probe's slab held the
        // derivative, the σ guessed from it bounds the edge's own line spread: the same bins are
        // fitted again from a window that holds just that, ±(4 σ + 1 px) of the largest σ the
        // guess allows, about the line. Only as a second chance: where the whole patch gives an
        // edge, it stands (near a chequerboard's corner the narrow start misses the corner's
        // clutter and reads the edge narrow). No pixel is read again. On the bench frame more
        // seeds give an edge, and 142 regions of 144 measure instead of 132 (docs/blur.md).
        const double narrowStart = pass == 0 && !cut ? 4.0 * largestSigma(sd0) + 1.0 : 0.0;
        const EsfFit f = fitWithSecondStart(bins, terms, patch.hw, o.minContrast, narrowStart, dec);
        if (usable(f)) {
            track = {patch, line.straight, narrowStart, threshold, slices};
            return makeMeasurement(patch, f, bins, line.straight, o);
        }
        if (f.ok) return std::nullopt;  // fitted, but clipped or collapsed: no wider patch helps
        if (!f.needWider || patch.hw >= o.maxHalfWidthPx) return std::nullopt;
        // A derivative held well inside the probe's slab, with a line spread that does not fit
        // in 4.5 σ + 3.5 px of it: the extra spread is another edge, shading or texture beside
        // this one, not its blur (on the bench frame, 91 of 112 such segments ended without a
        // usable edge once widened). Only an edge whose derivative the slab may have cut, a wide
        // blur, is widened.
        if (!cut) return std::nullopt;
        patch.hw = widerHalfWidth(f, patch.hw, o);
        refit = true;
    }
    return std::nullopt;
}

std::optional<EdgeMeasurement> remeasureEdge(const Luma8& luma, const Bounds& sb,
                                             const BlurOptions& o, const Kernels& k,
                                             EdgeTrack& track, bool rescue) {
    thread_local BinList bins;
    thread_local PairTerms terms;
    Patch& patch = track.patch;
    bool refit = false, refitted = false;
    const Decoding dec = decodingFor(o.transfer);
    for (int pass = 0; pass < 6; ++pass) {
        if (refit) {
            const auto line = refitOnto(luma, sb, k, patch, track.threshold, track.slices);
            if (!line) return std::nullopt;
            track.straight = line->straight;
            refitted = true;
        }
        sampleEsf(luma, sb, k, patch, o.binPx, dec, bins);
        terms.defer(bins, k);
        const EsfFit f =
            fitWithSecondStart(bins, terms, patch.hw, o.minContrast, track.narrowStart, dec);
        if (usable(f)) return makeMeasurement(patch, f, bins, track.straight, o);
        if (!rescue) return std::nullopt;
        refit = true;
        if (!refitted) continue;
        if (f.ok || !f.needWider || patch.hw >= o.maxHalfWidthPx) return std::nullopt;
        patch.hw = widerHalfWidth(f, patch.hw, o);
        track.narrowStart = 0.0;
    }
    return std::nullopt;
}

}  // namespace infocus::blur_detail
