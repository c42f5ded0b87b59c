// SPDX-License-Identifier: MIT
// Blur width at straight edges, a region at a time: the options in range, the region's setup,
// its seeds tried strongest first, and its blur from the sharpest trusted edges (docs/blur.md).
#include "internal.h"

namespace infocus::blur_detail {

namespace {

// The straightness share e^(−bend²) of the quality (relativeBend) above which a segment
// length counts as straight: a longer length is measured only while its bend costs it less than
// half its quality. The bend widens the ESF (the edge's wander across the segment adds to its
// spread), and a longer segment of a curved edge spends more pixels to measure it wider.
constexpr double kStraightShare = 0.5;

// What an edge needs to set the region's blur (measureBlur): a share of the region's best edge
// quality, and a contrast of this many times the grey-level spread beside it.
constexpr double kTrustedQuality = 0.3, kTrustedCnr = 5.0;

// The most an edge's rise-to-σ ratio may lie outside a defocus PSF's range (riseOffset) for
// it to set the region: beyond a quarter, its window closed on clutter or its plateaus hold
// another edge, and its σ says little about the blur.
constexpr double kTrustedRiseOffset = 0.22;

// Ranges of the options (BlurOptions, sanitized): the shortest segment measured (its half-length,
// px), the widest ESF half-width (px; a blur of some 800 px), the most edges a region and the
// coarsest candidate grid.
constexpr double kShortestHalfLengthPx = 6.0, kMaxHalfWidthPx = 1024.0;
constexpr int kMaxEdgesPerRegion = 256, kMaxCandidateStep = 64;

// The 10–90 % rise of a defocus PSF's ESF per σ of its line spread lies between a Gaussian's
// (2.5631) and a uniform disc's (2.7482); a pixel's box alone gives 2.77. A line spread whose
// tails hold another edge or shading has a larger σ for its rise (it reads wide), one whose window
// lost its tails a smaller σ (it reads narrow). Outside [kRiseLo, kRiseHi] an edge's rank falls as
// e^(−(ln(excess)/kRiseTolerance)²): 5 % out costs 63 %.
constexpr double kRiseLo = 2.55, kRiseHi = 2.8, kRiseTolerance = 0.05;

// The most confidence a region set by one segment alone gets (blurFromEdges): under
// kLowBlurConfidence, and as much as a lone segment's rank gave it below that.
constexpr double kLoneMost = 0.24;
static_assert(kLoneMost < kLowBlurConfidence);

// The disc's 10–90 % rise per diameter (a uniform disc's edge), and how far the moment's disc
// may exceed the disc of the measured rise (blurFromEdges).
constexpr double kDiscRisePerDiameter = 0.68705, kDiscRiseSlack = 0.03;

// The least share of its quality an edge keeps in the confidence however unlike a defocused edge
// it looks.
constexpr double kMatchFloor = 0.4;

// Rows of the next region asked for per seed tried: about a region's worth over the 16 or so
// seeds a region of the bench's grid looks at (most are passed over cheaply).
constexpr int kPrefetchRowsPerSeed = 8;

// The edge at seed @p c of a region set up as @p s: the best of its segment lengths, or none.
// @p covered is set to the patch along the seed's edge (over the full length), so that later
// seeds on the same edge are skipped, measured or not, and @p track to where the edge was
// measured.
std::optional<EdgeMeasurement> measureSeed(const Luma8& luma, const RegionSetup& s,
                                           const BlurOptions& o, const Kernels& k,
                                           const Candidate& c, Patch& covered, EdgeTrack& track) {
    thread_local std::vector<Slice> probe;
    probe.resize(s.slices);
    // One probe along the longest segment in a narrow slab about the seed's gradient: the
    // slices' derivative centroids give every length's line and straightness at once.
    const double g = std::sqrt(c.mag2);
    const double threshold = 0.2 * g;
    const Patch seed{c.x + 0.5, c.y + 0.5, c.gx / g, c.gy / g, kProbeHalfWidthPx, s.halfLength};
    geometrySlices(luma, s.sb, k, seed, threshold, s.slices, probe.data());
    // Long segments average more pixels; curved or crowded edges (texture) only stay straight
    // and clean over a short one. Lengths are judged shortest first: a longer one only while
    // the shorter is straight, since an edge that bends over a short segment bends more over
    // a long one (straight: kStraightShare). The longest straight one is measured, then,
    // while none rates above 0.3, the next shorter ones (three tries in all).
    LineFit fits[kMaxLengths];
    double share[kMaxLengths] = {};
    int longest = -1, bestShare = -1;
    for (int j = s.nLengths - 1; j >= 0; --j) {
        const int m = s.slices >> j;
        fits[j] = fitLine(probe.data() + (s.slices - m) / 2, m);
        if (!fits[j].ok) continue;  // too few slices with an edge (a border): try longer
        const double sd = std::max(guessSigma(fits[j]), std::sqrt(kPixelVariance));
        const double bend = relativeBend(fits[j].straight, sd);
        share[j] = std::exp(-bend * bend);
        if (bestShare < 0 || share[j] > share[bestShare]) bestShare = j;
        if (share[j] <= kStraightShare) break;
        longest = j;
    }
    std::optional<EdgeMeasurement> best;
    covered = seed;
    int tries = 0;
    const int from = longest >= 0 ? longest : bestShare;
    for (int j = from; j >= 0 && j < s.nLengths && tries < 3; ++j) {
        if (!fits[j].ok || (longest >= 0 && share[j] <= kStraightShare)) continue;
        ++tries;
        Patch p = seed;
        p.hl = s.lengths[j];
        moveOnto(p, fits[j]);
        EdgeTrack t;
        const auto m =
            measureClearOfEnds(luma, s.sb, o, k, p, threshold, fits[j], s.slices >> j, t,
                               probe.data(), s.slices, s.halfLength, kShortestHalfLengthPx);
        if (tries == 1) covered = p;
        if (m && (!best || m->quality > best->quality)) {
            best = m;
            covered = p;
            track = t;
        }
        if (best && best->quality > 0.3) break;
    }
    covered.hl = s.halfLength;
    return best;
}

// The spread edge @p e was measured with (px): σ, the pixel and the bins of @p binPx. A slanted
// edge's bins spread by h²/6 about their centres (docs/blur.md, Floors removed).
double measuredSpread(const EdgeMeasurement& e, double binPx) {
    return std::sqrt(e.sigmaPx * e.sigmaPx + kPixelVariance + binPx * binPx / 6.0);
}

// How far (a log ratio, 0 inside) edge @p e's rise-to-σ ratio lies outside the range of a
// defocus PSF, [kRiseLo, kRiseHi]; 0 where the rise is not measured.
double riseOffset(const EdgeMeasurement& e, double binPx) {
    if (!e.riseMeasured) return 0.0;
    const double ratio = e.riseRawPx / measuredSpread(e, binPx);
    return ratio < kRiseLo   ? std::log(kRiseLo / std::max(ratio, 1e-6))
           : ratio > kRiseHi ? std::log(ratio / kRiseHi)
                             : 0.0;
}

// How far edge @p e (ESF bins of @p binPx) looks like a defocused straight edge, 0..1: its
// rise-to-σ ratio in the range of a defocus PSF, and its bend counted a second time (the quality
// has e^(−bend²) already): on textured scenes a bend of 0.6 reads over 10 % wide more often than
// not. The ratio is not judged where the engine reports the Gaussian's rise of the measured σ in
// place of a measured one (an ESF sampled at whole-pixel spacing, near 0° and 45°).
double profileMatch(const EdgeMeasurement& e, double binPx) {
    const double bend = relativeBend(e.straightnessPx, measuredSpread(e, binPx));
    const double off = riseOffset(e, binPx);
    const double match =
        std::exp(-0.5 * bend * bend - (off / kRiseTolerance) * (off / kRiseTolerance));
    return kMatchFloor + (1.0 - kMatchFloor) * match;
}

}  // namespace

Bounds clipRect(const Rect& r, int w, int h) {
    const Rect c = intersect(r, {0, 0, w, h});
    return {c.x, c.y, c.x + c.w, c.y + c.h};
}

BlurOptions sanitized(const BlurOptions& given) {
    const BlurOptions defaults;
    const auto in = [](double v, double fallback, double lo, double hi) {
        return std::isnan(v) ? fallback : std::clamp(v, lo, hi);
    };
    // The ESF kernels' integer sums hold kEsfMaxBinPixels pixels a bin: bins of at most 1 px
    // along segments of at most 2 × 500 px (a bin of an axis-aligned edge takes one column of
    // the patch, one pixel a row).
    constexpr double kMaxHalfLengthPx = 500.0;
    static_assert(2 * kMaxHalfLengthPx + 1 <= detail::kEsfMaxBinPixels);
    BlurOptions o = given;
    o.maxEdges = std::clamp(given.maxEdges, 1, kMaxEdgesPerRegion);
    o.candidateStep = std::clamp(given.candidateStep, 1, kMaxCandidateStep);
    // 0 (or less, or not a number) picks the length from the region; a length is at least the
    // shortest segment measured.
    o.edgeHalfLengthPx =
        given.edgeHalfLengthPx > 0.0
            ? std::clamp(given.edgeHalfLengthPx, kShortestHalfLengthPx, kMaxHalfLengthPx)
            : 0.0;
    o.maxHalfWidthPx =
        in(given.maxHalfWidthPx, defaults.maxHalfWidthPx, kProbeHalfWidthPx, kMaxHalfWidthPx);
    o.binPx = in(given.binPx, defaults.binPx, 1.0 / 16.0, 1.0);
    o.minContrast = in(given.minContrast, defaults.minContrast, 0.0, 255.0);
    o.minGradient = in(given.minGradient, defaults.minGradient, 0.0, 1020.0);
    o.relativeGradient = in(given.relativeGradient, defaults.relativeGradient, 0.0, 1.0);
    o.opticsFloorSigmaPx = in(given.opticsFloorSigmaPx, 0.0, 0.0, kMaxHalfWidthPx);
    if (given.transfer != TransferFunction::Srgb && given.transfer != TransferFunction::Rec709)
        o.transfer = TransferFunction::Linear;
    return o;
}

std::optional<RegionSetup> regionSetup(const Luma8& luma, const Rect& roi, const BlurOptions& o) {
    if (luma.empty() || luma.width < 3 || luma.height < 3) return std::nullopt;
    RegionSetup s;
    s.r = clipRect(roi, luma.width, luma.height);
    if (s.r.x1 - s.r.x0 < 3 || s.r.y1 - s.r.y0 < 3) return std::nullopt;
    // Sampling stays one pixel inside the image: the derivative needs both neighbours.
    const Bounds sb = o.sampleOutsideRoi ? Bounds{0, 0, luma.width, luma.height} : s.r;
    s.sb = {std::max(sb.x0, 1), std::max(sb.y0, 1), std::min(sb.x1, luma.width - 1),
            std::min(sb.y1, luma.height - 1)};
    // Longer segments average more pixels per ESF bin (less noise) but must stay straight and
    // inside the region's scale: a quarter of the region's smaller side unless told.
    s.halfLength = o.edgeHalfLengthPx > 0
                       ? o.edgeHalfLengthPx
                       : std::clamp(0.25 * std::min(s.r.x1 - s.r.x0, s.r.y1 - s.r.y0), 8.0, 48.0);
    for (double len = s.halfLength; len >= kShortestHalfLengthPx && s.nLengths < kMaxLengths;
         len *= 0.5)
        s.lengths[s.nLengths++] = len;
    s.slices = 4 << (s.nLengths - 1);
    return s;
}

std::vector<EdgeMeasurement> measureEdgesPrefetching(const Luma8& luma, const Rect& roi,
                                                     const BlurOptions& options,
                                                     RowPrefetcher& next,
                                                     std::vector<EdgeTrack>* found) {
    std::vector<EdgeMeasurement> out;
    const std::optional<RegionSetup> setup = regionSetup(luma, roi, options);
    if (!setup) return out;
    const RegionSetup& s = *setup;
    const Kernels kernels = chooseKernels(options);
    // Whether the edges agree is asked while searching: their SFR is not needed for that.
    BlurOptions noSfr = options;
    noSfr.sfr = false;
    // The 64 strongest candidates first. A region without an edge yet whose candidates were all
    // passed over or covered (crossed by many lines stronger than its edges: traces, wires, text)
    // lists the next, weaker ones, four times as many each time. Equal gradients keep their scan
    // order, so a longer list starts with the shorter one.
    size_t cap = 64;
    const CandidateGrid grid = candidateGrid(luma, s.r, options, kernels);
    CandidateList cands = strongestCandidates(grid, kernels, cap);
    size_t i = 0;  // the next of cands
    std::vector<Patch> used;
    int attempts = 0;
    // A seed that passes oneSided usually gives an edge: a region gets maxEdges attempts, and one
    // more per 128 × 128 px so that a large region (a coarse grid on a big sensor) is not judged
    // by its first few seeds. The last attempt is kept for a region without a usable edge yet:
    // there it finds the region's first edge, where elsewhere it would only add one more to the
    // average. Since the ESF fit's second start (measureSegment) more seeds give an edge, and the
    // rule takes a sixth of a frame's instructions without losing a region (docs/blur.md).
    const int extra = (s.r.x1 - s.r.x0) * (s.r.y1 - s.r.y0) / (128 * 128);
    bool haveUsable = false;
    int most = options.maxEdges;
    for (;;) {
        if (static_cast<int>(out.size()) >= most ||
            attempts >= most + extra - (haveUsable ? 1 : 0)) {
            // Where fewer than three of its edges agree (blurFromEdges), one segment or two may
            // set the region, and one alone is never confident: it measures as many again, once.
            // On dense texture that doubles the regions whose blur two edges or more agree on.
            if (most == options.maxEdges && haveUsable && blurFromEdges(out, noSfr).edgeCount < 3) {
                most = std::min(2 * options.maxEdges, kMaxEdgesPerRegion);
                if (most > options.maxEdges) continue;
            }
            break;
        }
        if (i == cands.size()) {
            // Every point listed, or an edge found: the region is done.
            if (cands.strongest() < cap || !out.empty()) break;
            const size_t looked = cands.strongest();
            cap *= 4;
            cands = weakerCandidates(grid, kernels, cap, cands.lowest());
            i = 0;
            if (cands.strongest() == looked) break;
            continue;
        }
        const Candidate c = cands.at(i++);
        next.fetch(kPrefetchRowsPerSeed);
        // Skip seeds on an edge already measured (or already rejected).
        const double px = c.x + 0.5, py = c.y + 0.5;
        const bool covered = std::any_of(used.begin(), used.end(), [&](const Patch& p) {
            return std::abs(p.u(px, py)) <= std::max(p.hw, 3.0) && std::abs(p.t(px, py)) <= p.hl;
        });
        if (covered) continue;
        // Seeds on bars, lines and clutter are passed over (the scan goes on to weaker ones); the
        // test reads 81 grid points where a measurement walks a thousand pixels twice.
        if (!cands.judged() && !oneSided(grid, c.gridIndex, kernels)) continue;
        ++attempts;
        Patch edge{};
        EdgeTrack track;
        const std::optional<EdgeMeasurement> best =
            measureSeed(luma, s, options, kernels, c, edge, track);
        used.push_back(edge);
        if (best) {
            out.push_back(*best);
            if (found) found->push_back(track);
            haveUsable = haveUsable || best->quality > kUsableQuality;
        }
    }
    return out;
}

BlurEstimate blurFromEdges(const std::vector<EdgeMeasurement>& edges, const BlurOptions& options) {
    BlurEstimate est;
    // Each usable edge with its rank: its quality × how far it looks like a defocused straight
    // edge (profileMatch). Quality decides which edges set the region and how much they weigh;
    // the rank sets the confidence, so an edge that does not look the part still gives its
    // region its width, at a lower confidence.
    struct Ranked {
        const EdgeMeasurement* e;
        double rank;
    };
    std::vector<Ranked> good;
    for (const EdgeMeasurement& e : edges)
        if (e.quality > kUsableQuality)
            good.push_back({&e, e.quality * profileMatch(e, options.binPx)});
    if (good.empty()) return est;
    // The sharpest edges set the region's blur. An edge's width is the defocus blur convolved
    // with the edge's own softness (a rounded body, a shadow, a printed gradient), which only
    // widens it: no edge in focus at that depth is sharper than the blur, so the smallest σ
    // bounds it and wider edges are soft objects or edges at another depth. Only trusted edges
    // may set it: at least 0.3 × the region's best quality, and a contrast at least 5 × the
    // grey-level spread beside the edge. A cluttered edge (another edge or a corner in its
    // plateaus) can read narrow, and one such edge must not decide the region.
    // The edges within 25 % of the sharpest (15 % from σ 8 px), either side, are averaged in
    // variance, weighted by quality, against noise.
    double best = 0.0;
    for (const Ranked& g : good)
        best = std::max(best, g.e->quality);
    double sharpest = std::numeric_limits<double>::infinity();
    for (const Ranked& g : good)
        if (g.e->quality >= kTrustedQuality * best &&
            g.e->contrast >= kTrustedCnr * std::max(g.e->noise, 0.5) &&
            riseOffset(*g.e, options.binPx) <= kTrustedRiseOffset)
            sharpest = std::min(sharpest, g.e->sigmaPx);
    // A region of cluttered edges only: the sharpest of them, at their low confidence.
    if (!std::isfinite(sharpest))
        for (const Ranked& g : good)
            sharpest = std::min(sharpest, g.e->sigmaPx);
    // Noise scatters narrow edges by a few per cent, so their band is wide; a wide blur reads
    // within a per cent or two, and an edge 20 % wider than it is a segment cut across a corner.
    const double band = std::clamp(0.25 - 0.025 * (sharpest - 4.0), 0.15, 0.25);
    // Widths are compared as the spread the edge was measured with, pixel included: a blur well
    // under a pixel is seen through the pixel's own spread, and σ of 0 and 0.2 px differ by less
    // than sampling scatters them.
    const auto spread = [](double sigma) { return std::sqrt(sigma * sigma + kPixelVariance); };
    const double sharpestSpread = spread(sharpest);
    double sw = 0, sv = 0, sr = 0, sh = 0, shw = 0, sRank = 0, sm = 0, smp = 0, smw = 0;
    int agreeing = 0;
    bool measuredRise = true;
    for (const Ranked& g : good) {
        const EdgeMeasurement* e = g.e;
        if (std::abs(spread(e->sigmaPx) - sharpestSpread) > band * sharpestSpread) continue;
        sw += e->quality;
        sv += e->quality * e->sigmaPx * e->sigmaPx;
        sr += e->quality * e->edgeWidthPx * e->edgeWidthPx;
        if (e->contrast >= kCleanCnr * std::max(e->noise, 0.5) && e->sigmaPx <= kHaloSigmaPx)
            sh += e->quality * e->haloFraction, shw += e->quality;
        sRank += g.rank;
        if (options.sfr && e->lineSpread)
            if (const auto m = mtf50Of(*e->lineSpread))
                sm += e->quality * m->mtf50CyPx, smp += e->quality * m->mtf50pCyPx,
                    smw += e->quality;
        measuredRise = measuredRise && e->riseMeasured;
        ++agreeing;
    }
    const double sigma = std::sqrt(sv / sw), width = std::sqrt(sr / sw);
    const double floor2 = options.opticsFloorSigmaPx * options.opticsFloorSigmaPx;
    const double s = std::sqrt(std::max(0.0, sigma * sigma - floor2));
    est.sigmaPx = s;
    // A disc's projection is a semicircle of variance d²/16: the disc of equal moment has d = 4σ.
    est.discDiameterPx = 4.0 * s;
    est.edgeWidthPx = std::sqrt(
        std::max(0.0, width * width - kGaussianRisePerSigma * kGaussianRisePerSigma * floor2));
    // Light beyond the core that the second moment weighs by distance² (crowded texture, another
    // edge within reach of the blur) widens σ and barely moves the rise: the disc is no wider than
    // the one whose rise is the measured rise, to within the rise's own scatter on clean edges.
    // Near 0° and 45° the rise is not read (EdgeMeasurement::riseMeasured) and 4 σ stands.
    if (measuredRise)
        est.discDiameterPx = std::min(
            *est.discDiameterPx, (1.0 + kDiscRiseSlack) * *est.edgeWidthPx / kDiscRisePerDiameter);
    est.edgeCount = agreeing;
    if (shw > 0) est.haloFraction = sh / shw;
    if (smw > 0) est.mtf50CyPx = sm / smw, est.mtf50pCyPx = smp / smw;
    // Confidence: mean rank of the agreeing edges, more edges better, discounted by the
    // share of edges that disagree with them (mixed widths: soft objects or several depths).
    // One segment alone cannot tell the blur from its own softness or from a neighbour's light
    // within reach, and is never confident (under kLowBlurConfidence): on dense texture half of
    // the lone segments read more than 10 % off, against a fifth of two or more that agree.
    const double agreement = static_cast<double>(agreeing) / good.size();
    est.confidence =
        std::clamp((sRank / agreeing) * (1.0 - std::exp(-agreeing / 1.5)) * agreement, 0.0, 1.0);
    if (agreeing == 1) est.confidence = std::min(est.confidence, kLoneMost);
    return est;
}

}  // namespace infocus::blur_detail

