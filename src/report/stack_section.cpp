// SPDX-License-Identifier: MIT
// The stack section of the HTML report (stackReportHtml in include/infocus/report.h): the focus
// map, the composite, and a few regions' curves with their peaks and blur V fits, all inline.
#include <algorithm>
#include <cmath>

#include "html.h"
#include "infocus/report.h"
#include "infocus/stack.h"
#include "infocus/units.h"

namespace infocus {

using report_detail::base64;
using report_detail::escapeHtml;
using report_detail::fmt;

namespace {

const char* kStackStyle = R"(<style>
body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}
h1{font-size:1.6em}h2{border-bottom:2px solid #ddd;padding-bottom:.2em;margin-top:2em}
img{max-width:100%}svg{max-width:100%;height:auto}figure{margin:1em 0}
figcaption{font-size:.85em;color:#555}
</style>)";

std::string pngImage(const std::string& png, const std::string& alt) {
    if (png.empty()) return "";
    return "<img alt=\"" + escapeHtml(alt) + "\" src=\"data:image/png;base64," +
           base64(reinterpret_cast<const unsigned char*>(png.data()), png.size()) + "\"/>";
}

// Up to four textured regions worth a look: the nearest and farthest peaks, and the two
// sharpest of the rest.
std::vector<const StackRegion*> regionsToShow(const StackResult& r) {
    std::vector<const StackRegion*> ok;
    for (const StackRegion& g : r.regions)
        if (g.status == StackRegionStatus::Ok && g.peakFrame) ok.push_back(&g);
    if (ok.size() <= 4) return ok;
    std::sort(ok.begin(), ok.end(), [](const StackRegion* a, const StackRegion* b) {
        return *a->peakFrame < *b->peakFrame;
    });
    std::vector<const StackRegion*> out{ok.front(), ok.back()};
    std::vector<const StackRegion*> rest(ok.begin() + 1, ok.end() - 1);
    std::sort(rest.begin(), rest.end(), [](const StackRegion* a, const StackRegion* b) {
        return a->peak->score > b->peak->score;
    });
    out.insert(out.begin() + 1, rest.begin(), rest.begin() + 2);
    return out;
}

// One region's sharpness (relative to its peak) and blur widths over the frames, the V fitted
// to the widths, and both vertices.
void curvePlot(std::string& h, const StackResult& r, const StackRegion& g) {
    const size_t n = r.frames.size();
    double bmax = 1.0;
    for (size_t i = 0; i < n; ++i)
        if (g.usable[i] && g.blurWidth[i]) bmax = std::max(bmax, *g.blurWidth[i]);
    bmax *= 1.1;
    const double smax = g.peak ? g.peak->score : 1.0;
    const double W = 520, H = 240, L = 44, B = 30, T = 10, R = 44;
    const auto X = [&](double f) { return L + f / std::max<double>(1, n - 1) * (W - L - R); };
    const auto Ys = [&](double s) { return H - B - std::clamp(s / smax, 0.0, 1.0) * (H - B - T); };
    const auto Yb = [&](double b) { return H - B - std::min(b, bmax) / bmax * (H - B - T); };
    h +=
        fmt("<figure style=\"display:inline-block\"><svg viewBox=\"0 0 %.0f %.0f\" width=\"%.0f\" "
            "xmlns=\"http://www.w3.org/2000/svg\" font-size=\"11\">",
            W, H, W);
    h += fmt("<line x1=\"%.0f\" y1=\"%.0f\" x2=\"%.0f\" y2=\"%.0f\" stroke=\"#000\"/>", L, H - B,
             W - R, H - B);
    for (size_t i = 0; i < n; i += std::max<size_t>(1, n / 8))
        h += fmt("<text x=\"%.1f\" y=\"%.0f\" text-anchor=\"middle\">%zu</text>", X(i), H - B + 14,
                 i);
    h += fmt("<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"middle\">frame</text>", (W + L - R) / 2,
             H - 2);
    h += fmt("<text x=\"4\" y=\"%.0f\" fill=\"#258\">sharpness</text>", T + 4);
    h += fmt("<text x=\"%.0f\" y=\"%.0f\" fill=\"#d60\" text-anchor=\"end\">blur %.0f px</text>",
             W - 2, T + 4, bmax);
    std::string line;
    for (size_t i = 0; i < n; ++i) {
        if (!g.usable[i]) continue;
        line += fmt("%.1f,%.1f ", X(i), Ys(g.sharpness[i]));
        if (g.blurWidth[i])
            h += fmt(
                "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"%.1f\" fill=\"#d60\" fill-opacity=\"0.7\"/>",
                X(i), Yb(*g.blurWidth[i]), 1.5 + 2.5 * g.confidence[i]);
    }
    h += "<polyline fill=\"none\" stroke=\"#258\" stroke-width=\"2\" points=\"" + line + "\"/>";
    if (g.blurFit) {
        std::string v;
        // The V drawn through every frame and its vertex (straight between frames).
        std::vector<double> fs;
        for (size_t i = 0; i < n; ++i)
            fs.push_back(static_cast<double>(i));
        if (g.blurPeakFrame) fs.push_back(*g.blurPeakFrame);
        std::sort(fs.begin(), fs.end());
        for (double f : fs)
            v += fmt("%.1f,%.1f ", X(f), Yb(r.blurModelPx(*g.blurFit, r.axisAt(f))));
        h += "<polyline fill=\"none\" stroke=\"#e00\" stroke-width=\"1.5\" points=\"" + v + "\"/>";
    }
    if (g.peakFrame)
        h +=
            fmt("<line x1=\"%.1f\" y1=\"%.0f\" x2=\"%.1f\" y2=\"%.0f\" stroke=\"#258\" "
                "stroke-dasharray=\"4 3\"/>",
                X(*g.peakFrame), T, X(*g.peakFrame), H - B);
    if (g.blurPeakFrame)
        h +=
            fmt("<line x1=\"%.1f\" y1=\"%.0f\" x2=\"%.1f\" y2=\"%.0f\" stroke=\"#e00\" "
                "stroke-dasharray=\"2 3\"/>",
                X(*g.blurPeakFrame), T, X(*g.blurPeakFrame), H - B);
    h += "</svg><figcaption>" + fmt("Region (%d, %d): sharpness peak at frame ", g.col, g.row) +
         (g.peakFrame ? fmt("%.2f", *g.peakFrame) : std::string("none")) +
         " (blue), blur V vertex at frame " +
         (g.blurPeakFrame ? fmt("%.2f", *g.blurPeakFrame) : std::string("none")) + " (red)" +
         (g.inFocusDistance ? ", in focus at " + formatDistance(*g.inFocusDistance) : "") +
         ".</figcaption></figure>";
}

}  // namespace

std::string stackReportHtml(const StackResult& r, const std::string& focusMapPng,
                            const std::string& compositePng) {
    std::string h =
        "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>infocus focus "
        "stack</title>";
    h += kStackStyle;
    h += "</head><body><h1>Focus stack: " + escapeHtml(r.source) + "</h1>";
    int textured = 0, both = 0, agree = 0;
    for (const StackRegion& g : r.regions) {
        if (g.status != StackRegionStatus::Ok) continue;
        ++textured;
        if (g.agree) ++both, agree += *g.agree;
    }
    h +=
        fmt("<p>%zu frames of %d &times; %d pixels, curves over %s. %d of %zu regions have "
            "texture; in %d of the %d with both, the sharpness peak and the blur V's vertex "
            "agree within one frame.</p>",
            r.frames.size(), r.width, r.height,
            r.axisUnit == "frame" ? "the frame index" : escapeHtml(r.axisUnit).c_str(), textured,
            r.regions.size(), agree, both);
    h += "<h2>Focus map</h2><figure>" + pngImage(focusMapPng, "focus map") +
         fmt("<figcaption>Where each part of the image is sharpest: the peak of the sharpness "
             "of windows %d px wide every %d px, interpolated between frames (a Gaussian through "
             "the sharpest frame and its neighbours).</figcaption></figure>",
             2 * r.map.stepPx, r.map.stepPx);
    h += "<h2>All-in-focus composite</h2><figure>" + pngImage(compositePng, "composite") +
         "<figcaption>Each part of the image from the frames about its peak, the focus map "
         "interpolated between its cells so that the frames blend without seams.</figcaption>"
         "</figure>";
    h += "<h2>Regions' curves</h2>";
    for (const StackRegion* g : regionsToShow(r))
        curvePlot(h, r, *g);
    h += "</body></html>\n";
    return h;
}

}  // namespace infocus
