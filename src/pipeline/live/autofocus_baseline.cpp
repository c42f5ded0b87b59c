// SPDX-License-Identifier: MIT
#include "src/pipeline/live/autofocus_baseline.h"

#include <algorithm>
#include <vector>

#include "infocus/luma.h"
#include "infocus/metrics.h"

namespace infocus::live_detail {

SourceTap::SourceTap(std::unique_ptr<FrameSource> source) : source_(std::move(source)) {
    control_ = source_->focusControl();
}
Status SourceTap::start() {
    if (!control_) return makeError(ErrorKind::Unsupported, "the source has no lens to move");
    return source_->start();
}
Result<Frame> SourceTap::next(uint64_t& seen) {
    auto f = source_->next();
    if (!f) return f.error();
    seen = ++serial_;
    return f;
}
Result<LensPosition> SourceTap::lensPosition() {
    return control_->get();
}
Status SourceTap::moveLens(double value, uint64_t& capturedBefore) {
    capturedBefore = serial_;
    return control_->set(value);
}
FocusRange SourceTap::range() const {
    return control_->range();
}
int SourceTap::settleFrames() const {
    return control_->settleFrames();
}
int SourceTap::framesToSettle(double from, double to) const {
    return control_->framesToSettle(from, to);
}
SourceInfo SourceTap::info() const {
    return source_->info();
}

ContrastRun runContrastSchedule(FrameTap& tap, const std::optional<Rect>& subject) {
    const FocusRange range = tap.range();
    const double coarse = (range.max - range.min) / 10.0, fine = coarse / 4.0;
    uint64_t seen = 0, first = 0;
    double pos = range.defaultValue;
    if (auto p = tap.lensPosition()) pos = p->value;
    LumaConverter converter;
    std::vector<std::pair<double, double>> points;  // position, contrast
    const auto contrast = [&](const Frame& f) {
        auto luma = converter.toLuma8(f);
        if (!luma) return 0.0;
        const Rect whole{0, 0, luma->width, luma->height};
        const Rect r =
            subject ? intersect(*subject, whole)
                    : Rect{luma->width / 4, luma->height / 4, luma->width / 2, luma->height / 2};
        return regionSharpness(*luma, r, SharpnessParams{});
    };
    const auto settleAt = [&](double to) {
        uint64_t before = 0;
        (void)tap.moveLens(to, before);
        if (first == 0) first = before;
        for (int i = 0; i < tap.framesToSettle(pos, to); ++i)
            (void)tap.next(seen);
        pos = to;
        return tap.next(seen);
    };
    const auto measureAt = [&](double to) {
        auto f = settleAt(to);
        const double c = f ? contrast(*f) : 0.0;
        points.emplace_back(to, c);
        return c;
    };
    const auto scan = [&](double from, double to, double step, double& bestPos) {
        double best = 0;
        for (double d = from; d <= to + 1e-9 * step; d += step) {
            const double c = measureAt(d);
            if (c > best) {
                best = c;
                bestPos = d;
            } else if (c < 0.75 * best) {
                break;
            }
        }
    };
    double bestPos = range.min;
    scan(range.min, range.max, coarse, bestPos);
    points.clear();
    scan(std::max(range.min, bestPos - coarse), std::min(range.max, bestPos + coarse), fine,
         bestPos);
    std::sort(points.begin(), points.end());
    size_t i = 0;
    for (size_t k = 0; k < points.size(); ++k)
        if (points[k].second > points[i].second) i = k;
    double target = points.empty() ? pos : points[i].first;
    if (i > 0 && i + 1 < points.size()) {
        const double a = points[i - 1].second, b = points[i].second, c = points[i + 1].second;
        const double den = a - 2 * b + c;
        if (den < 0) target += fine * 0.5 * (a - c) / den;
    }
    (void)settleAt(target);  // the first frame that shows it
    return {target, static_cast<int>(seen - first)};
}

}  // namespace infocus::live_detail
