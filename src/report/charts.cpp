// SPDX-License-Identifier: MIT
// The report's SVG figures: the frame with its regions tinted by blur, the blur and sharpness
// maps, and the blur against the distance from the in-focus line.
#include <algorithm>
#include <cmath>

#include "html.h"
#include "report_impl.h"

namespace infocus {

using report_detail::escapeHtml;
using report_detail::fmt;
using report_detail::regionName;

namespace {

// The colour of a blur of @p b px against a CoC of @p coc px: green while sharp, then yellow
// through red as the blur grows to 16 × the CoC (a log scale: defocus doubles per step).
std::string blurColour(double b, double coc) {
    if (b <= coc) return "#1a9850";
    const double t = std::clamp(std::log2(b / coc) / 4.0, 0.0, 1.0);
    const auto mix = [](int a, int c, double u) { return static_cast<int>(a + (c - a) * u + 0.5); };
    int r, g, bl;
    if (t < 0.5) {
        r = mix(0xfe, 0xfc, 2 * t), g = mix(0xe0, 0x8d, 2 * t), bl = mix(0x8b, 0x59, 2 * t);
    } else {
        r = mix(0xfc, 0xd7, 2 * t - 1), g = mix(0x8d, 0x30, 2 * t - 1),
        bl = mix(0x59, 0x27, 2 * t - 1);
    }
    return fmt("#%02x%02x%02x", r, g, bl);
}

// A grey for a sharpness score, relative to the frame's best region (black: none, white: best).
std::string sharpnessGrey(double s, double best) {
    const int v = best > 0 ? static_cast<int>(std::clamp(s / best, 0.0, 1.0) * 235.0 + 20.0) : 20;
    return fmt("#%02x%02x%02x", v, v, v);
}

}  // namespace

void ReportWriter::Impl::overlay(std::string& h, const Entry& e) const {
    const FrameAnalysis& a = e.a;
    const double coc = o.optics.cocPx;
    const double sw = std::max(1.0, a.width / 400.0);
    h +=
        fmt("<figure><svg viewBox=\"0 0 %d %d\" width=\"%d\" xmlns=\"http://www.w3.org/2000/svg\">",
            a.width, a.height, std::min(a.width, 1000));
    if (!e.jpeg.empty())
        h += fmt("<image width=\"%d\" height=\"%d\" preserveAspectRatio=\"none\" "
                 "href=\"data:image/jpeg;base64,",
                 a.width, a.height) +
             e.jpeg + "\"/>";
    else
        h += fmt("<rect width=\"%d\" height=\"%d\" fill=\"#888\"/>", a.width, a.height);
    for (const RegionDepth& d : e.map.regions) {
        const RegionResult& r = a.regions[d.region];
        if (!d.used) continue;
        const bool sharp = *r.blurWidthPx <= coc;
        h += fmt(
            "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"%s\" fill-opacity=\"%.2f\" "
            "stroke=\"%s\" stroke-width=\"%.1f\"><title>region %s: blur %.2f px, confidence "
            "%.2f</title></rect>",
            r.rect.x, r.rect.y, r.rect.w, r.rect.h, blurColour(*r.blurWidthPx, coc).c_str(),
            sharp ? 0.25 : 0.45, sharp ? "#00ff66" : "none", 2 * sw, regionName(r).c_str(),
            *r.blurWidthPx, r.confidence);
    }
    if (e.map.plane && e.map.plane->inFocusLine) {
        const auto& s = *e.map.plane->inFocusLine;
        h +=
            fmt("<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#e00\" "
                "stroke-width=\"%.1f\" stroke-dasharray=\"%.0f %.0f\"/>",
                s.x0, s.y0, s.x1, s.y1, 3 * sw, 12 * sw, 6 * sw);
    }
    h += "</svg><figcaption>The frame with each measured region tinted by its blur width "
         "(<span style=\"color:#1a9850\">green</span>: within the circle of confusion, outlined; "
         "yellow to red: up to 16 times it; untinted: no usable edge). The dashed red line is "
         "where the fitted plane of focus crosses the image.</figcaption></figure>";
}

void ReportWriter::Impl::maps(std::string& h, const Entry& e) const {
    const FrameAnalysis& a = e.a;
    int cols = 0, rows = 0;
    for (const auto& r : a.regions)
        cols = std::max(cols, r.col + 1), rows = std::max(rows, r.row + 1);
    if (cols * rows != static_cast<int>(a.regions.size())) return;  // ROIs, not a grid
    double best = 0.0;
    for (const auto& r : a.regions)
        if (r.status == RegionStatus::Ok) best = std::max(best, r.sharpness);
    const int cw = 60, ch = 34;
    const auto grid = [&](bool blur) {
        h +=
            fmt("<svg viewBox=\"0 0 %d %d\" width=\"%d\" xmlns=\"http://www.w3.org/2000/svg\" "
                "font-size=\"11\" text-anchor=\"middle\">",
                cols * cw, rows * ch, std::min(cols * cw, 520));
        for (const auto& r : a.regions) {
            const int x = r.col * cw, y = r.row * ch;
            std::string fill, label, ink = "#000";
            if (r.status != RegionStatus::Ok) {
                // Not measurable (too dark or clipped): no score, no blur.
                fill = "#eee";
                label = std::string(regionStatusName(r.status));
            } else if (blur) {
                fill = r.blurWidthPx ? blurColour(*r.blurWidthPx, o.optics.cocPx) : "#eee";
                label = r.blurWidthPx ? fmt("%.1f", *r.blurWidthPx) : "-";
            } else {
                fill = sharpnessGrey(r.sharpness, best);
                label = fmt("%.3g", r.sharpness);
                if (best > 0 && r.sharpness / best < 0.5) ink = "#fff";
            }
            h += fmt(
                "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"%s\" stroke=\"#fff\"/>"
                "<text x=\"%d\" y=\"%d\" fill=\"%s\">%s</text>",
                x, y, cw, ch, fill.c_str(), x + cw / 2, y + ch / 2 + 4, ink.c_str(), label.c_str());
        }
        h += "</svg>";
    };
    h += "<figure>";
    grid(true);
    h += "<figcaption>Blur width per region, pixels (disc diameter, the thin-lens model's "
         "&Delta;X<sub>i</sub>; "
         "- : no usable edge).</figcaption></figure><figure>";
    grid(false);
    h +=
        fmt("<figcaption>Sharpness per region (%s; white: the frame's sharpest region). "
            "Sharpness ranks regions; only the blur width is an absolute "
            "measure.</figcaption></figure>",
            escapeHtml(a.metric).c_str());
}

void ReportWriter::Impl::vPlot(std::string& h, const Entry& e) const {
    if (!e.map.plane || !(e.map.plane->gradient > 0.0)) return;
    const optics::BlurPlane& p = *e.map.plane;
    const FrameAnalysis& a = e.a;
    struct Pt {
        double s, b;
        bool inlier;
    };
    std::vector<Pt> pts;
    size_t k = 0;  // index among the fitted samples (BlurPlane::inlier)
    for (const RegionDepth& d : e.map.regions) {
        if (!d.used) continue;
        const RegionResult& r = a.regions[d.region];
        const double s =
            p.signedAt(r.rect.x + 0.5 * r.rect.w, r.rect.y + 0.5 * r.rect.h) / p.gradient;
        pts.push_back({s, *r.blurWidthPx, k < p.inlier.size() && p.inlier[k]});
        ++k;
    }
    if (pts.empty()) return;
    double s0 = pts[0].s, s1 = pts[0].s, bmax = o.optics.cocPx * 1.5;
    for (const Pt& q : pts)
        s0 = std::min(s0, q.s), s1 = std::max(s1, q.s), bmax = std::max(bmax, q.b);
    const double span = std::max(s1 - s0, 1.0);
    s0 -= 0.05 * span, s1 += 0.05 * span, bmax *= 1.1;
    const double W = 640, H = 300, L = 50, B = 30, T = 10, R = 24;
    const auto X = [&](double s) { return L + (s - s0) / (s1 - s0) * (W - L - R); };
    const auto Y = [&](double b) { return H - B - b / bmax * (H - B - T); };
    h +=
        fmt("<figure><svg viewBox=\"0 0 %.0f %.0f\" width=\"%.0f\" "
            "xmlns=\"http://www.w3.org/2000/svg\" "
            "font-size=\"11\">",
            W, H, W);
    // The circle of confusion: blur under it counts as sharp.
    h +=
        fmt("<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"#1a9850\" "
            "fill-opacity=\"0.15\"/>",
            L, Y(o.optics.cocPx), W - L - R, Y(0) - Y(o.optics.cocPx));
    h += fmt("<line x1=\"%.0f\" y1=\"%.1f\" x2=\"%.0f\" y2=\"%.1f\" stroke=\"#000\"/>", L, Y(0),
             W - R, Y(0));
    h += fmt("<line x1=\"%.0f\" y1=\"%.1f\" x2=\"%.0f\" y2=\"%.1f\" stroke=\"#000\"/>", L, Y(0), L,
             Y(bmax));
    for (int i = 0; i <= 4; ++i) {
        const double b = bmax * i / 4, s = s0 + (s1 - s0) * i / 4;
        h += fmt("<text x=\"%.0f\" y=\"%.1f\" text-anchor=\"end\">%.1f</text>", L - 4, Y(b) + 4, b);
        h += fmt("<text x=\"%.1f\" y=\"%.0f\" text-anchor=\"middle\">%.0f</text>", X(s), H - B + 14,
                 s);
    }
    h +=
        fmt("<text x=\"%.0f\" y=\"%.0f\" text-anchor=\"middle\">signed distance from the in-focus "
            "line, px</text>",
            (W + L) / 2, H - 2);
    h +=
        fmt("<text x=\"12\" y=\"%.0f\" transform=\"rotate(-90 12 %.0f)\" "
            "text-anchor=\"middle\">blur, px</text>",
            H / 2, H / 2);
    // The fitted V: |g s| (the signed blur is g s along the blur gradient).
    const auto vy = [&](double s) { return Y(std::min(bmax, p.gradient * std::abs(s))); };
    h +=
        fmt("<polyline fill=\"none\" stroke=\"#e00\" stroke-width=\"2\" points=\"%.1f,%.1f "
            "%.1f,%.1f %.1f,%.1f\"/>",
            X(s0), vy(s0), X(std::clamp(0.0, s0, s1)), vy(std::clamp(0.0, s0, s1)), X(s1), vy(s1));
    for (const Pt& q : pts)
        h += fmt("<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3.5\" fill=\"%s\" stroke=\"#258\"/>", X(q.s),
                 Y(std::min(q.b, bmax)), q.inlier ? "#258" : "none");
    h +=
        fmt("</svg><figcaption>Each region's blur against its distance from the in-focus line, "
            "across it (filled: fitted, hollow: outlier). For a flat scene the thin-lens model's "
            "blur is "
            "|p<sub>0</sub> + p<sub>1</sub>x + p<sub>2</sub>y|: a V whose slope here is %.4g px of "
            "blur per px across the image. The green band is the circle of confusion (%.2f px): "
            "where the V stays inside it is the depth of field in the image.</figcaption></figure>",
            p.gradient, o.optics.cocPx);
}

}  // namespace infocus
