// SPDX-License-Identifier: MIT
// The slanted-edge ESF: the patch's pixels binned across the edge, the second moment of its line
// spread fitted in a settling window, and its halos (docs/blur.md, "ESF" and "Moment").
#include <limits>

#include "internal.h"

namespace infocus::blur_detail {

namespace {

// Centroid and variance of the line spread between bins @p il and @p ir, the ESF taken as @p lo
// at il and @p hi at ir (the plateau levels), and the mean variance of the bins' own spread
// (spacing²/12 + within-bin variance of the positions) that each difference of two bins adds.
struct Moments {
    double mean, var, binVar;
};

// Fewest non-empty bins an ESF needs to be fitted.
constexpr size_t kMinEsfBins = 8;

// The moments of the line spread (see Moments) from the pair terms @p t of @p bins.
Moments lineSpreadMoments(const PairTerms& t, size_t il, size_t ir, double lo, double hi,
                          const BinList& bins) {
    double m0 = 0, m1 = 0, m2 = 0, corr = 0;
    auto add = [&](size_t i, double l) {
        m0 += l;
        m1 += l * t.x[i];
        m2 += l * t.x[i] * t.x[i];
        corr += l * t.c[i];
    };
    // The first pair steps up from the low plateau, the last to the high one; the pairs between
    // them from the running sums.
    add(il, (il + 1 == ir ? hi : bins.value[il + 1]) - lo);
    if (ir > il + 2) {
        const double* a = t.sums.data() + 4 * (il + 1);
        const double* b = t.sums.data() + 4 * (ir - 1);
        m0 += b[0] - a[0];
        m1 += b[1] - a[1];
        m2 += b[2] - a[2];
        corr += b[3] - a[3];
    }
    if (ir > il + 1) add(ir - 1, hi - bins.value[ir - 1]);
    const double mean = m1 / m0;
    return {mean, m2 / m0 - mean * mean, corr / m0};
}

// The number of leading @p bins (in ascending position) for which @p before holds of its position
// (it holds for a prefix of them), by a bisection whose steps are conditional moves: the fit asks
// for a window's ends many times an ESF, and the branches of a plain bisection over 50–100 bins
// mispredict.
template <class Before>
size_t countBefore(const BinList& bins, Before before) {
    if (bins.size == 0) return 0;
    const double* base = bins.pos.data();
    for (size_t len = bins.size; len > 1;) {
        const size_t half = len / 2;
        base = before(base[half]) ? base + half : base;
        len -= half;
    }
    return static_cast<size_t>(base - bins.pos.data()) + (before(*base) ? 1 : 0);
}

// Index of the first of @p bins whose position exceeds @p x, and of the first at or right of it.
size_t firstAfter(const BinList& bins, double x) {
    return countBefore(bins, [x](double pos) { return pos <= x; });
}
size_t firstAtOrAfter(const BinList& bins, double x) {
    return countBefore(bins, [x](double pos) { return pos < x; });
}

// Calls @p fn(centre, mean) for each bin from the first at or after @p from while its position
// is at most @p to: mean is the ESF averaged over 1 px there (the bin and those less than 1 px
// after it, by a running sum), centre the middle of those bins' positions.
template <class Fn>
void forEachPixelMean(const BinList& bins, double from, double to, Fn&& fn) {
    const double* pos = bins.pos.data();
    const double* value = bins.value.data();
    const double* count = bins.count.data();
    const size_t size = bins.size;
    size_t i = firstAtOrAfter(bins, from), j = i;
    double sum = 0.0;
    double n = 0.0;  // a whole number of pixels
    for (; i < size && pos[i] <= to; ++i) {
        for (; j < size && pos[j] < pos[i] + 1.0; ++j)
            sum += value[j] * count[j], n += count[j];
        fn(0.5 * (pos[i] + pos[j - 1]), sum / n);
        sum -= value[i] * count[i], n -= count[i];
    }
}

// The ESF about @p x: the mean of the bins from @p from to @p to px of it (or the nearest bin),
// and the number of pixels averaged.
struct Level {
    double value, pixels;
};
Level levelAt(const BinList& bins, double x, double from, double to) {
    const size_t size = bins.size;
    double sum = 0.0, n = 0.0;
    for (size_t i = firstAtOrAfter(bins, x + from); i < size && bins.pos[i] <= x + to; ++i)
        sum += bins.value[i] * bins.count[i], n += bins.count[i];
    if (n > 0) return {sum / n, n};
    const size_t i = std::min(firstAtOrAfter(bins, x), size - 1);
    return {bins.value[i], std::max(bins.count[i], 1.0)};
}

}  // namespace

double esfHalo(const BinList& bins, double mu, double sd) {
    const double* pos = bins.pos.data();
    const double* value = bins.value.data();
    const double* count = bins.count.data();
    const size_t size = bins.size;
    if (size < 2) return 0.0;
    double sumLo = 0, nLo = 0, sumHi = 0, nHi = 0;
    for (size_t k = 0; k < size && pos[k] < pos[0] + 2.0; ++k)
        sumLo += value[k] * count[k], nLo += count[k];
    for (size_t k = size; k-- > 0 && pos[k] > pos[size - 1] - 2.0;)
        sumHi += value[k] * count[k], nHi += count[k];
    const double lo = sumLo / nLo, hi = sumHi / nHi;
    if (!(hi > lo)) return 0.0;
    const double reach = 2.5 * sd + 2.5;
    double above = 0.0, below = 0.0;
    // From 1 px before the reach, so that every 1 px mean centred within it is seen.
    forEachPixelMean(bins, mu - reach - 1.0, mu + reach, [&](double centre, double v) {
        if (std::abs(centre - mu) > reach) return;
        if (centre > mu)
            above = std::max(above, v - hi);
        else
            below = std::max(below, lo - v);
    });
    return std::min(above, below) / (hi - lo);
}

EsfFit fitEsf(const BinList& bins, PairTerms& terms, double halfWidth, double minContrast,
              const Decoding& dec, double startRadius) {
    EsfFit f;
    const size_t size = bins.size;
    if (size < kMinEsfBins) return f;
    const double* pos = bins.pos.data();
    const double* value = bins.value.data();
    const double* count = bins.count.data();
    const double* pixelVar = bins.pixelVar.data();
    const double first = pos[0], last = pos[size - 1];
    double mu = 0.5 * (first + last), radius = halfWidth;
    if (startRadius > 0.0) mu = 0.0, radius = std::min(startRadius, halfWidth);
    constexpr double kPlateauPx = 2.0;
    for (int iter = 0; iter < 6; ++iter) {
        const double wl = mu - radius, wr = mu + radius;
        // Plateau levels: mean over up to 2 px just outside the window (or the outermost bin).
        // The bins are in ascending position: the window's ends by bisection, then only the
        // plateau bins are visited (left before right, as a full scan would add them).
        double sl = 0, nl = 0, sr = 0, nr = 0, pv = 0, npv = 0;
        // First bin right of wl (pos > wl), first bin at or right of wr.
        const size_t afterL = firstAfter(bins, wl);
        const size_t atR = firstAtOrAfter(bins, wr);
        size_t il = afterL > 0 ? afterL - 1 : 0;
        size_t ir = std::min(atR, size - 1);
        {
            size_t i = afterL;
            while (i > 0 && pos[i - 1] > wl - kPlateauPx)
                --i;
            for (; i < afterL; ++i) {
                sl += value[i] * count[i], nl += count[i];
                pv += pixelVar[i] * count[i], npv += count[i];
            }
        }
        for (size_t i = atR; i < size && pos[i] < wr + kPlateauPx; ++i) {
            sr += value[i] * count[i], nr += count[i];
            pv += pixelVar[i] * count[i], npv += count[i];
        }
        if (wl < first) il = 0;
        if (wr > last) ir = size - 1;
        const double lo = nl > 0 ? sl / nl : value[il];
        const double hi = nr > 0 ? sr / nr : value[ir];
        // The edge is judged in the frame's grey levels (Decoding), its profile taken in light.
        const double judgedLo = dec.table ? dec.encode(lo) : lo;
        const double contrast = dec.table ? dec.encode(hi) - judgedLo : hi - lo;
        if (contrast < minContrast || ir <= il + 2) return f;
        const Moments m = lineSpreadMoments(terms.get(), il, ir, lo, hi, bins);
        mu = m.mean;
        const double var = m.var;
        f.binVar = m.binVar;
        f.varLsf = var - f.binVar;
        f.contrast = contrast;
        f.lo = judgedLo;
        f.profileLo = lo;
        f.profileContrast = hi - lo;
        f.mean = mu;
        f.noise = npv > 0 ? std::sqrt(pv / npv) : 0.0;
        f.plateauPixels = npv;
        const double newRadius = 4.0 * std::sqrt(std::max(var, 0.05)) + 1.0;
        const bool converged = std::abs(newRadius - radius) < 0.05;
        radius = newRadius;
        if (converged) break;
    }
    // The window and a plateau beside it must lie inside what was sampled.
    if (mu - radius - 1.0 < first || mu + radius + 1.0 > last) {
        f.needWider = true;
        return f;
    }
    // The variance in the narrow window, sized by the σ of the wide one (and, where it cuts a
    // halo, then by its own). Only where the spread beside the edge is small against the contrast:
    // the scatter it removes is that of white noise, while a plateau spread of clutter (other
    // edges, texture along the edge) means the ESF outside 3 σ is no tail of this edge's PSF either
    // way, and the wide window's value is kept.
    f.varCore = f.varLsf;
    if (f.contrast >= kCleanCnr * std::max(f.noise, 0.5)) {
        double centre = f.mean;
        double half = kMomentSigmas * std::sqrt(std::max(f.varLsf + f.binVar, 0.05));
        for (int iter = 0; iter < kCoreIterations; ++iter) {
            const double wl = centre - half, wr = centre + half;
            // The last bin at or left of wl (or the first), the first at or right of wr (or the
            // last).
            const size_t afterL = firstAfter(bins, wl);
            const size_t il = afterL > 0 ? afterL - 1 : 0;
            const size_t ir = std::min(firstAtOrAfter(bins, wr), size - 1);
            if (ir <= il + 2) break;
            // The light between the window's ends and the far plateaus is placed at the ends
            // (a Gaussian's tail beyond 3 σ), unless it is more than kHaloTailShare of the
            // contrast and than noise explains: then a halo (flare, glare) keeps the ESF moving
            // beyond the core, and its light, which would weigh with 9 σ², is cut to that share
            // at that end (docs/blur.md, "Flare and aberrations").
            const double c = f.profileContrast, hiFar = f.profileLo + c, tail = kHaloTailShare * c;
            const Level l = levelAt(bins, wl, -0.5, 0.5), r = levelAt(bins, wr, -0.5, 0.5);
            // A PSF's halo spreads both ways; an excess on one side only is shading or clutter.
            // Near 0° and 45° the ESF is sampled at whole-pixel spacing, too coarse to read its
            // level at an end of a sharp edge's window, and in a window narrower than ±2.5 px
            // the ±0.5 px about its end reach into the core's own tail: there the far plateaus
            // stand.
            const double el = l.value - f.profileLo, er = hiFar - r.value;
            const double noise = 2.0 * f.noise * std::sqrt(1.0 / l.pixels + 1.0 / r.pixels);
            const bool dense = f.binVar < 0.5 * kPixelVariance && half >= kHaloMinHalfPx;
            const bool halo = dense && el > tail && er > tail && el + er > 2.0 * tail + noise;
            const double lo = halo ? l.value - tail : f.profileLo;
            const double hi = halo ? r.value + tail : hiFar;
            if (!(hi - lo > 0.5 * f.profileContrast)) break;
            const Moments m = lineSpreadMoments(terms.get(), il, ir, lo, hi, bins);
            f.varCore = m.var - m.binVar;
            centre = m.mean;
            const double next = kMomentSigmas * std::sqrt(std::max(m.var, 0.05));
            // Only a halo's window is sized again: elsewhere the σ of the wide one stands (a
            // window sized by its own σ can settle on a step of clutter).
            const bool settled = !halo || std::abs(next - half) < 0.05;
            half = next;
            if (settled) break;
        }
    }
    // 10–90 % rise of the sampled ESF, searched outwards from the centroid.
    double x10 = mu, x90 = mu;
    // The last bin left of the centroid (or the first).
    const size_t beforeMu = firstAtOrAfter(bins, mu);
    const size_t c = beforeMu > 0 ? beforeMu - 1 : 0;
    auto level = [&](size_t i) { return (value[i] - f.profileLo) / f.profileContrast; };
    for (size_t i = c; i > 0; --i) {
        const double a = level(i - 1), b = level(i);
        if (a <= 0.1 && b > 0.1) {
            x10 = pos[i - 1] + (0.1 - a) / (b - a) * (pos[i] - pos[i - 1]);
            break;
        }
    }
    for (size_t i = c; i + 1 < size; ++i) {
        const double a = level(i), b = level(i + 1);
        if (a < 0.9 && b >= 0.9) {
            x90 = pos[i] + (0.9 - a) / (b - a) * (pos[i + 1] - pos[i]);
            break;
        }
    }
    f.rise = x90 - x10;
    // A clean edge rises monotonically from one plateau to the other. A second edge inside the
    // window (a thin line, a small blob, crowded texture) overshoots a plateau: measure by how
    // much, on the ESF averaged over 1 px so that noise does not count.
    double overshoot = 0.0;
    forEachPixelMean(bins, mu - radius, mu + radius, [&](double, double v) {
        overshoot = std::max({overshoot, v - (f.profileLo + f.profileContrast), f.profileLo - v});
    });
    f.overshoot = overshoot / f.profileContrast;
    f.ok = true;
    return f;
}

void sampleEsf(const Luma8& img, const Bounds& b, const Kernels& k, const Patch& p, double binPx,
               const Decoding& dec, BinList& bins) {
    const int n = static_cast<int>(std::ceil(2.0 * p.hw / binPx));
    const auto bp = static_cast<float>(binPx);
    const detail::EsfPatch e{
        static_cast<float>(p.nx), static_cast<float>(p.hw), 1.0f / bp, bp, n, 2048.0f / bp};
    // Four integer sums per bin and the spare ones (see blur_kernels.h); scratch reused.
    thread_local std::vector<uint32_t> acc;
    acc.assign(4 * static_cast<size_t>(n + detail::kEsfSpareBins), 0u);
    const auto& spans = patchSpans(img, b, p, k);
    k.esfRows(spans.data(), static_cast<int>(spans.size()), img.width, e, acc.data());
    // Written in place, one division per bin: this runs for every bin of every ESF, a hundred
    // thousand times a frame.
    bins.size = static_cast<size_t>(k.esfBins(acc.data(), 0, n, binPx, p.hw, bins.reserve(n)));
    if (!dec.table) return;
    const std::vector<double>& t = *dec.table;
    for (size_t i = 0; i < bins.size; ++i) {
        const double x = bins.value[i] * kDecodeSteps;
        const auto j = std::min(static_cast<size_t>(x), t.size() - 2);
        bins.value[i] = t[j] + (x - static_cast<double>(j)) * (t[j + 1] - t[j]);
    }
}

}  // namespace infocus::blur_detail
