// SPDX-License-Identifier: MIT
// Blur over a stream of frames: each region's edges measured again where they were found, a few
// regions searched afresh a frame (docs/blur.md, "Streams").
#include <algorithm>
#include <chrono>
#include <cmath>

#include "internal.h"

namespace infocus {

using namespace blur_detail;

// What the tracker keeps of one region: where its edges were measured when it was last searched
// (those still found since), and whether it waits for a search.
struct BlurTracker::Impl {
    struct Region {
        std::vector<EdgeTrack> edges;
        bool due = true;        // lost an edge since its last search
        uint64_t searched = 0;  // the frame of its last search
    };
    BlurOptions options;
    int searchesPerFrame = 0;
    double searchBudgetS = 0.0;  // seconds of searching a frame; 0: no limit
    int width = 0, height = 0;
    std::vector<Rect> rois;
    std::vector<Region> regions;
    uint64_t frame = 0;  // frames measured since the last full search
};

BlurTracker::BlurTracker(const BlurOptions& options, int searchesPerFrame, double searchBudgetS)
    : impl_(std::make_unique<Impl>()) {
    impl_->options = sanitized(options);
    impl_->searchesPerFrame = std::max(searchesPerFrame, 1);
    impl_->searchBudgetS = std::isnan(searchBudgetS) ? 0.0 : std::max(searchBudgetS, 0.0);
}

BlurTracker::~BlurTracker() = default;
BlurTracker::BlurTracker(BlurTracker&&) noexcept = default;
BlurTracker& BlurTracker::operator=(BlurTracker&&) noexcept = default;

void BlurTracker::reset() {
    impl_->rois.clear();
    impl_->regions.clear();
}

std::vector<BlurEstimate> BlurTracker::measure(const Luma8& luma, std::span<const Rect> rois) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    const auto elapsedS = [&] {
        return std::chrono::duration<double>(Clock::now() - start).count();
    };
    Impl& t = *impl_;
    const bool same = luma.width == t.width && luma.height == t.height &&
                      std::equal(rois.begin(), rois.end(), t.rois.begin(), t.rois.end());
    const size_t n = rois.size();
    if (!same) {
        t.width = luma.width, t.height = luma.height;
        t.rois.assign(rois.begin(), rois.end());
        t.regions.assign(n, {});
        t.frame = 0;
    }
    std::vector<BlurEstimate> out(n);
    std::vector<char> searched(n, 0);
    // A region searched afresh: its edges and where they were found replace the old ones.
    const auto search = [&](size_t i, size_t next) {
        Impl::Region& r = t.regions[i];
        RowPrefetcher ahead = next < n ? RowPrefetcher(luma, rois[next]) : RowPrefetcher();
        r.edges.clear();
        out[i] = blurFromEdges(measureEdgesPrefetching(luma, rois[i], t.options, ahead, &r.edges),
                               t.options);
        ahead.finish();
        r.due = false;
        r.searched = t.frame;
        searched[i] = 1;
    };
    if (!same) {
        // The first frame: every region in order, within the budget where there is one, so that
        // a large stream's first frame is not its slowest; those left wait as due, searched
        // first from the next frame on.
        for (size_t i = 0; i < n; ++i) {
            if (i > 0 && t.searchBudgetS > 0.0 && elapsedS() >= t.searchBudgetS) break;
            search(i, i + 1);
        }
    } else {
        // This frame's searches, at most searchesPerFrame: first the regions not searched for
        // 2n / searchesPerFrame frames, then those that lost an edge, then those searched
        // longest ago, oldest first within each. A frame's cost stays bounded while the scene
        // changes, lost edges are looked for again at once, and no region goes unsearched for
        // long (a sharper edge may have come into focus there).
        std::vector<size_t> order(n);
        for (size_t i = 0; i < n; ++i)
            order[i] = i;
        // Oldest search first; equal ages in region order, so that the round is deterministic.
        std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
            return t.regions[a].searched < t.regions[b].searched;
        });
        const auto most = static_cast<size_t>(t.searchesPerFrame);
        const uint64_t overdue = 2 * n / most;
        std::vector<size_t> queue;
        std::vector<char> queued(n, 0);
        const auto take = [&](auto&& wanted) {
            for (const size_t i : order)
                if (queue.size() < most && !queued[i] && wanted(t.regions[i]))
                    queue.push_back(i), queued[i] = 1;
        };
        take([&](const Impl::Region& r) { return t.frame - r.searched >= overdue; });
        take([](const Impl::Region& r) { return r.due; });
        take([](const Impl::Region&) { return true; });
        // With a time budget, the searches stop once it is spent (one at least, so that the
        // round goes on): on frames far out of focus a search costs many times more.
        for (size_t q = 0; q < queue.size(); ++q) {
            if (q > 0 && t.searchBudgetS > 0.0 && elapsedS() >= t.searchBudgetS) break;
            search(queue[q], q + 1 < queue.size() ? queue[q + 1] : n);
        }
    }
    // Every other region: its edges measured again where they were found. With a time budget,
    // an edge that fails there is looked for again (refitted, widened) only while the frame has
    // taken less than twice the budget: after a cut most edges fail, and their rescue, not
    // their one ESF each, is what makes that frame slow. Dropped, they wait for a search.
    const Kernels kernels = chooseKernels(t.options);
    for (size_t i = 0; i < n; ++i) {
        if (searched[i]) continue;
        Impl::Region& r = t.regions[i];
        std::vector<EdgeMeasurement> edges;
        if (const auto setup = regionSetup(luma, rois[i], t.options)) {
            size_t kept = 0;
            for (EdgeTrack& e : r.edges)
                if (const auto m = remeasureEdge(
                        luma, setup->sb, t.options, kernels, e,
                        t.searchBudgetS <= 0.0 || elapsedS() < 2.0 * t.searchBudgetS)) {
                    edges.push_back(*m);
                    r.edges[kept++] = e;
                }
            r.due = kept < r.edges.size();
            r.edges.resize(kept);
        }
        out[i] = blurFromEdges(edges, t.options);
    }
    ++t.frame;
    return out;
}

LiveBlurSearch liveBlurSearch(double fps) {
    LiveBlurSearch out;
    if (!(fps > kLiveBlurSearchFps) || !std::isfinite(fps)) return out;
    const double share = kLiveBlurSearchFps / fps;
    out.searchesPerFrame =
        std::max(1, static_cast<int>(std::lround(kLiveBlurSearchesPerFrame * share)));
    out.budgetS = kLiveBlurSearchBudgetS * share;
    return out;
}

}  // namespace infocus
