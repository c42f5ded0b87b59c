// SPDX-License-Identifier: MIT
// The text face: a line a second for a log or a pipe.
#include <cstdio>

#include "src/live/present.h"
#include "src/live/printed_face.h"

namespace infocus {

std::string textLine(const LiveState& s) {
    char blur[32] = "-";
    if (s.blurPx) std::snprintf(blur, sizeof blur, "%.1f", *s.blurPx);
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "frame %llu  %.1f fps  %s %.5g  %5.1f%% of peak  %-7s%s  blur %s px",
                  static_cast<unsigned long long>(s.frame), s.fps, s.metric.c_str(), s.score,
                  s.percentOfPeak, std::string(trendName(s.trend)).c_str(),
                  s.pastPeak ? "  past the peak: back up" : "", blur);
    std::string line = buf;
    if (s.lens) {
        std::snprintf(buf, sizeof buf, "  lens %.4g %s", s.lens->value, s.lens->unit.c_str());
        line += buf;
    }
    if (s.inFocusDistanceM) line += "  in focus at " + present::distanceText(s.inFocusDistanceM);
    if (s.dofNearM)
        line += "  DoF " + present::distanceText(s.dofNearM) + " to " +
                present::distanceText(s.dofFarM);
    std::snprintf(buf, sizeof buf, "  dropped %llu  skipped %llu  latency %.1f/%.1f ms",
                  static_cast<unsigned long long>(s.dropped),
                  static_cast<unsigned long long>(s.skipped), s.latencyP50Ms, s.latencyP99Ms);
    line += buf;
    if (const std::string af = present::autofocusText(s.autofocus); !af.empty()) line += "  " + af;
    if (!s.status.empty()) line += "  (" + s.status + ")";
    return line;
}

std::unique_ptr<Face> makeTextFace() {
    return makePrintedFace(textLine);
}

}  // namespace infocus
