// SPDX-License-Identifier: MIT
// The HTML depth-of-field report (include/infocus/report.h). Everything it draws is inline SVG
// and one JPEG per frame as a data URI, so the file can be mailed or archived on its own.
#include "infocus/report.h"

#include <turbojpeg.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>

#include "infocus/dof.h"
#include "infocus/units.h"

namespace infocus {

namespace {

std::string fmt(const char* f, ...) __attribute__((format(printf, 1, 2)));
std::string fmt(const char* f, ...) {
    va_list ap, again;
    va_start(ap, f);
    va_copy(again, ap);
    const int n = std::vsnprintf(nullptr, 0, f, ap);
    va_end(ap);
    std::string out(n > 0 ? static_cast<size_t>(n) : 0, '\0');
    if (n > 0) std::vsnprintf(out.data(), out.size() + 1, f, again);
    va_end(again);
    return out;
}

std::string escapeHtml(const std::string& s) {
    std::string out;
    out.reserve(s.size());
    for (const char c : s) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

std::string base64(const unsigned char* data, size_t n) {
    static const char* kAlphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((n + 2) / 3 * 4);
    for (size_t i = 0; i < n; i += 3) {
        const uint32_t v = (uint32_t{data[i]} << 16) |
                           (i + 1 < n ? uint32_t{data[i + 1]} << 8 : 0) |
                           (i + 2 < n ? uint32_t{data[i + 2]} : 0);
        out += kAlphabet[(v >> 18) & 63];
        out += kAlphabet[(v >> 12) & 63];
        out += i + 1 < n ? kAlphabet[(v >> 6) & 63] : '=';
        out += i + 2 < n ? kAlphabet[v & 63] : '=';
    }
    return out;
}

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

double median(std::vector<double> v) {
    if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
    const size_t m = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + m, v.end());
    if (v.size() % 2) return v[m];
    return 0.5 * (v[m] + *std::max_element(v.begin(), v.begin() + m));
}

}  // namespace

struct ReportWriter::Impl {
    struct Entry {
        FrameAnalysis a;
        std::string jpeg;  // base64, empty without an image
        DepthMap map;
        std::optional<optics::CameraGeometry> camera;
        std::string focusSource;
        std::optional<optics::DofResult> dof;
    };
    ReportOptions o;
    std::vector<Entry> entries;
    tjhandle tj = nullptr;

    ~Impl() {
        if (tj) tjDestroy(tj);
    }

    Result<std::string> thumbnail(const Luma8& luma) {
        if (luma.empty()) return std::string();
        const cv::Mat full(luma.height, luma.width, CV_8UC1, const_cast<uint8_t*>(luma.data),
                           static_cast<size_t>(luma.stride));
        cv::Mat small = full;
        if (luma.width > o.thumbnailWidth) {
            const int h = std::max(1, static_cast<int>(std::lround(double(luma.height) *
                                                                   o.thumbnailWidth / luma.width)));
            cv::resize(full, small, cv::Size(o.thumbnailWidth, h), 0, 0, cv::INTER_AREA);
        }
        if (!tj) tj = tjInitCompress();
        unsigned char* out = nullptr;
        unsigned long size = 0;
        if (!tj || tjCompress2(tj, small.data, small.cols, static_cast<int>(small.step), small.rows,
                               TJPF_GRAY, &out, &size, TJSAMP_GRAY, 85, TJFLAG_FASTDCT) != 0) {
            const std::string why = tj ? tjGetErrorStr2(tj) : "no JPEG compressor";
            if (out) tjFree(out);
            return makeError(ErrorKind::Io, "could not encode the frame for the report: " + why);
        }
        std::string b64 = base64(out, size);
        tjFree(out);
        return b64;
    }

    std::optional<optics::CameraGeometry> cameraFor(const FrameAnalysis& a, std::string& source) {
        const ReportOptics& p = o.optics;
        if (!p.lens || !p.pixelPitch) return std::nullopt;
        double focus = 0.0;
        if (p.focusDistance) {
            focus = *p.focusDistance;
            source = p.focusSource;
        } else if (const auto f = focusFromLensPosition(a)) {
            focus = *f;
            source = "lens position of the frame";
        } else {
            return std::nullopt;
        }
        if (!(focus > p.lens->focalLength)) return std::nullopt;
        return optics::CameraGeometry{*p.lens, focus, *p.pixelPitch, 0.5 * a.width, 0.5 * a.height};
    }

