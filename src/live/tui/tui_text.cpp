// SPDX-License-Identifier: MIT
#include "src/live/tui/tui_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "src/live/present.h"

namespace infocus::tui {

namespace {

std::string format(const char* fmt, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, fmt, v);
    return buf;
}

bool isContinuation(unsigned char c) {
    return (c & 0xC0) == 0x80;
}

}  // namespace

std::string regionLabel(const LiveRegion& region, int width) {
    if (!present::showsBlur(region)) return {};
    const double b = *region.blurPx;
    // The most precise form that fits: one decimal below 10 px, whole pixels above.
    for (const std::string& s :
         {b < 9.95 ? format("%.1f", b) : std::string(),
          b < 999.5 ? format("%.0f", b) : std::string(), std::string("99+")}) {
        if (!s.empty() && static_cast<int>(s.size()) <= width) return s;
    }
    return {};
}

Sparkline sparkline(const std::vector<HistoryPoint>& history, std::optional<HistoryPoint> peak,
                    double nowS, double windowS, int width) {
    Sparkline out;
    if (width <= 0 || !(windowS > 0.0)) return out;
    out.levels.assign(width, -1);
    const double start = nowS - windowS;
    auto column = [&](double tS) {
        const int c = static_cast<int>(std::floor((tS - start) / windowS * width));
        return std::clamp(c, 0, width - 1);
    };
    std::vector<double> best(width, -INFINITY);
    double lo = INFINITY, hi = -INFINITY;
    for (const HistoryPoint& p : history) {
        if (p.tS < start || p.tS > nowS) continue;
        double& b = best[column(p.tS)];
        b = std::max(b, p.score);
        lo = std::min(lo, p.score);
        hi = std::max(hi, p.score);
    }
    for (int c = 0; c < width; ++c) {
        if (std::isinf(best[c])) continue;
        const double f = hi > lo ? (best[c] - lo) / (hi - lo) : 0.5;
        out.levels[c] = std::clamp(static_cast<int>(std::lround(f * 7.0)), 0, 7);
    }
    if (peak && peak->tS >= start && peak->tS <= nowS) out.peakColumn = column(peak->tS);
    return out;
}

std::string_view sparkGlyph(int level) {
    static constexpr std::array<std::string_view, 8> kBlocks = {"▁", "▂", "▃", "▄",
                                                                "▅", "▆", "▇", "█"};
    return level < 0 || level > 7 ? std::string_view(" ") : kBlocks[level];
}

std::array<std::string, 3> bigText(std::string_view text) {
    // A three-line block font: half blocks give six pixel rows per glyph.
    static constexpr std::array<std::array<std::string_view, 3>, 10> kDigits = {{
        {"█▀█", "█ █", "▀▀▀"},
        {"▀█ ", " █ ", "▀▀▀"},
        {"▀▀█", "█▀▀", "▀▀▀"},
        {"▀▀█", " ▀█", "▀▀▀"},
        {"█ █", "▀▀█", "  ▀"},
        {"█▀▀", "▀▀█", "▀▀▀"},
        {"█▀▀", "█▀█", "▀▀▀"},
        {"▀▀█", "  █", "  ▀"},
        {"█▀█", "█▀█", "▀▀▀"},
        {"█▀█", "▀▀█", "▀▀▀"},
    }};
    static constexpr std::array<std::string_view, 3> kPercent = {"▀ █", " █ ", "█ ▄"};
    static constexpr std::array<std::string_view, 3> kDot = {" ", " ", "▀"};
    static constexpr std::array<std::string_view, 3> kSpace = {" ", " ", " "};
    std::array<std::string, 3> out;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        const std::array<std::string_view, 3>& g = c >= '0' && c <= '9' ? kDigits[c - '0']
                                                   : c == '%'           ? kPercent
                                                   : c == '.'           ? kDot
                                                                        : kSpace;
        for (int r = 0; r < 3; ++r) {
            if (i > 0) out[r] += ' ';
            out[r] += g[r];
        }
    }
    return out;
}

int bigTextWidth(std::string_view text) {
    return displayWidth(bigText(text)[0]);
}

