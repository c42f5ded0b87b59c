// SPDX-License-Identifier: MIT
#include "src/live/window/window_view.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "src/live/present.h"

namespace infocus::window {

namespace {

// Heat map colours by blur against the circle of confusion: within it, up to twice, up to four
// times, beyond. The fill is faint so the picture stays readable; the outline carries the colour.
constexpr ImU32 kSharp = IM_COL32(40, 220, 90, 255);
constexpr ImU32 kNear = IM_COL32(235, 220, 40, 255);
constexpr ImU32 kSoft = IM_COL32(255, 140, 30, 255);
constexpr ImU32 kBlurred = IM_COL32(240, 50, 50, 255);
constexpr ImU32 kUnknown = IM_COL32(150, 150, 150, 255);
constexpr int kFillAlpha = 48;
constexpr int kOutlineAlpha = 150;
constexpr ImU32 kInFocusLine = IM_COL32(0, 230, 255, 255);
constexpr ImU32 kRoi = IM_COL32(255, 255, 255, 255);
constexpr ImU32 kDrag = IM_COL32(255, 230, 0, 255);
constexpr ImU32 kHistoryLine = IM_COL32(120, 200, 255, 255);
constexpr ImU32 kPeakMark = IM_COL32(255, 90, 60, 255);
// The magnifier inset sits this far from the mouse, down and right, so the cursor stays visible.
constexpr float kInsetOffset = 24.0f;

ImU32 withAlpha(ImU32 c, int alpha) {
    return (c & ~IM_COL32_A_MASK) | (static_cast<ImU32>(alpha) << IM_COL32_A_SHIFT);
}

// The heat map's colour of a region; grey for a reading under the confidence the engine trusts.
ImU32 heatColour(present::Heat heat) {
    switch (heat) {
        case present::Heat::InCoc:
            return kSharp;
        case present::Heat::Near:
            return kNear;
        case present::Heat::Far:
            return kSoft;
        case present::Heat::Beyond:
            return kBlurred;
        case present::Heat::Unknown:
            break;
    }
    return kUnknown;
}

// The score with four significant digits, as the terminal meter shows it.
std::string scoreText(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}

void drawRect(ImDrawList& dl, const PictureRect& pic, const Rect& r, ImU32 colour, float thick) {
    const ImVec2 a(pic.x + r.x * pic.scale, pic.y + r.y * pic.scale);
    const ImVec2 b(pic.x + (r.x + r.w) * pic.scale, pic.y + (r.y + r.h) * pic.scale);
    dl.AddRect(a, b, colour, 0.0f, 0, thick);
}

// The 10 s score history as a line, its peak as a dot with its value.
void drawHistory(const LiveState& s, float height) {
    ImDrawList& dl = *ImGui::GetWindowDrawList();
    const ImVec2 p0 = ImGui::GetCursorScreenPos();
    const float w = ImGui::GetContentRegionAvail().x;
    const ImVec2 p1(p0.x + w, p0.y + height);
    dl.AddRectFilled(p0, p1, IM_COL32(25, 28, 34, 255));
    dl.AddRect(p0, p1, IM_COL32(80, 80, 90, 255));
    ImGui::Dummy(ImVec2(w, height));
    if (s.history.size() < 2) return;
    const double t1 = s.history.back().tS;
    const double t0 = std::min(s.history.front().tS, t1 - 10.0);
    double lo = s.history.front().score, hi = lo;
    for (const HistoryPoint& h : s.history) {
        lo = std::min(lo, h.score);
        hi = std::max(hi, h.score);
    }
    // A flat history still gets a band, so noise does not fill the plot.
    const double pad = std::max(0.05 * (hi - lo), 1e-3 * std::max(std::abs(hi), 1.0));
    lo -= pad;
    hi += pad;
    auto at = [&](const HistoryPoint& h) {
        return ImVec2(p0.x + 2 + static_cast<float>((h.tS - t0) / (t1 - t0)) * (w - 4),
                      p1.y - 2 - static_cast<float>((h.score - lo) / (hi - lo)) * (height - 4));
    };
    std::vector<ImVec2> line;
    line.reserve(s.history.size());
    for (const HistoryPoint& h : s.history)
        line.push_back(at(h));
    dl.AddPolyline(line.data(), static_cast<int>(line.size()), kHistoryLine, 0, 1.5f);
    if (s.historyPeak) {
        const ImVec2 pk = at(*s.historyPeak);
        dl.AddLine(ImVec2(pk.x, p0.y + 1), ImVec2(pk.x, p1.y - 1), withAlpha(kPeakMark, 110));
        dl.AddCircleFilled(pk, 4.0f, kPeakMark);
        const std::string label = "peak " + scoreText(s.historyPeak->score);
        const float tw = ImGui::CalcTextSize(label.c_str()).x;
        const float tx = std::clamp(pk.x - tw / 2, p0.x + 2, p1.x - tw - 2);
        dl.AddText(ImVec2(tx, p0.y + 2), kPeakMark, label.c_str());
    }
    char span[32];
    std::snprintf(span, sizeof span, "-%.0f s", t1 - t0);
    dl.AddText(ImVec2(p0.x + 4, p1.y - ImGui::GetTextLineHeight() - 2),
               IM_COL32(150, 150, 160, 255), span);
}

void row(const char* label, const std::string& value) {
    ImGui::TextDisabled("%s", label);
    ImGui::SameLine(130);
    ImGui::TextUnformatted(value.c_str());
}

std::string fmt(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

}  // namespace

PictureRect letterbox(int frameW, int frameH, float areaW, float areaH) {
    PictureRect r;
    if (frameW <= 0 || frameH <= 0 || areaW <= 0 || areaH <= 0) return r;
    r.scale = std::min(areaW / frameW, areaH / frameH);
    r.w = frameW * r.scale;
    r.h = frameH * r.scale;
    r.x = std::floor((areaW - r.w) / 2);
    r.y = std::floor((areaH - r.h) / 2);
    return r;
}

void drawOverlays(ImDrawList& dl, const LiveState& s, const PictureRect& pic,
                  const OverlayNotes& notes) {
    // The heat map: each region's blur against the circle of confusion, its number where the
    // cell is wide enough to hold it.
    for (const LiveRegion& r : s.regions) {
        if (!r.blurPx) continue;
        const ImU32 c = heatColour(present::heatOf(r, s.cocPx));
        const ImVec2 a(pic.x + r.rect.x * pic.scale + 1, pic.y + r.rect.y * pic.scale + 1);
        const ImVec2 b(pic.x + (r.rect.x + r.rect.w) * pic.scale - 1,
                       pic.y + (r.rect.y + r.rect.h) * pic.scale - 1);
        dl.AddRectFilled(a, b, withAlpha(c, kFillAlpha));
        dl.AddRect(a, b, withAlpha(c, kOutlineAlpha));
        char text[16];
        std::snprintf(text, sizeof text, "%.1f", *r.blurPx);
        const ImVec2 ts = ImGui::CalcTextSize(text);
        if (ts.x + 6 <= b.x - a.x && ts.y + 4 <= b.y - a.y) {
            const ImVec2 at((a.x + b.x - ts.x) / 2, (a.y + b.y - ts.y) / 2);
            dl.AddRectFilled(ImVec2(at.x - 2, at.y), ImVec2(at.x + ts.x + 2, at.y + ts.y),
                             IM_COL32(0, 0, 0, 150));
            dl.AddText(at, IM_COL32(255, 255, 255, 255), text);
        }
    }
    if (s.inFocusLine) {
        const auto& l = *s.inFocusLine;
        const ImVec2 a(pic.x + static_cast<float>(l.x0) * pic.scale,
                       pic.y + static_cast<float>(l.y0) * pic.scale);
        const ImVec2 b(pic.x + static_cast<float>(l.x1) * pic.scale,
                       pic.y + static_cast<float>(l.y1) * pic.scale);
        dl.PushClipRect(ImVec2(pic.x, pic.y), ImVec2(pic.x + pic.w, pic.y + pic.h), true);
        dl.AddLine(a, b, IM_COL32(0, 0, 0, 160), 5.0f);
        dl.AddLine(a, b, kInFocusLine, 2.5f);
        dl.AddText(ImVec2(a.x + 6, a.y + 4), kInFocusLine, "in focus");
        dl.PopClipRect();
    }
    if (s.scoreRoi) {
        drawRect(dl, pic, *s.scoreRoi, kRoi, 2.0f);
        dl.AddText(
            ImVec2(pic.x + s.scoreRoi->x * pic.scale + 4, pic.y + s.scoreRoi->y * pic.scale + 2),
            kRoi, "ROI");
    }
    if (notes.dragRoi) drawRect(dl, pic, *notes.dragRoi, kDrag, 1.5f);

    // The magnifier inset beside the mouse, kept inside the picture.
    if (notes.mouse && notes.magnifierTexture && s.magnifier && s.magnifier->crop.data()) {
        const Magnifier& m = *s.magnifier;
        const float side = static_cast<float>(m.crop.width());
        float x = (*notes.mouse)[0] + kInsetOffset, y = (*notes.mouse)[1] + kInsetOffset;
        if (x + side > pic.x + pic.w) x = (*notes.mouse)[0] - kInsetOffset - side;
        if (y + side > pic.y + pic.h) y = (*notes.mouse)[1] - kInsetOffset - side;
        const ImVec2 a(x, y), b(x + side, y + static_cast<float>(m.crop.height()));
        dl.AddImage(notes.magnifierTexture, a, b);
        dl.AddRect(ImVec2(a.x - 1, a.y - 1), ImVec2(b.x + 1, b.y + 1), IM_COL32(255, 255, 255, 220),
                   0.0f, 0, 2.0f);
        const char* label = m.zoom == 2 ? "2:1" : "1:1";
        dl.AddRectFilled(a, ImVec2(a.x + 30, a.y + ImGui::GetTextLineHeight() + 2),
                         IM_COL32(0, 0, 0, 160));
        dl.AddText(ImVec2(a.x + 3, a.y + 1), IM_COL32(255, 255, 255, 255), label);
        // Where the inset looks, on the picture.
        drawRect(dl, pic, m.source, IM_COL32(255, 255, 255, 140), 1.0f);
    }
}

void drawPanel(const LiveState* s, const PanelNotes& notes, float windowW, float windowH) {
    ImGui::SetNextWindowPos(ImVec2(windowW - kPanelWidth, 0));
    ImGui::SetNextWindowSize(ImVec2(kPanelWidth, windowH));
    ImGui::Begin("infocus live", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                     ImGuiWindowFlags_NoSavedSettings);
    if (!s) {
        ImGui::TextUnformatted("waiting for the first frame…");
        ImGui::End();
        return;
    }

    // The meter: the score large, the bar against the peak, the trend and the past-peak cue.
    ImGui::TextDisabled("%s score%s", s->metric.c_str(), s->scoreRoi ? " (ROI)" : "");
    if (notes.bigFont)
        ImGui::PushFont(notes.bigFont);
    else
        ImGui::SetWindowFontScale(3.0f);
    ImGui::TextUnformatted(scoreText(s->score).c_str());
    if (notes.bigFont)
        ImGui::PopFont();
    else
        ImGui::SetWindowFontScale(1.0f);
    const std::string pct = fmt("%.1f %% of peak", s->percentOfPeak);
    ImGui::PushStyleColor(ImGuiCol_PlotHistogram, s->percentOfPeak >= 98.0
                                                      ? ImVec4(0.2f, 0.8f, 0.35f, 1.0f)
                                                      : ImVec4(0.25f, 0.55f, 0.9f, 1.0f));
    ImGui::ProgressBar(static_cast<float>(std::clamp(s->percentOfPeak / 100.0, 0.0, 1.0)),
                       ImVec2(-1, 22), pct.c_str());
    ImGui::PopStyleColor();
    ImGui::Text("peak %s", scoreText(s->peak).c_str());
    ImGui::SameLine(170);
    const ImVec4 trendColour = s->trend == Trend::Sharper ? ImVec4(0.3f, 0.9f, 0.4f, 1.0f)
                               : s->trend == Trend::Worse ? ImVec4(1.0f, 0.6f, 0.2f, 1.0f)
                                                          : ImVec4(0.7f, 0.7f, 0.7f, 1.0f);
    ImGui::TextColored(trendColour, "%s", std::string(trendName(s->trend)).c_str());
    if (s->pastPeak)
        ImGui::TextColored(ImVec4(1.0f, 0.3f, 0.25f, 1.0f), "past the peak: back up");
    else
        ImGui::TextUnformatted(" ");
    drawHistory(*s, 110.0f);

    ImGui::Separator();
    if (s->lens) {
        std::string lens = fmt("%.4g ", s->lens->value) + s->lens->unit;
        if (s->lens->dioptres && s->lens->unit != "dioptre")
            lens += fmt("  (%.3g dpt)", *s->lens->dioptres);
        row("lens", lens);
    } else {
        row("lens", s->hasFocusControl ? "-" : "no focus control");
    }
    row("in focus at", present::distanceText(s->inFocusDistanceM));
    if (const std::string af = present::autofocusText(s->autofocus); !af.empty())
        ImGui::TextColored(ImVec4(1, 0.85f, 0.2f, 1), "%s", af.c_str());

    ImGui::Separator();
    std::string blur = s->blurPx ? fmt("%.2f px", *s->blurPx) : "-";
    if (s->blurUm) blur += fmt("  %.1f µm", *s->blurUm);
    row("blur (median)", blur);
    row("circle of conf.",
        fmt("%.2f px", s->cocPx) + (s->cocFromLens ? "  (lens)" : "  (default)"));
    if (s->diffractionPx) row("diffraction", fmt("%.2f px", *s->diffractionPx));
    row("within CoC",
        std::to_string(s->regionsInCoc) + " of " + std::to_string(s->regionsWithBlur) + " regions");
    if (s->dofNearM)
        row("depth of field",
            present::distanceText(s->dofNearM) + " to " + present::distanceText(s->dofFarM));
    else
        row("depth of field", "needs --focal and --fnumber (or --lens)");
    row("tilt", s->tiltDeg ? fmt("%.1f°", *s->tiltDeg) : std::string("-"));

    ImGui::Separator();
    row("frame", std::to_string(s->width) + "×" + std::to_string(s->height) + "  grid " +
                     std::to_string(s->cols) + "×" + std::to_string(s->rows));
    row("analysed", fmt("%.1f fps", s->fps) + fmt("   drawn %.1f fps", notes.drawFps) + " (" +
                        notes.renderer + ")");
    row("dropped", std::to_string(s->dropped) + "   skipped " + std::to_string(s->skipped));
    row("latency", fmt("%.1f ms median", s->latencyP50Ms) + fmt(", %.1f ms p99", s->latencyP99Ms));
    row("peaking", std::string(peakingModeName(s->peaking)));
    row("magnifier", notes.magnifierZoom == 2 ? "2:1" : "1:1");

    ImGui::Separator();
    ImGui::PushTextWrapPos(0.0f);
    const std::string& status = notes.status.empty() ? s->status : notes.status;
    if (!status.empty())
        ImGui::TextColored(
            notes.status.empty() ? ImVec4(0.8f, 0.8f, 0.8f, 1) : ImVec4(1, 0.4f, 0.3f, 1), "%s",
            status.c_str());
    ImGui::TextDisabled(
        "wheel or ←/→ focus (Shift ×10) · a autofocus · c continuous AF · r reset peak · g grid · "
        "p peaking · "
        "m zoom 1:1/2:1 · drag: ROI, click: whole frame · q quit");
    ImGui::PopTextWrapPos();
    ImGui::TextDisabled("%s", s->source.c_str());
    ImGui::End();
}

}  // namespace infocus::window