    void frameSection(std::string& h, const Entry& e, size_t index) const;
    void overlay(std::string& h, const Entry& e) const;
    void maps(std::string& h, const Entry& e) const;
    void vPlot(std::string& h, const Entry& e) const;
    void regionTable(std::string& h, const Entry& e) const;
};

ReportWriter::ReportWriter(ReportOptions options) : impl_(std::make_unique<Impl>()) {
    impl_->o = std::move(options);
}
ReportWriter::~ReportWriter() = default;

size_t ReportWriter::frames() const {
    return impl_->entries.size();
}

Status ReportWriter::add(const FrameAnalysis& a, const Luma8& luma) {
    Impl::Entry e;
    e.a = a;
    auto jpeg = impl_->thumbnail(luma);
    if (!jpeg) return jpeg.error();
    e.jpeg = std::move(*jpeg);
    e.camera = impl_->cameraFor(a, e.focusSource);
    e.map = depthMap(a, e.camera, impl_->o.depth);
    if (e.camera) {
        optics::DofInput in;
        in.lens = e.camera->lens;
        in.focusDistance = e.camera->focusDistance;
        in.coc = impl_->o.optics.cocPx * e.camera->pixelPitch;
        e.dof = optics::depthOfField(in);
    }
    impl_->entries.push_back(std::move(e));
    return {};
}

namespace {

const char* kStyle = R"(<style>
body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}
h1{font-size:1.6em}h2{border-bottom:2px solid #ddd;padding-bottom:.2em;margin-top:2em}
table{border-collapse:collapse;font-size:.85em}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}
th{background:#f4f4f4}.note{background:#f7f7f0;border-left:4px solid #cc9;padding:.5em 1em}
svg{max-width:100%;height:auto}figure{margin:1em 0}figcaption{font-size:.85em;color:#555}
</style>)";

std::string regionName(const RegionResult& r) {
    return fmt("(%d, %d)", r.col, r.row);
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
        best = std::max(best, r.sharpness);
    const int cw = 60, ch = 34;
    const auto grid = [&](bool blur) {
        h +=
            fmt("<svg viewBox=\"0 0 %d %d\" width=\"%d\" xmlns=\"http://www.w3.org/2000/svg\" "
                "font-size=\"11\" text-anchor=\"middle\">",
                cols * cw, rows * ch, std::min(cols * cw, 520));
        for (const auto& r : a.regions) {
            const int x = r.col * cw, y = r.row * ch;
            std::string fill, label, ink = "#000";
            if (blur) {
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
    h += "<figcaption>Blur width per region, pixels (disc diameter, the lecture's "
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
            "across it (filled: fitted, hollow: outlier). For a flat scene the lecture's blur is "
            "|p<sub>0</sub> + p<sub>1</sub>x + p<sub>2</sub>y|: a V whose slope here is %.4g px of "
            "blur per px across the image. The green band is the circle of confusion (%.2f px): "
            "where the V stays inside it is the depth of field in the image.</figcaption></figure>",
            p.gradient, o.optics.cocPx);
}

void ReportWriter::Impl::regionTable(std::string& h, const Entry& e) const {
    const bool depths = e.camera.has_value();
    h += "<details><summary>Every region</summary><table><tr><th>region</th><th>x, y, w, h</th>"
         "<th>sharpness</th><th>edge 10-90 % px</th><th>blur &sigma; px</th><th>blur width px</th>"
         "<th>confidence</th><th>sharp</th>";
    if (depths) h += "<th>blur on sensor</th><th>near root</th><th>far root</th><th>side</th>";
    h += "</tr>";
    const auto opt = [](const std::optional<double>& v) {
        return v ? fmt("%.2f", *v) : std::string("-");
    };
    for (const RegionDepth& d : e.map.regions) {
        const RegionResult& r = e.a.regions[d.region];
        h += fmt("<tr><td>%s</td><td>%d, %d, %d, %d</td><td>%.4g</td>", regionName(r).c_str(),
                 r.rect.x, r.rect.y, r.rect.w, r.rect.h, r.sharpness);
        h += "<td>" + opt(r.edgeWidthPx) + "</td><td>" + opt(r.blurSigmaPx) + "</td><td>" +
             opt(r.blurWidthPx) + "</td>" + fmt("<td>%.2f</td>", r.confidence);
        h += std::string("<td>") +
             (!d.used ? "-" : (*r.blurWidthPx <= o.optics.cocPx ? "yes" : "no")) + "</td>";
        if (depths) {
            if (d.roots) {
                h += "<td>" + formatSensorLength(*r.blurWidthPx * e.camera->pixelPitch) +
                     "</td><td>" + formatDistance(d.roots->nearRoot) + "</td><td>" +
                     (d.roots->farRoot ? formatDistance(*d.roots->farRoot) : std::string("none")) +
                     "</td><td>" +
                     (d.side > 0   ? "+"
                      : d.side < 0 ? "&minus;"
                                   : "") +
                     "</td>";
            } else {
                h += "<td>-</td><td>-</td><td>-</td><td></td>";
            }
        }
        h += "</tr>";
    }
    h += "</table></details>";
}

void ReportWriter::Impl::frameSection(std::string& h, const Entry& e, size_t index) const {
    const FrameAnalysis& a = e.a;
    const double coc = o.optics.cocPx;
    h +=
        fmt("<h2 id=\"frame%zu\">Frame %llu</h2>", index, static_cast<unsigned long long>(a.frame));
    h += fmt("<p>%d &times; %d pixels", a.width, a.height);
    if (a.lens)
        h += fmt(", lens position %.4g %s", a.lens->value, escapeHtml(a.lens->unit).c_str());
    if (a.timestampNs) h += fmt(", time stamp %.3f s", a.timestampNs * 1e-9);
    h += ".</p><ul>";
    int measured = 0, sharp = 0;
    const RegionResult* best = nullptr;
    const RegionResult* worst = nullptr;
    for (const RegionDepth& d : e.map.regions) {
        if (!d.used) continue;
        const RegionResult& r = a.regions[d.region];
        ++measured;
        sharp += *r.blurWidthPx <= coc;
        if (!best || *r.blurWidthPx < *best->blurWidthPx) best = &r;
        if (!worst || *r.blurWidthPx > *worst->blurWidthPx) worst = &r;
    }
    if (e.camera)
        h += "<li><b>Focus</b>: " + formatDistance(e.camera->focusDistance) + " from the lens (" +
             escapeHtml(e.focusSource) + ").</li>";
    h +=
        fmt("<li><b>In focus</b>: %d of the %d regions with a blur measurement (of %zu) are sharp: "
            "their "
            "blur width is at most the circle of confusion, %.2f px",
            sharp, measured, a.regions.size(), coc);
    if (o.optics.pixelPitch)
        h += " = " + formatSensorLength(coc * *o.optics.pixelPitch) + " on the sensor";
    h += " (" + escapeHtml(o.optics.cocSource) + ").";
    if (best)
        h += fmt(" Sharpest region %s at %.2f px, most blurred %s at %.2f px.",
                 regionName(*best).c_str(), *best->blurWidthPx, regionName(*worst).c_str(),
                 *worst->blurWidthPx);
    h += "</li>";
    if (!e.map.plane) {
        h += "<li><b>Plane of focus</b>: not found; it needs blur in at least 3 regions not on one "
             "line.</li>";
    } else {
        const optics::BlurPlane& p = *e.map.plane;
        h +=
            fmt("<li><b>Plane of focus</b>: the blur map fits |p<sub>0</sub> + p<sub>1</sub>x + "
                "p<sub>2</sub>y| in %d of %d regions (rms %.2f px). ",
                p.inliers, p.samples, p.rmsResidual);
        if (p.inFocusLine)
            h +=
                fmt("It crosses the image from (%.0f, %.0f) to (%.0f, %.0f) px, at %.1f&deg; from "
                    "the x "
                    "axis: the scene is sharpest along that line and blurs on both sides of it.",
                    p.inFocusLine->x0, p.inFocusLine->y0, p.inFocusLine->x1, p.inFocusLine->y1,
                    p.lineAngleDeg);
        else
            h += fmt(
                "It does not cross the image: every region is on one side of focus, and the blur "
                "grows towards %.0f&deg; (from the x axis, y down) by %.3g px per 1000 px.",
                std::atan2(p.signedAt(0, 0) > 0 ? p.p[2] : -p.p[2],
                           p.signedAt(0, 0) > 0 ? p.p[1] : -p.p[1]) *
                    180.0 / M_PI,
                p.gradient * 1000.0);
        h += "</li>";
    }
    if (e.map.scenes) {
        const auto& s = *e.map.scenes;
        h += fmt(
            "<li><b>Tilt</b>: the scene plane meets the plane of focus at %.2f&deg;, about an axis "
            "at %.1f&deg; in the image. One focus setting cannot say which side of the in-focus "
            "line is nearer: either the plane recedes towards %.0f&deg; and crosses the optical "
            "axis at %s, or it recedes towards %.0f&deg; and crosses it at %s. A second focus "
            "setting, or knowing which side is nearer, decides it.</li>",
            s[0].tiltDeg, s[0].axisAngleDeg, s[0].recedesTowardsDeg,
            formatDistance(s[0].depthOnAxis).c_str(), s[1].recedesTowardsDeg,
            formatDistance(s[1].depthOnAxis).c_str());
    }
    if (e.dof) {
        const auto& d = *e.dof;
        h += "<li><b>Depth of field</b> for this lens and circle of confusion: from " +
             formatDistance(d.exact.nearLimit) + " to " + formatDistance(d.exact.farLimit) + " (" +
             (std::isinf(d.exact.farLimit) ? std::string("to infinity")
                                           : formatDistance(d.exact.total()) + " deep") +
             "); hyperfocal distance " + formatDistance(d.hyperfocal) +
             ". Distances from the lens.";
        if (d.diffractionLimited)
            h += " The Airy disc (" + formatSensorLength(d.airyDisc) +
                 ") is larger than the circle of confusion: diffraction alone blurs past it.";
        // Blur is linear in dioptres of defocus: A z_s of sensor blur per dioptre.
        const double k = e.camera->lens.aperture() * d.sensorDistance / e.camera->pixelPitch;
        h +=
            fmt(" Here each dioptre of defocus blurs by %.3g px (A z<sub>s</sub> / pitch), so the "
                "circle of confusion allows &plusmn;%.3g dpt about the focus.",
                k, coc / k);
        h += "</li>";
    }
    h += "</ul>";
    overlay(h, e);
    maps(h, e);
    vPlot(h, e);
    regionTable(h, e);
}

std::string ReportWriter::html() const {
    const Impl& m = *impl_;
    const ReportOptics& p = m.o.optics;
    std::string h;
    h.reserve(200000 + m.entries.size() * 150000);
    h += "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>" +
         escapeHtml(m.o.title) + "</title>" + kStyle + "</head><body>";
    h += "<h1>" + escapeHtml(m.o.title) + "</h1>";
    h += "<p>Source <code>" + escapeHtml(m.o.source) + "</code>, " +
         std::to_string(m.entries.size()) + (m.entries.size() == 1 ? " frame" : " frames") + ".";
    if (p.lens) h += fmt(" Lens %.4g mm f/%.3g", p.lens->focalLength * 1e3, p.lens->fNumber);
    if (p.pixelPitch) h += ", pixel pitch " + formatSensorLength(*p.pixelPitch);
    if (p.lens || p.pixelPitch) h += ".";
    h += "</p>";
    // What the optics would add, where they are missing.
    std::vector<std::string> missing;
    if (!p.lens) missing.push_back("the lens (--focal and --fnumber, or --lens PRESET)");
    if (!p.pixelPitch) missing.push_back("the pixel pitch of the analysed image (--pixel-pitch)");
    bool anyFocus = false;
    for (const auto& e : m.entries)
        anyFocus = anyFocus || e.camera;
    if (p.lens && p.pixelPitch && !anyFocus)
        missing.push_back(
            "the focus distance (--focus; the frames carry no lens position in dioptres)");
    if (!missing.empty()) {
        h += "<p class=\"note\">This report is in pixels of the image. With ";
        for (size_t i = 0; i < missing.size(); ++i)
            h += (i ? (i + 1 == missing.size() ? " and " : ", ") : "") + escapeHtml(missing[i]);
        h += " it would also give each region's distance, the depth of field and the tilt of the "
             "scene "
             "in degrees.</p>";
    }
    if (m.entries.size() > 1) {
        h += "<h2>Frames</h2><table><tr><th>frame</th><th>lens position</th><th>sharpness</th>"
             "<th>regions with blur</th><th>sharp</th><th>median blur px</th><th>in-focus line at "
             "the centre column</th></tr>";
        for (size_t i = 0; i < m.entries.size(); ++i) {
            const auto& e = m.entries[i];
            std::vector<double> blurs;
            int sharp = 0;
            for (const auto& d : e.map.regions)
                if (d.used) {
                    const double b = *e.a.regions[d.region].blurWidthPx;
                    blurs.push_back(b);
                    sharp += b <= p.cocPx;
                }
            std::string at = "-";
            if (e.map.plane && e.map.plane->inFocusLine && std::abs(e.map.plane->p[2]) > 0) {
                const double y =
                    -(e.map.plane->p[0] + e.map.plane->p[1] * 0.5 * e.a.width) / e.map.plane->p[2];
                if (y >= 0 && y <= e.a.height) at = fmt("y = %.0f px", y);
            }
            const double med = median(blurs);
            h += fmt(
                "<tr><td><a "
                "href=\"#frame%zu\">%llu</a></td><td>%s</td><td>%.4g</td><td>%zu</td><td>%d</td>"
                "<td>%s</td><td>%s</td></tr>",
                i, static_cast<unsigned long long>(e.a.frame),
                e.a.lens
                    ? fmt("%.4g %s", e.a.lens->value, escapeHtml(e.a.lens->unit).c_str()).c_str()
                    : "-",
                e.a.frameSharpness, blurs.size(), sharp,
                std::isnan(med) ? "-" : fmt("%.2f", med).c_str(), at.c_str());
        }
        h += "</table>";
    }
    for (size_t i = 0; i < m.entries.size(); ++i)
        m.frameSection(h, m.entries[i], i);
    h += "<h2>How this is measured</h2><p>Each region's blur width is measured at its straight "
         "edges: the "
         "profile across each edge is sampled at sub-pixel positions and fitted, and the width of "
         "the "
         "uniform disc that blurs a step into that profile is the region's blur (the lecture's "
         "&Delta;X<sub>i</sub>, in pixels; the pixel's own area is removed). Regions without a "
         "straight, "
         "clean edge have no blur value. A region is sharp when its blur is at most the circle of "
         "confusion c.</p><p>Through the thin-lens model a blur b on the sensor comes from one of "
         "two "
         "depths, 1/z = 1/u &plusmn; b/(A z<sub>s</sub>), in front of or behind the in-focus "
         "distance u "
         "(A = f/N the aperture, z<sub>s</sub> the lens-to-sensor distance): blur is linear in "
         "dioptres "
         "of defocus. For a flat scene the signed blur is affine in the image coordinates, so the "
         "measured "
         "blur is a V whose zero line is where the scene crosses the plane of focus; its slope "
         "gives the "
         "tilt. The depth of field is the range of distances whose blur stays within c: near = u "
         "f&sup2;/(f&sup2; "
         "+ N c (u &minus; f)), far = u f&sup2;/(f&sup2; &minus; N c (u &minus; f)).</p>";
    h += "</body></html>\n";
    return h;
}

Status writeFileAtomically(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".part";
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        if (!f)
            return makeError(ErrorKind::Io, "cannot write " + tmp +
                                                ": check that the folder exists and is writable");
        f.write(text.data(), static_cast<std::streamsize>(text.size()));
        f.flush();
        if (!f) {
            std::error_code ec;
            std::filesystem::remove(tmp, ec);
            return makeError(ErrorKind::Io, "writing " + tmp + " failed (disk full?); " + path +
                                                " is left as it was");
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        return makeError(ErrorKind::Io, "cannot replace " + path + ": " + ec.message());
    }
    return {};
}

}  // namespace infocus
