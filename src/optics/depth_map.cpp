// SPDX-License-Identifier: MIT
#include "infocus/depth_map.h"

#include <limits>

#include "infocus/optics.h"

namespace infocus {

std::optional<double> focusFromLensPosition(const FrameAnalysis& a) {
    if (!a.lens || !a.lens->dioptres) return std::nullopt;
    return optics::distanceFromDioptres(*a.lens->dioptres);
}

DepthMap depthMap(const FrameAnalysis& a, const std::optional<optics::CameraGeometry>& camera,
                  const DepthMapOptions& options) {
    DepthMap m;
    std::vector<optics::BlurSample> samples;
    m.regions.reserve(a.regions.size());
    for (size_t i = 0; i < a.regions.size(); ++i) {
        const RegionResult& r = a.regions[i];
        RegionDepth d;
        d.region = i;
        d.used = r.blurWidthPx && r.confidence >= options.minConfidence;
        if (d.used) {
            if (camera)
                d.roots = optics::depthFromBlur(camera->lens, camera->focusDistance,
                                                *r.blurWidthPx * camera->pixelPitch,
                                                options.blurFloorPx * camera->pixelPitch);
            samples.push_back({r.rect.x + 0.5 * r.rect.w, r.rect.y + 0.5 * r.rect.h, *r.blurWidthPx,
                               r.confidence});
        }
        m.regions.push_back(d);
    }
    optics::PlaneFitOptions fit;
    fit.blurFloor = options.blurFloorPx;
    m.plane = optics::fitBlurPlane(samples, a.width, a.height, fit);
    if (camera) {
        const auto limit = optics::farRootLimit(camera->lens, camera->focusDistance);
        m.farRootLimitPx = limit.value_or(0.0) / camera->pixelPitch;
        if (m.plane) m.scenes = optics::scenePlanes(*m.plane, *camera);
    }
    if (m.plane)
        for (RegionDepth& d : m.regions) {
            if (!d.used) continue;
            const Rect& r = a.regions[d.region].rect;
            const double s = m.plane->signedAt(r.x + 0.5 * r.w, r.y + 0.5 * r.h);
            d.side = s > 0.0 ? 1 : (s < 0.0 ? -1 : 0);
        }
    return m;
}

}  // namespace infocus
