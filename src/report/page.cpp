// SPDX-License-Identifier: MIT
// The HTML depth-of-field report (include/infocus/report.h). Everything it draws is inline SVG
// and one JPEG per frame as a data URI, so the file can be mailed or archived on its own.
#include <algorithm>
#include <cmath>
#include <limits>

#include "area_resize.h"
#include "html.h"
#include "infocus/units.h"
#include "report_impl.h"

namespace infocus {

using report_detail::base64;
using report_detail::escapeHtml;
using report_detail::fmt;
using report_detail::regionName;

namespace {

double median(std::vector<double> v) {
    if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
    const size_t m = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + m, v.end());
    if (v.size() % 2) return v[m];
    return 0.5 * (v[m] + *std::max_element(v.begin(), v.begin() + m));
}

const char* kStyle = R"(<style>
body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}
h1{font-size:1.6em}h2{border-bottom:2px solid #ddd;padding-bottom:.2em;margin-top:2em}
table{border-collapse:collapse;font-size:.85em}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}
th{background:#f4f4f4}.note{background:#f7f7f0;border-left:4px solid #cc9;padding:.5em 1em}
svg{max-width:100%;height:auto}figure{margin:1em 0}figcaption{font-size:.85em;color:#555}
</style>)";

}  // namespace

Result<std::string> ReportWriter::Impl::thumbnail(const Luma8& luma) {
    if (luma.empty()) return std::string();
    Luma8 small = luma;
    if (luma.width > o.thumbnailWidth) {
        const int h = std::max(
            1, static_cast<int>(std::lround(double(luma.height) * o.thumbnailWidth / luma.width)));
        const Image<uint8_t> reduced = report_detail::resizeArea(luma, o.thumbnailWidth, h);
        small = reduced.view();
    }
    if (!tj) tj = tjInitCompress();
    unsigned char* out = nullptr;
    unsigned long size = 0;
    if (!tj ||
        tjCompress2(tj, small.data, small.width, static_cast<int>(small.stride), small.height,
                    TJPF_GRAY, &out, &size, TJSAMP_GRAY, 85, TJFLAG_FASTDCT) != 0) {
        const std::string why = tj ? tjGetErrorStr2(tj) : "no JPEG compressor";
        if (out) tjFree(out);
        return makeError(ErrorKind::Io, "could not encode the frame for the report: " + why);
    }
    std::string b64 = base64(out, size);
    tjFree(out);
    return b64;
}

std::optional<optics::CameraGeometry> ReportWriter::Impl::cameraFor(const FrameAnalysis& a,
                                                                    std::string& source) {
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
        h += fmt("<tr><td>%s</td><td>%d, %d, %d, %d</td><td>%s</td>", regionName(r).c_str(),
                 r.rect.x, r.rect.y, r.rect.w, r.rect.h,
                 r.status == RegionStatus::Ok
                     ? fmt("%.4g", r.sharpness).c_str()
                     : escapeHtml(std::string(regionStatusName(r.status))).c_str());
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
                "href=\"#frame%zu\">%llu</a></td><td>%s</td><td>%s</td><td>%zu</td><td>%d</td>"
                "<td>%s</td><td>%s</td></tr>",
                i, static_cast<unsigned long long>(e.a.frame),
                e.a.lens
                    ? fmt("%.4g %s", e.a.lens->value, escapeHtml(e.a.lens->unit).c_str()).c_str()
                    : "-",
                hasMeasurableRegion(e.a) ? fmt("%.4g", e.a.frameSharpness).c_str() : "-",
                blurs.size(), sharp, std::isnan(med) ? "-" : fmt("%.2f", med).c_str(), at.c_str());
        }
        h += "</table>";
    }
    for (size_t i = 0; i < m.entries.size(); ++i)
        m.frameSection(h, m.entries[i], i);
    h += "<h2>How this is measured</h2><p>Each region's blur width is measured at its straight "
         "edges: the "
         "profile across each edge is sampled at sub-pixel positions and fitted, and the width of "
         "the "
         "uniform disc that blurs a step into that profile is the region's blur (the thin-lens "
         "model's "
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

}  // namespace infocus
