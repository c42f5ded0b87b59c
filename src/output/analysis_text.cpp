// SPDX-License-Identifier: MIT
// The `infocus analyze` record as CSV (one row per region) and as a table for people.
#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>

#include "infocus/analysis_output.h"
#include "infocus/blur.h"

namespace infocus {

namespace {

std::string csvNumber(const std::optional<double>& v) {
    if (!v) return "";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", *v);
    return buf;
}

}  // namespace

void writeAnalysisCsv(std::ostream& out, const FrameAnalysis& a, bool header) {
    if (header)
        out << "frame,timestamp_ns,lens_value,lens_unit,width,height,col,row,x,y,w,h,sharpness,"
               "edge_width_px,blur_sigma_px,blur_width_px,mtf50_cy_px,mtf50p_cy_px,confidence,"
               "status,"
               "reason\n";
    for (const auto& r : a.regions) {
        // A region that could not be measured has empty fields (its reason has no comma).
        const bool ok = r.status == RegionStatus::Ok;
        const auto value = [ok](const std::optional<double>& v) {
            return ok ? csvNumber(v) : std::string();
        };
        out << a.frame << ',' << a.timestampNs << ',' << (a.lens ? csvNumber(a.lens->value) : "")
            << ',' << (a.lens ? a.lens->unit : "") << ',' << a.width << ',' << a.height << ','
            << r.col << ',' << r.row << ',' << r.rect.x << ',' << r.rect.y << ',' << r.rect.w << ','
            << r.rect.h << ',' << value(r.sharpness) << ',' << value(r.edgeWidthPx) << ','
            << value(r.blurSigmaPx) << ',' << value(r.blurWidthPx) << ',' << value(r.mtf50CyPx)
            << ',' << value(r.mtf50pCyPx) << ',' << value(r.confidence) << ','
            << regionStatusName(r.status) << ',' << (ok ? "" : r.statusReason) << '\n';
    }
}

void writeAnalysisTable(std::ostream& out, const FrameAnalysis& a, bool grid) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "frame %llu  %dx%d  t=%.3f s", (unsigned long long)a.frame,
                  a.width, a.height, a.timestampNs * 1e-9);
    out << buf;
    if (a.lens) {
        std::snprintf(buf, sizeof buf, "  lens %.4g %s", a.lens->value, a.lens->unit.c_str());
        out << buf;
    }
    if (a.noiseSigma) {
        std::snprintf(buf, sizeof buf, "  noise σ %.2f", *a.noiseSigma);
        out << buf;
    } else if (!a.noiseReason.empty()) {
        out << "  noise σ -";
    }
    if (a.regions.empty() || hasMeasurableRegion(a)) {
        std::snprintf(buf, sizeof buf, "  whole frame %s %.4g", a.metric.c_str(), a.frameSharpness);
        out << buf;
    } else {
        out << "  whole frame - (no region could be measured)";
    }
    out << "\n";
    if (!grid) {
        for (const auto& r : a.regions) {
            if (r.status != RegionStatus::Ok) {
                std::snprintf(buf, sizeof buf, "  roi %d (%d,%d %dx%d): ", r.col, r.rect.x,
                              r.rect.y, r.rect.w, r.rect.h);
                out << buf << r.statusReason << "\n";
                continue;
            }
            std::snprintf(buf, sizeof buf, "  roi %d (%d,%d %dx%d): %s %.4g", r.col, r.rect.x,
                          r.rect.y, r.rect.w, r.rect.h, a.metric.c_str(), r.sharpness);
            out << buf;
            if (r.blurWidthPx) {
                std::snprintf(buf, sizeof buf, "  blur %.2f px (σ %.2f px, confidence %.2f)",
                              *r.blurWidthPx, r.blurSigmaPx.value_or(0), r.confidence);
                out << buf;
                if (r.mtf50CyPx) {
                    std::snprintf(buf, sizeof buf, "  MTF50 %.3f cy/px (MTF50P %.3f)", *r.mtf50CyPx,
                                  r.mtf50pCyPx.value_or(*r.mtf50CyPx));
                    out << buf;
                }
            }
            out << "\n";
        }
        return;
    }
    int cols = 0, rows = 0;
    double peak = 0;
    for (const auto& r : a.regions) {
        cols = std::max(cols, r.col + 1);
        rows = std::max(rows, r.row + 1);
        if (r.status == RegionStatus::Ok) peak = std::max(peak, r.sharpness);
    }
    out << "  sharpness (" << a.metric << ", % of the sharpest region)";
    for (int c = 0; c < std::max(0, cols * 5 - 38); ++c)
        out << ' ';
    out << "   blur width, px (disc diameter; (w) confidence under " << kLowBlurConfidence
        << "; - no edge; dark, clip: not measurable)\n";
    for (int row = 0; row < rows; ++row) {
        out << "  ";
        for (int c = 0; c < cols; ++c) {
            const auto& r = a.regions[static_cast<size_t>(row * cols + c)];
            if (r.status == RegionStatus::Dark)
                std::snprintf(buf, sizeof buf, "%5s", "dark");
            else if (r.status == RegionStatus::Clipped)
                std::snprintf(buf, sizeof buf, "%5s", "clip");
            else
                std::snprintf(buf, sizeof buf, "%5.0f", peak > 0 ? 100 * r.sharpness / peak : 0.0);
            out << buf;
        }
        out << "   ";
        for (int c = 0; c < cols; ++c) {
            const auto& r = a.regions[static_cast<size_t>(row * cols + c)];
            if (r.status != RegionStatus::Ok) {
                std::snprintf(buf, sizeof buf, "%6s",
                              r.status == RegionStatus::Dark ? "dark" : "clip");
            } else if (r.blurWidthPx && r.confidence < kLowBlurConfidence) {
                // In parentheses: a width to take with caution (kLowBlurConfidence).
                char low[32];
                std::snprintf(low, sizeof low, *r.blurWidthPx < 99.95 ? "(%.1f)" : "(%.0f)",
                              *r.blurWidthPx);
                std::snprintf(buf, sizeof buf, "%6s", low);
            } else if (r.blurWidthPx)
                std::snprintf(buf, sizeof buf, "%6.1f", *r.blurWidthPx);
            else
                std::snprintf(buf, sizeof buf, "%6s", "-");
            out << buf;
        }
        out << "\n";
    }
}

}  // namespace infocus
