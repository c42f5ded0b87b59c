// SPDX-License-Identifier: MIT
// The QA page of `infocus check --report`: the regions drawn over the frame in pass/fail
// colours with Imatest's zone boundaries, the criteria table, and the through-focus curves of
// MTF50 when a stack was judged (docs/qa.md).
#include <turbojpeg.h>

#include <algorithm>
#include <cmath>

#include "area_resize.h"
#include "html.h"
#include "infocus/report.h"

namespace infocus {

using report_detail::base64;
using report_detail::escapeHtml;
using report_detail::fmt;

namespace {

const char* kQaStyle = R"(<style>
body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}
h2{border-bottom:2px solid #ddd;padding-bottom:.2em;margin-top:2em}
table{border-collapse:collapse;font-size:.85em}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}
th{background:#f4f4f4}td.pass{color:#070}td.fail{color:#b00;font-weight:bold}
svg{max-width:100%;height:auto}figcaption{font-size:.85em;color:#555}
</style>)";

// The frame reduced to at most @p width pixels wide, as base64 JPEG; empty without one.
std::string frameJpeg(const Luma8& luma, int width) {
    if (luma.empty()) return {};
    Image<uint8_t> reduced;
    Luma8 small = luma;
    if (luma.width > width) {
        const int h =
            std::max(1, static_cast<int>(std::lround(double(luma.height) * width / luma.width)));
        reduced = report_detail::resizeArea(luma, width, h);
        small = reduced.view();
    }
    tjhandle tj = tjInitCompress();
    unsigned char* out = nullptr;
    unsigned long size = 0;
    std::string b64;
    if (tj && tjCompress2(tj, small.data, small.width, static_cast<int>(small.stride), small.height,
                          TJPF_GRAY, &out, &size, TJSAMP_GRAY, 85, TJFLAG_FASTDCT) == 0)
        b64 = base64(out, size);
    if (out) tjFree(out);
    if (tj) tjDestroy(tj);
    return b64;
}

std::string zoneMap(const qa::Verdict& v, const std::string& jpeg) {
    const int w = std::max(v.width, 1), h = std::max(v.height, 1);
    std::string s = fmt("<svg viewBox=\"0 0 %d %d\" width=\"%d\">", w, h, std::min(w, 960));
    if (!jpeg.empty())
        s += fmt("<image width=\"%d\" height=\"%d\" href=\"data:image/jpeg;base64,", w, h) + jpeg +
             "\"/>";
    else
        s += fmt("<rect width=\"%d\" height=\"%d\" fill=\"#ddd\"/>", w, h);
    // Zone boundaries: 30 % and 75 % of the centre-to-corner distance.
    const double diag = std::hypot(0.5 * w, 0.5 * h);
    for (double share : {0.30, 0.75})
        s +=
            fmt("<circle cx=\"%.1f\" cy=\"%.1f\" r=\"%.1f\" fill=\"none\" stroke=\"#36c\" "
                "stroke-width=\"%.1f\" stroke-dasharray=\"%.1f\"/>",
                0.5 * w, 0.5 * h, share * diag, w / 400.0, w / 80.0);
    for (const qa::RegionVerdict& r : v.regions) {
        const char* colour = !r.mtf50CyPx ? "#999" : r.pass ? "#2a2" : "#d22";
        s +=
            fmt("<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"%s\" "
                "fill-opacity=\"0.25\" stroke=\"%s\" stroke-width=\"%.1f\"/>",
                r.rect.x, r.rect.y, r.rect.w, r.rect.h, colour, colour, w / 500.0);
        if (r.mtf50CyPx)
            s += fmt(
                "<text x=\"%.1f\" y=\"%.1f\" font-size=\"%.1f\" text-anchor=\"middle\" "
                "fill=\"#000\">%.3f</text>",
                r.rect.x + 0.5 * r.rect.w, r.rect.y + 0.5 * r.rect.h, r.rect.h / 5.0, *r.mtf50CyPx);
    }
    return s + "</svg>";
}

std::string criteriaTable(const qa::Verdict& v) {
    std::string s =
        "<table><tr><th>criterion</th><th>measured</th><th>limit</th><th>result</th>"
        "<th>note</th></tr>";
    for (const qa::Criterion& c : v.criteria) {
        const std::string unit = c.unit.empty() ? "" : " " + c.unit;
        s += "<tr><td>" + escapeHtml(c.name) + "</td><td>" +
             (c.measured ? fmt("%.4g", *c.measured) + escapeHtml(unit) : "-") + "</td><td>" +
             (c.isMinimum ? "&ge; " : "&le; ") + fmt("%.4g", c.limit) + escapeHtml(unit) +
             "</td><td class=\"" + (c.pass ? "pass\">pass" : "fail\">FAIL") + "</td><td>" +
             escapeHtml(c.reason) + "</td></tr>";
    }
    return s + "</table>";
}

// MTF50 against position, one line per region coloured by zone, a dot at each best focus.
std::string curves(const qa::ThroughFocus& tf) {
    if (tf.axis.size() < 2) return {};
    const double x0 = *std::min_element(tf.axis.begin(), tf.axis.end());
    const double x1 = *std::max_element(tf.axis.begin(), tf.axis.end());
    double top = 0.0;
    for (const qa::RegionFocus& r : tf.regions)
        for (const auto& m : r.mtf50)
            if (m) top = std::max(top, *m);
    if (!(x1 > x0) || !(top > 0)) return {};
    top *= 1.1;
    const double W = 720, H = 320, L = 50, B = 30;
    auto px = [&](double x) { return L + (x - x0) / (x1 - x0) * (W - L - 10); };
    auto py = [&](double y) { return H - B - y / top * (H - B - 10); };
    std::string s = fmt("<svg viewBox=\"0 0 %.0f %.0f\" width=\"%.0f\">", W, H, W);
    s += fmt("<line x1=\"%.0f\" y1=\"%.0f\" x2=\"%.0f\" y2=\"%.0f\" stroke=\"#000\"/>", L, H - B,
             W - 10, H - B);
    s += fmt("<line x1=\"%.0f\" y1=\"10\" x2=\"%.0f\" y2=\"%.0f\" stroke=\"#000\"/>", L, L, H - B);
    s += fmt("<text x=\"%.0f\" y=\"%.0f\" font-size=\"12\">%.4g</text>", L, H - 8, x0);
    s += fmt("<text x=\"%.0f\" y=\"%.0f\" font-size=\"12\" text-anchor=\"end\">%.4g %s</text>",
             W - 10, H - 8, x1, escapeHtml(tf.axisUnit).c_str());
    s += fmt("<text x=\"4\" y=\"20\" font-size=\"12\">%.2f cy/px</text>", top);
    for (const qa::RegionFocus& r : tf.regions) {
        const char* colour = r.zone == qa::Zone::Centre   ? "#c22"
                             : r.zone == qa::Zone::Middle ? "#2a2"
                                                          : "#36c";
        std::string pts;
        for (size_t i = 0; i < r.mtf50.size() && i < tf.axis.size(); ++i)
            if (r.mtf50[i]) pts += fmt("%.1f,%.1f ", px(tf.axis[i]), py(*r.mtf50[i]));
        if (!pts.empty())
            s += "<polyline fill=\"none\" stroke-opacity=\"0.6\" stroke=\"" + std::string(colour) +
                 "\" points=\"" + pts + "\"/>";
        if (r.bestPosition)
            s += fmt("<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3\" fill=\"%s\"/>", px(*r.bestPosition),
                     py(*r.bestMtf50), colour);
    }
    return s + "</svg>";
}

}  // namespace

std::string qaReportHtml(const std::vector<qa::Verdict>& verdicts,
                         const std::optional<qa::ThroughFocus>& tf, const Luma8& firstFrame,
                         const std::string& source) {
    std::string h = "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>infocus check " +
                    escapeHtml(source) + "</title>" + kQaStyle + "</head><body>";
    int passed = 0;
    for (const qa::Verdict& v : verdicts)
        passed += v.pass;
    h += "<h1>QA: " + escapeHtml(source) + "</h1>";
    h += fmt("<p>%d of %zu %s passed.</p>", passed, verdicts.size(), tf ? "stacks" : "frames");
    const std::string jpeg = frameJpeg(firstFrame, 960);
    for (size_t i = 0; i < verdicts.size(); ++i) {
        const qa::Verdict& v = verdicts[i];
        h += tf ? std::string("<h2>Stack, at each region's best focus: ")
                : fmt("<h2>Frame %llu: ", static_cast<unsigned long long>(v.frame));
        h += v.pass ? "PASS</h2>" : "FAIL</h2>";
        if (!v.reason.empty()) h += "<p>" + escapeHtml(v.reason) + "</p>";
        h += "<figure>" + zoneMap(v, i == 0 ? jpeg : std::string()) +
             "<figcaption>Regions with their MTF50 (cy/px): green pass, red fail, grey no "
             "confident edge. Dashed circles: 30 % and 75 % of the centre-to-corner distance "
             "(centre, middle, corners).</figcaption></figure>";
        h += criteriaTable(v);
    }
    if (tf) {
        h += "<h2>MTF50 through focus</h2><figure>" + curves(*tf) +
             "<figcaption>MTF50 of each region against position (red centre, green middle, blue "
             "corners); dots: best focus.</figcaption></figure>";
        if (tf->tiltAcross)
            h +=
                fmt("<p>Tilt across the frame %.4g %s, field curvature (corners minus centre) "
                    "%.4g %s.</p>",
                    *tf->tiltAcross, escapeHtml(tf->axisUnit).c_str(), *tf->fieldCurvature,
                    escapeHtml(tf->axisUnit).c_str());
    }
    return h + "</body></html>\n";
}

}  // namespace infocus
