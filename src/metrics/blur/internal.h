// SPDX-License-Identifier: MIT
// Internal: what the stages of the blur-width engine share (docs/blur.md, "Method"): the region's
// candidates (candidates.cpp), the edge's geometry (geometry.cpp), its ESF and fit (esf.cpp), the
// measurement of one edge (edge.cpp), the region's blur (region.cpp) and the light of grey levels
// (transfer.cpp). Nothing here is public API.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "infocus/blur.h"
#include "kernels.h"

namespace infocus::blur_detail {

using detail::chooseKernels;
using detail::Kernels;

// ---- Constants the stages share.

// Variance of a 1 px box (the pixel's own area), px². Its projection on any edge normal is a
// trapezoid of variance (cos²θ + sin²θ)/12 = 1/12, whatever the edge angle.
constexpr double kPixelVariance = 1.0 / 12.0;

// Quality above which an edge counts towards a region's blur at all (blurFromEdges).
constexpr double kUsableQuality = 0.05;

// 10–90 % rise of a Gaussian edge per unit σ (docs/design.md).
constexpr double kGaussianRisePerSigma = 2.5631;

// Segment lengths tried per seed (halved from the longest down to 6 px: 48 → 6 is 4).
constexpr int kMaxLengths = 8;

// Half-width of the window in which the reported line-spread variance is taken, in its σ, and the
// contrast-to-spread ratio above which the spread beside an edge counts as noise (fitEsf).
constexpr double kMomentSigmas = 3.0, kCleanCnr = 20.0;
// Most sizings of the narrow window by its own σ, and the share of the contrast a halo may place
// at each of its ends (fitEsf): two thirds of a Gaussian's 0.135 % beyond 3 σ, so that flare of
// 1–5 % at 5–20 × the core's σ reads the core (docs/blur.md, "Flare and aberrations"); and the
// narrowest half-width (px) of that window tested for a halo.
constexpr int kCoreIterations = 4;
constexpr double kHaloTailShare = 0.0009, kHaloMinHalfPx = 2.5;

// The widest σ (px) at which an edge's halo is counted (BlurEstimate::haloFraction).
constexpr double kHaloSigmaPx = 2.0;

// Half-width (px) of the slab across the edge in which the geometry is first fitted.
constexpr double kProbeHalfWidthPx = 6.0;

// ---- Light (transfer.cpp).

// The encoded value (0..1) of light @p l (0..1) under @p tf: the inverse of decodeLight.
double encodeLight(TransferFunction tf, double l);

constexpr int kDecodeSteps = 16;  // table entries per grey level
// Grey levels decoded to linear light (BlurOptions::transfer). Blur spreads light, so the ESF's
// profile (its line spread's moments, rise and overshoot) is taken in light: each bin's mean
// grey level goes through the inverse transfer function, tabulated every 1/16 grey level and
// interpolated (a bin's pixels lie at one place of the profile and differ by noise, over which
// the curve is nearly straight). What judges an edge stays in the frame's grey levels, where
// its thresholds were set: the plateaus' levels and contrast (encoded again), their pixels'
// spread and the clip levels; so do the candidates and the one-sided test.
struct Decoding {
    TransferFunction tf = TransferFunction::Linear;
    const std::vector<double>* table = nullptr;  // 255 × light at grey i/16; null: linear
    // The grey level of light @p level (both 0..255).
    double encode(double level) const { return 255.0 * encodeLight(tf, level / 255.0); }
};

// The decoding of @p tf (its table built once); Linear decodes nothing.
Decoding decodingFor(TransferFunction tf);

// ---- What the stages pass on.

// A rectangle of pixels.
struct Bounds {
    int x0, y0, x1, y1;  // half-open [x0, x1) × [y0, y1)
};

// A seed: a grid point, its Sobel gradient (grey levels per pixel), |g|² and grid index.
struct Candidate {
    int x, y;
    float gx, gy, mag2;
    size_t gridIndex;  // in CandidateGrid
};

// A region's candidate Sobel grid (the scratch of the last candidateGrid call on this thread):
// gradients and |g|² per point, row by row from (x0, y0) at step px; the region's peak |g|² and
// the least |g|² a candidate needs.
struct CandidateGrid {
    const int16_t* gx = nullptr;
    const int16_t* gy = nullptr;
    const int32_t* m = nullptr;
    size_t size = 0;
    int perRow = 0, rows = 0, step = 1, x0 = 0, y0 = 0;
    int32_t peak = 0, least = 0;
};

// An oriented rectangle on the image: centre c, unit normal n (dark → bright), tangent
// t = (−ny, nx); half-extent hw across the edge, hl along it.
struct Patch {
    double cx, cy, nx, ny, hw, hl;
    double u(double x, double y) const { return (x - cx) * nx + (y - cy) * ny; }
    double t(double x, double y) const { return -(x - cx) * ny + (y - cy) * nx; }
};

// Where an edge was measured, kept from frame to frame by BlurTracker: the patch its ESF was
// sampled in (on its fitted line), the line's straightness, the window the ESF fit's second
// start began with (0: none; measureSegment), and the derivative threshold and slice count of
// its geometry fit.
struct EdgeTrack {
    Patch patch;
    double straight = 0.0, narrowStart = 0.0, threshold = 0.0;
    int slices = 0;
};

// ---- Candidates (candidates.cpp).

// The candidate grid of region @p roi: a Sobel gradient (grey levels per pixel) on a sparse grid,
// in one pass that stores the grid's gradients and magnitudes (the kernel computes only the
// grid's points) and the region's peak; the threshold relative to it then sets the least |g|².
// Scratch is reused across regions.
CandidateGrid candidateGrid(const Luma8& img, const Bounds& roi, const BlurOptions& o,
                            const Kernels& k);

// Points of a candidate grid, handed out strongest first (CandidateList::at): the strongest
// `strongest()` of the grid's passing points, or, after a region has looked at those, the next
// weaker ones that oneSided does not pass over (weakerCandidates). A list of up to kMaxOrderKeys
// keys comes in order; the keys of a longer one are put in order a block at a time as they are
// asked for (a region looks at about 20 of its 64), each block as long as all the blocks before
// it, so that a list walked to its end is ordered in O(n log n).
class CandidateList {
public:
    CandidateList() = default;
    // The @p size keys @p keys (of @p listed, the first @p ordered of them already in order) of
    // @p grid's @p strongest strongest points, the least of which is @p lowest; @p judged when
    // oneSided has passed them.
    CandidateList(const CandidateGrid& grid, uint64_t* keys, size_t listed, size_t size,
                  size_t ordered, size_t strongest, uint64_t lowest, bool judged)
        : grid_(&grid),
          keys_(keys),
          listed_(listed),
          size_(size),
          ordered_(ordered),
          strongest_(strongest),
          lowest_(lowest),
          judged_(judged) {}
    size_t size() const { return size_; }
    // How many of the grid's strongest points the list was drawn from, and the least of them.
    size_t strongest() const { return strongest_; }
    uint64_t lowest() const { return lowest_; }
    // True when every point handed out has passed oneSided already.
    bool judged() const { return judged_; }
    // The @p i-th strongest (i < size()).
    Candidate at(size_t i) {
        while (i >= ordered_) {
            // Keys are unique (they hold the grid index), so the block after ordered_ is the
            // same whichever way the rest was left: the order is exact.
            const size_t next = std::min(size_, ordered_ + std::max(kBlock, ordered_));
            std::nth_element(keys_ + ordered_, keys_ + next, keys_ + listed_, std::greater<>());
            std::sort(keys_ + ordered_, keys_ + next, std::greater<>());
            ordered_ = next;
        }
        const size_t q = detail::candidateIndex(keys_[i]);
        return {grid_->x0 + static_cast<int>(q % grid_->perRow) * grid_->step,
                grid_->y0 + static_cast<int>(q / grid_->perRow) * grid_->step,
                grid_->gx[q] / 8.0f,
                grid_->gy[q] / 8.0f,
                static_cast<float>(grid_->m[q]) * (1.0f / 64.0f),
                q};
    }

private:
    static constexpr size_t kBlock = 16;
    const CandidateGrid* grid_ = nullptr;
    uint64_t* keys_ = nullptr;
    size_t listed_ = 0, size_ = 0, ordered_ = 0, strongest_ = 0;
    uint64_t lowest_ = 0;
    bool judged_ = false;
};

// The @p cap strongest passing points of @p grid, strongest first (the list lives until the next
// call on this thread).
CandidateList strongestCandidates(const CandidateGrid& grid, const Kernels& k, size_t cap);

// Whether the gradient about the grid point @p q is one-sided: Σ g·n / Σ |g·n| ≥ kMinOneSided
// over the grid points within kOneSidedRadiusPx, n the point's gradient. A lone edge gives about
// 1. A bar, a thin line or crowded texture, whose two sides lie within a few pixels, gives
// gradients of both signs; its ESF has no two plateaus and the fit would lose its contrast after
// all the pixel work.
bool oneSided(const CandidateGrid& g, size_t q, const Kernels& k);

// The points among the @p cap strongest of @p grid that are weaker than @p below (the least of the
// list a region has looked at) and that oneSided does not pass over, strongest first. A region
// that asks for them has passed over all its stronger seeds (traces, text, a fine chart's bars),
// and may pass over most of these too: judging them before they are put in order spares it the
// ordering of seeds it would skip (on a chart of fine bars, every one). oneSided depends on the
// grid alone, so the region measures the seeds it would have measured, in the same order.
CandidateList weakerCandidates(const CandidateGrid& grid, const Kernels& k, size_t cap,
                               uint64_t below);

// ---- Geometry (geometry.cpp).

// The rows of @p p inside @p b as kernel spans (scratch reused across calls): for every row
// holding pixel centres inside the patch, its pixels x0..x1 and the patch coordinates (u0, t0)
// of pixel x0; along the row u grows by nx and t by −ny per pixel, so the kernels step them
// instead of projecting every pixel.
std::span<const detail::GeometrySpan> patchSpans(const Luma8& img, const Bounds& b, const Patch& p,
                                                 const Kernels& k);

// The directional derivative's moments in one slice along the edge: Σw, Σw·u, Σw·t, Σw·u².
struct Slice {
    double w, wu, wt, wuu;
};

// Fills @p out with the @p slices slices of @p p (equal widths along the edge) of the pixels whose
// derivative along the normal exceeds @p threshold, weighted by the excess.
void geometrySlices(const Luma8& img, const Bounds& b, const Kernels& k, const Patch& p,
                    double threshold, int slices, Slice* out);

// The edge as the line u = a + slope·t in a patch's coordinates, from slice centroids.
struct LineFit {
    bool ok = false;
    double a = 0, slope = 0;
    double straight = 0;  // RMS scatter of the centroids about the line, px
    double spread2 = 0;   // the derivative's variance across the edge within a slice, px²
};

// Weighted least squares e = a + b·t through the centroids (t_k, e_k) of the @p n slices @p s,
// weights Σw; needs three slices with an edge.
LineFit fitLine(const Slice* s, int n);

// Moves @p p onto the line @p f: the centre onto it, the normal turned by atan(slope)
// (n' ∝ n − slope·t̂).
void moveOnto(Patch& p, const LineFit& f);

// How trimToEdge left a segment.
enum class Trim {
    Whole,     ///< no end of the edge within its reach: unchanged
    Trimmed,   ///< shortened to stop short of the edge's ends
    TooShort,  ///< the edge's whole part is shorter than the least length: unchanged
};

// Shortens @p p (on its line, spanning ±p.hl about the probe's seed) to the part of the edge the
// probe's @p n slices of ±@p probeHalfLength found whole: where the derivative falls below half
// the strongest slice's and then stops for good (a corner), the edge ends, and the segment stops
// @p marginPx short of it so that the other side's blur stays out of the ESF.
Trim trimToEdge(Patch& p, const Slice* s, int n, double probeHalfLength, double marginPx,
                double minHalfLengthPx);

// ---- ESF (esf.cpp).

// An ESF's non-empty bins (see detail::EsfBins), in ascending position; scratch reused.
struct BinList {
    std::vector<double> pos, value, withinVar, pixelVar, count;
    size_t size = 0;
    // Room for @p n bins and the kernels' slack; the arrays to fill.
    detail::EsfBins reserve(size_t n) {
        for (auto* v : {&pos, &value, &withinVar, &pixelVar, &count})
            if (v->size() < n + detail::kEsfBinSlack) v->resize(n + detail::kEsfBinSlack);
        return {pos.data(), value.data(), withinVar.data(), pixelVar.data(), count.data()};
    }
};

// An ESF fit (fitEsf): the line spread's centroid and variances, the plateaus' level, contrast
// and pixel spread, the 10–90 % rise, and what judges the edge.
struct EsfFit {
    bool ok = false;
    bool needWider = false;  // the edge's spread does not fit in the sampled width
    double mean = 0, varLsf = 0, lo = 0, contrast = 0, noise = 0, rise = 0, binVar = 0;
    double varCore = 0;        // line-spread variance in the narrow window: the width reported
    double overshoot = 0;      // largest excursion past a plateau, fraction of the contrast
    double plateauPixels = 0;  // pixels beside the window that set the plateau levels
    // lo and contrast of the profile itself: in light where the frame is decoded (Decoding),
    // else lo and contrast.
    double profileLo = 0, profileContrast = 0;
};

// The terms of each pair of neighbouring bins (i, i + 1) that lineSpreadMoments adds up, computed
// once per ESF (detail::pairTermsGeneric): the running sums of the step and its products (so that
// the fit's every window costs the same whatever its width), and the midpoint x and the bins' own
// spread c for the window's end pairs, whose step runs from or to a plateau level instead.
struct PairTerms {
    std::vector<double> x, c, sums;
    /// Makes the terms of @p bins due: they are computed when a fit first asks for them (get).
    /// A fit that ends at its first window (the ESF's two ends within minContrast, or too few
    /// bins) asks for none: on the 12 px bench frame a fifth of the ESFs' pixels go to such fits.
    void defer(const BinList& bins, const Kernels& k) { src = &bins, kernels = &k, ready = false; }
    /// The terms of the bins last deferred (whose BinList must still hold them), computed on the
    /// first call.
    const PairTerms& get() {
        if (!ready) set(*src, *kernels), ready = true;
        return *this;
    }

private:
    const BinList* src = nullptr;
    const Kernels* kernels = nullptr;
    bool ready = false;
    void set(const BinList& bins, const Kernels& k) {
        const size_t n = bins.size;
        if (x.size() < n + detail::kEsfBinSlack)
            x.resize(n + detail::kEsfBinSlack), c.resize(n + detail::kEsfBinSlack);
        if (sums.size() < 4 * (n + 1)) sums.resize(4 * (n + 1));
        k.pairTerms({bins.pos.data(), bins.value.data(), bins.withinVar.data()}, 0,
                    static_cast<int>(n), x.data(), c.data(), sums.data());
    }
};

// Sharpening halos of the ESF @p bins about an edge at @p mu whose line spread has the standard
// deviation @p sd (px): the lesser of the two sides' excursions past their far plateaus (the
// outermost 2 px of each side), on the ESF averaged over 1 px, within 2.5 sd + 2.5 px of the
// edge, as a fraction of the far plateaus' contrast. Blur by any PSF keeps an edge's profile
// between its plateaus, so a clean edge gives about 0; an unsharp mask raises a bright halo on
// one side and a dark one on the other. Clutter (another edge in one side) mostly gives one.
double esfHalo(const BinList& bins, double mu, double sd);

// Second moment of the line spread from the binned ESF. The edge's extent is found in a window
// grown or shrunk to 4 σ + 1 px about the centroid (holds 99.99 % of a Gaussian and all of a
// disc), with the plateau levels just outside it; that window's variance (varLsf) rates and
// screens the edge. Noise in a bin weighs on the moment with the square of its distance from the
// centroid, so its share grows as the window's cube: for a sharp edge the wide window is mostly
// noise (a 0.7 px Gaussian scattered 4–6 % per edge at 2 % noise). The width reported (varCore) is
// therefore taken in a ±3 σ window about the centroid, the ESF beyond it set to the same plateau
// levels, so the tail mass between 3 σ and the plateaus (0.27 % of a Gaussian, none of a disc)
// is kept, placed at the window's edge. That misses (x² − 9σ²) over a Gaussian's tails, 0.5 % of
// its variance (σ 0.25 % low), and nothing of a disc from d = 2 px up (its projection ends at
// 2 σ, the pixel's at 0.71 px). Where the ESF still moves beyond both ends by more than
// kHaloTailShare and noise explain (a halo: flare, glare), the levels at the ends are taken
// instead, with kHaloTailShare of tail, and the window is sized by its own σ: the width then
// describes the core, not the halo. The bins' own spread is removed here, the pixel's 1/12 by the
// caller. The window starts over the whole patch (@p halfWidth about its middle), or, with
// @p startRadius > 0, over ±startRadius about the patch's line (u = 0).
EsfFit fitEsf(const BinList& bins, PairTerms& terms, double halfWidth, double minContrast,
              const Decoding& dec, double startRadius = 0.0);

// Bins the pixels of @p p by their distance across the edge (the slanted-edge ESF) into @p bins,
// their mean grey levels decoded to light by @p dec.
void sampleEsf(const Luma8& img, const Bounds& b, const Kernels& k, const Patch& p, double binPx,
               const Decoding& dec, BinList& bins);

// ---- One edge (edge.cpp).

// An edge's bend in units of what its blur tolerates: its straightness (RMS scatter of the slice
// centroids, px) over 0.3 px + a quarter of its σ (px). The quality's straightness share is
// e^(−bend²), both for a measured edge and for judging a probe's segment lengths.
double relativeBend(double straightPx, double sigmaPx);

// σ (px) of the line spread guessed from the spread of the thresholded derivative across the
// edge (spread2, px²): a Gaussian's derivative above 0.2 of its peak has 0.72 σ, a disc's 0.95 σ.
double guessSigma(const LineFit& f);

// Whether the fit @p f measures an edge: fitted, and neither clipped nor collapsed. A clipped
// edge (a plateau at black or white) has lost the part of its spread beyond the clip, so its
// moment says nothing about the blur; an LSF narrower than half the pixel's own spread is no
// imaged edge (JPEG block seams, a window collapsed on clutter), and a fit without plateau
// pixels has nothing to trust.
bool usable(const EsfFit& f);

// Measures the edge along @p patch (on the edge's line, half-length set, @p slices slices along
// it) from the line @p line found in the probe. The ESF is sampled as wide as the guessed blur
// needs; where the probe's slab may have cut the derivative, the geometry is refitted in the
// patch's own slab and the ESF widened while its line spread does not fit. On return @p patch is
// where the edge was sampled.
std::optional<EdgeMeasurement> measureSegment(const Luma8& img, const Bounds& b,
                                              const BlurOptions& o, const Kernels& k, Patch& patch,
                                              double threshold, LineFit line, int slices,
                                              EdgeTrack& track);

// measureSegment on @p patch kept clear of the edge's ends (trimToEdge on the probe's
// @p probeSlices slices of ±@p probeHalfLength), by 3 σ + 1 px of the guessed σ and then of the
// measured one: a shortened segment has its line fitted again in its own slab and is measured
// again; one that would be shorter than the least length is measured as it was.
std::optional<EdgeMeasurement> measureClearOfEnds(const Luma8& img, const Bounds& b,
                                                  const BlurOptions& o, const Kernels& k,
                                                  Patch& patch, double threshold,
                                                  const LineFit& line, int slices, EdgeTrack& track,
                                                  const Slice* probe, int probeSlices,
                                                  double probeHalfLength, double minHalfLengthPx);

// The edge of @p track measured again in @p luma (BlurTracker): its ESF sampled in the same
// patch, on the same line, and fitted as measureSegment fitted it there, so that an unchanged
// frame gives the same measurement. The probe and the segment lengths that found the edge are
// not repeated: on photographs they and the failed tries take most of an edge's pixel work.
// Where that fit gives no usable edge, the edge may have moved (focus breathing, a camera that
// shifts): its line is fitted again in the patch's slab, as measureSegment refits it, and the
// edge measured there, widened as measureSegment widens it while its line spread does not fit.
// Empty when it gives no usable edge then either, or at once when @p rescue is false.
std::optional<EdgeMeasurement> remeasureEdge(const Luma8& luma, const Bounds& sb,
                                             const BlurOptions& o, const Kernels& k,
                                             EdgeTrack& track, bool rescue);

// ---- The region (region.cpp).

// The part of @p r inside a @p w × @p h image (intersect: a rectangle near INT_MAX clips).
Bounds clipRect(const Rect& r, int w, int h);

// Asks the cache for the pixels the candidate pass of the next region will read, a few rows at
// a time while the current region is measured. A 1080p frame (2 MB) does not stay in a core's
// L2 cache (1 MB here) from one pass over the regions to the next, and the Sobel pass reads each
// region row by row, a stride apart, with nothing else to do while a row comes from memory: on
// the bench frame it took 1.8 M cycles a frame when its rows were cold and 0.6 M when warm.
// Fetched during the seeds' pixel work, which reads only what the Sobel pass already brought in,
// the rows arrive in time. Empty (no region) does nothing.
class RowPrefetcher {
public:
    RowPrefetcher() = default;
    RowPrefetcher(const Luma8& img, const Rect& roi) : img_(&img) {
        const Bounds b = clipRect(roi, img.width, img.height);
        // The rows and columns the candidate Sobel reads (its vector loads reach 32 px on).
        y_ = std::max(b.y0 - 1, 0), y1_ = std::min(b.y1 + 1, img.height);
        xa_ = std::max(b.x0 - 1, 0), xb_ = std::min(b.x1 + 32, img.width - 1);
        if (b.x0 >= b.x1 || b.y0 >= b.y1) y_ = y1_;  // an empty region: nothing to fetch
    }
    // Asks for the next @p rows rows.
    void fetch(int rows) {
        constexpr int kLine = 64;
        for (const int end = std::min(y_ + rows, y1_); y_ < end; ++y_) {
            const uint8_t* row = img_->row(y_);
            for (int x = xa_; x < xb_; x += kLine)
                __builtin_prefetch(row + x);
            __builtin_prefetch(row + xb_);
        }
    }
    // Asks for every row not asked for yet.
    void finish() { fetch(y1_ - y_); }

private:
    const Luma8* img_ = nullptr;
    int y_ = 0, y1_ = 0, xa_ = 0, xb_ = 0;
};

// @p given with every knob in its range (blur.h): a value outside it taken as the nearest one
// inside, one that is not a number as the default. The engine's sizes follow from these (the
// bins of a patch, the slices of a probe, the candidate grid), so an unchecked value would cost
// memory or read past the scratch rather than only give a poor measurement.
BlurOptions sanitized(const BlurOptions& given);

// What the seeds of one region share: the region, where sampling may reach, and the segment
// lengths tried (halved from the longest down to 6 px), whose probe slices nest: the central
// 4·2^j of them cover the j-th shortest length.
struct RegionSetup {
    Bounds r, sb;
    double halfLength = 0.0;
    double lengths[kMaxLengths] = {};
    int nLengths = 0, slices = 0;
};

// The setup of region @p roi of @p luma, @p o sanitized; empty when the region or the image is
// too small to hold a 3 × 3 gradient.
std::optional<RegionSetup> regionSetup(const Luma8& luma, const Rect& roi, const BlurOptions& o);

// measureEdges with @p options already sanitized, asking the cache for the pixels of @p next
// meanwhile. When @p found is given, where each edge was measured is added to it, in the edges'
// order (BlurTracker measures them there again on later frames).
std::vector<EdgeMeasurement> measureEdgesPrefetching(const Luma8& luma, const Rect& roi,
                                                     const BlurOptions& options,
                                                     RowPrefetcher& next,
                                                     std::vector<EdgeTrack>* found = nullptr);

// The region's blur from its edges (measureBlur), @p options already sanitized.
BlurEstimate blurFromEdges(const std::vector<EdgeMeasurement>& edges, const BlurOptions& options);

}  // namespace infocus::blur_detail