namespace infocus {

using namespace blur_detail;

std::vector<EdgeMeasurement> measureEdges(const Luma8& luma, const Rect& roi,
                                          const BlurOptions& options) {
    RowPrefetcher none;
    std::vector<EdgeMeasurement> edges =
        measureEdgesPrefetching(luma, roi, sanitized(options), none);
    for (EdgeMeasurement& e : edges)
        if (e.lineSpread)
            if (const auto m = mtf50Of(*e.lineSpread))
                e.mtf50CyPx = m->mtf50CyPx, e.mtf50pCyPx = m->mtf50pCyPx;
    return edges;
}

BlurEstimate measureBlur(const Luma8& luma, const Rect& roi, const BlurOptions& options) {
    const BlurOptions o = sanitized(options);
    RowPrefetcher none;
    return blurFromEdges(measureEdgesPrefetching(luma, roi, o, none), o);
}

std::vector<BlurEstimate> measureBlurRegions(const Luma8& luma, std::span<const Rect> rois,
                                             const BlurOptions& options) {
    const BlurOptions o = sanitized(options);
    std::vector<BlurEstimate> out;
    out.reserve(rois.size());
    for (size_t i = 0; i < rois.size(); ++i) {
        RowPrefetcher next =
            i + 1 < rois.size() ? RowPrefetcher(luma, rois[i + 1]) : RowPrefetcher();
        out.push_back(blurFromEdges(measureEdgesPrefetching(luma, rois[i], o, next), o));
        next.finish();
    }
    return out;
}

}  // namespace infocus