std::string meterBar(double percent, int width) {
    static constexpr std::array<std::string_view, 8> kEighths = {"",  "▏", "▎", "▍",
                                                                 "▌", "▋", "▊", "▉"};
    if (width <= 0) return {};
    const double p = std::isfinite(percent) ? std::clamp(percent, 0.0, 100.0) : 0.0;
    const int eighths = static_cast<int>(std::lround(p / 100.0 * width * 8));
    std::string out;
    const int full = eighths / 8;
    for (int i = 0; i < full; ++i)
        out += "█";
    if (full < width) {
        out += kEighths[eighths % 8];
        out.append(width - full - (eighths % 8 ? 1 : 0), ' ');
    }
    return out;
}

std::string trendText(Trend trend) {
    switch (trend) {
        case Trend::Sharper:
            return "▲ sharper";
        case Trend::Worse:
            return "▼ worse";
        case Trend::Steady:
            break;
    }
    return "● steady";
}

std::string titleStats(const LiveState& s) {
    char buf[192];
    std::snprintf(buf, sizeof buf,
                  "%d×%d  %.1f fps  dropped %llu  skipped %llu  latency %.1f/%.1f ms", s.width,
                  s.height, s.fps, static_cast<unsigned long long>(s.dropped),
                  static_cast<unsigned long long>(s.skipped), s.latencyP50Ms, s.latencyP99Ms);
    return buf;
}

std::string titleLine(const LiveState& s, bool fromSim, int columns) {
    const std::string stats = titleStats(s);
    std::string source = s.source + (fromSim ? " (simulated: no camera named)" : "");
    // The figures matter more than the tail of a long source string: the source gives way.
    const int room = columns - displayWidth(stats) - 2;
    if (room < 2) return std::string(fitColumns(stats, std::max(columns, 0)));
    if (displayWidth(source) > room) source = std::string(fitColumns(source, room - 1)) + "…";
    return source + std::string(columns - displayWidth(source) - displayWidth(stats), ' ') + stats;
}

std::string lensLine(const LiveState& s) {
    std::string out = "lens ";
    if (!s.lens) {
        out += s.hasFocusControl ? "position unknown" : "no focus control";
    } else if (s.lens->unit == "dioptre") {
        out += format("%.2f D", s.lens->value);
    } else {
        out += format("%g", s.lens->value) + " " + s.lens->unit;
        if (s.lens->dioptres) out += format(" (%.2f D)", *s.lens->dioptres);
    }
    const std::string af = present::autofocusText(s.autofocus);
    if (s.autofocusRunning && af.empty()) {
        out += "   autofocus…";
    } else if (s.inFocusDistanceM) {
        out += "   in focus at " + present::distanceText(*s.inFocusDistanceM);
    }
    if (!af.empty()) out += "   " + af;
    return out;
}

std::optional<std::string> dofLine(const LiveState& s) {
    if (!s.dofNearM || !s.dofFarM) return std::nullopt;
    return "DoF " + present::distanceText(*s.dofNearM) + " – " + present::distanceText(*s.dofFarM);
}

std::string blurLine(const LiveState& s) {
    std::string out = s.blurPx ? format("blur %.1f px", *s.blurPx) : std::string("blur —");
    if (s.blurPx && s.blurUm) out += format(" = %.1f µm", *s.blurUm);
    out += format("  CoC %.1f px", s.cocPx);
    if (!s.cocFromLens) out += " (default)";
    if (s.diffractionPx) out += format("  diffraction %.1f px", *s.diffractionPx);
    return out;
}

std::string regionsLine(const LiveState& s) {
    std::string out = std::to_string(s.regionsInCoc) + " of " + std::to_string(s.regionsWithBlur) +
                      " regions within CoC";
    if (s.tiltDeg) out += format("   tilt %.1f°", *s.tiltDeg);
    if (s.inFocusLine) {
        const auto& l = *s.inFocusLine;
        char buf[96];
        std::snprintf(buf, sizeof buf, "   in focus along (%.0f, %.0f)–(%.0f, %.0f)", l.x0, l.y0,
                      l.x1, l.y1);
        out += buf;
    }
    return out;
}

int displayWidth(std::string_view text) {
    return static_cast<int>(std::count_if(text.begin(), text.end(), [](char c) {
        return !isContinuation(static_cast<unsigned char>(c));
    }));
}

std::string_view fitColumns(std::string_view text, int columns) {
    int used = 0;
    for (size_t i = 0; i < text.size(); ++i) {
        if (isContinuation(static_cast<unsigned char>(text[i]))) continue;
        if (used == columns) return text.substr(0, i);
        ++used;
    }
    return text;
}

}  // namespace infocus::tui
