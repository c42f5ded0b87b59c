// SPDX-License-Identifier: MIT
#include "src/live/tui/screen.h"

#include <curses.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string_view>

#include "src/live/present.h"
#include "src/live/tui/tui_text.h"

namespace infocus::tui {

namespace {

enum Pair : short {
    kGreen = 1,
    kRed,
    kYellow,
    kCyan,
    kHeatInCoc,
    kHeatNear,
    kHeatFar,
    kHeatBeyond,
    kHeatUnknown,
};

bool gColours = false;
bool gGreyCells = false;  // a grey background exists (256 colours); otherwise unknown cells dim

// The rows the bottom block takes: lens, DoF, blur, regions, status, help.
constexpr int kBottomRows = 6;
// The meter's big digits are reserved for "100%" so that the bar never moves.
constexpr std::string_view kWidestPercent = "100%";

attr_t colour(short pair) {
    return gColours ? COLOR_PAIR(pair) : A_NORMAL;
}

// Writes @p text at (y, x), cut at column @p endX (exclusive) so nothing wraps.
void put(int y, int x, std::string_view text, int endX, attr_t attr = A_NORMAL) {
    if (y < 0 || y >= LINES || x >= endX) return;
    const std::string fit(fitColumns(text, endX - x));  // a copy: GCC 12 sees the view dangle
    attron(attr);
    mvaddstr(y, x, fit.c_str());
    attroff(attr);
}

void drawMeter(const LiveState& s, int top) {
    const int w = COLS;
    const int percent = static_cast<int>(std::lround(std::clamp(s.percentOfPeak, 0.0, 999.0)));
    const std::string number = std::to_string(percent) + "%";
    int barX = 1;
    if (w >= 60) {
        const std::array<std::string, 3> big = bigText(number);
        const int bigW = bigTextWidth(kWidestPercent);
        const int x = 1 + bigW - bigTextWidth(number);  // right-aligned against the bar
        for (int r = 0; r < 3; ++r)
            put(top + r, x, big[r], w, A_BOLD);
        barX = 1 + bigW + 2;
    } else {
        put(top + 1, 1, number, w, A_BOLD);
        barX = 7;
    }
    // The bar fills to the percent of the peak; the cell after it is the peak-hold mark (100 %).
    const int barW = std::max(1, w - barX - 3);
    const short pair = s.percentOfPeak >= 95.0 ? kGreen : s.percentOfPeak >= 80.0 ? kYellow : kRed;
    const std::string bar = meterBar(s.percentOfPeak, barW);
    for (int r = 0; r < 3; ++r) {
        put(top + r, barX, bar, barX + barW, colour(pair) | A_BOLD);
        put(top + r, barX + barW, "▏", w, colour(kCyan) | A_BOLD);
    }

    const int y = top + 3;
    const std::string trend = trendText(s.trend);
    const attr_t trendAttr = s.trend == Trend::Sharper ? colour(kGreen) | A_BOLD
                             : s.trend == Trend::Worse ? colour(kRed) | A_BOLD
                                                       : A_BOLD;
    put(y, 1, trend, w, trendAttr);
    char buf[160];
    std::snprintf(buf, sizeof buf, "score %.4g  peak %.4g  %s", s.score, s.peak, s.metric.c_str());
    put(y, 1 + displayWidth(trend) + 3, buf, barX + barW - 6, A_DIM);
    put(y, std::max(1, barX + barW - 4), "peak┘", w, colour(kCyan));
}

void drawHistory(const LiveState& s, int top, double windowS) {
    const int w = COLS;
    const int width = w - 2;
    const Sparkline line = sparkline(s.history, s.historyPeak, s.elapsedS, windowS, width);
    for (int c = 0; c < width; ++c) {
        const bool atPeak = line.peakColumn && *line.peakColumn == c;
        put(top, 1 + c, sparkGlyph(line.levels[c]), w, atPeak ? colour(kCyan) | A_BOLD : A_NORMAL);
    }
    char label[48];
    std::snprintf(label, sizeof label, "score, last %.0f s", windowS);
    const std::string_view cue = "◀ past the peak — back up";
    const int cueX = w - 1 - displayWidth(cue);
    int peakX = -1;
    if (line.peakColumn) {
        peakX = 1 + *line.peakColumn;
        put(top + 1, peakX, "^", w, colour(kCyan) | A_BOLD);
    }
    if (peakX < 0 || peakX > displayWidth(label) + 1)
        put(top + 1, 1, label, peakX < 0 ? w : peakX, A_DIM);
    if (s.pastPeak) {
        // Kept clear of the caret: at the left when the peak is on the right.
        const int x = peakX >= cueX - 1 ? 1 : cueX;
        put(top + 1, x, cue, w, colour(kRed) | A_BOLD | A_REVERSE);
    }
}

short heatPair(present::Heat h) {
    switch (h) {
        case present::Heat::InCoc:
            return kHeatInCoc;
        case present::Heat::Near:
            return kHeatNear;
        case present::Heat::Far:
            return kHeatFar;
        case present::Heat::Beyond:
            return kHeatBeyond;
        case present::Heat::Unknown:
            break;
    }
    return kHeatUnknown;
}

void drawLegend(const LiveState& s, int y) {
    const int w = COLS;
    char head[96];
    std::snprintf(head, sizeof head, "regions %d×%d, blur px against CoC %.1f px: ", s.cols, s.rows,
                  s.cocPx);
    put(y, 1, head, w, A_DIM);
    int x = 1 + displayWidth(head);
    for (const auto& [heat, word] : {std::pair{present::Heat::InCoc, " ≤1× "},
                                     {present::Heat::Near, " ≤2× "},
                                     {present::Heat::Far, " ≤4× "},
                                     {present::Heat::Beyond, " >4× "},
                                     {present::Heat::Unknown, " ? "}}) {
        attr_t a = colour(heatPair(heat));
        if (heat == present::Heat::Unknown && !gGreyCells) a |= A_DIM;
        put(y, x, word, w, a);
        x += displayWidth(word) + 1;
    }
}

void drawGrid(const LiveState& s, int top, int bottom) {
    const int w = COLS;
    const int availW = w - 2, availH = bottom - top;
    if (s.cols <= 0 || s.rows <= 0 || availH <= 0) return;
    // Cells share the space as evenly as whole columns and lines allow, within reason (at most
    // 14×4 each); a grid larger than the terminal shows as many columns (rows) as fit.
    const int shownCols = std::min(s.cols, availW / 2);
    const int shownRows = std::min(s.rows, availH);
    const int gridW = std::min(availW, shownCols * 14);
    const int gridH = std::min(availH, shownRows * 4);
    const int x0 = 1 + (availW - gridW) / 2;
    auto colX = [&](int c) { return x0 + c * gridW / shownCols; };
    auto rowY = [&](int r) { return top + r * gridH / shownRows; };
    for (const LiveRegion& r : s.regions) {
        if (r.col >= shownCols || r.row >= shownRows) continue;
        const present::Heat heat = present::heatOf(r, s.cocPx);
        attr_t a = colour(heatPair(heat));
        if (heat == present::Heat::Unknown && !gGreyCells) a |= A_DIM;
        const int x = colX(r.col), cellW = colX(r.col + 1) - x;
        const int y = rowY(r.row), cellH = rowY(r.row + 1) - y;
        // A blank column between cells keeps neighbours of one colour apart.
        const int inner = cellW >= 4 ? cellW - 1 : cellW;
        std::string label = regionLabel(r, inner);
        if (label.empty() && heat == present::Heat::Unknown) label = "·";
        const int labelW = displayWidth(label);
        const int pad = (inner - labelW) / 2;
        for (int dy = 0; dy < cellH; ++dy) {
            std::string text(inner, ' ');
            if (dy == cellH / 2) {
                text = std::string(pad, ' ') + label + std::string(inner - pad - labelW, ' ');
            }
            put(y + dy, x, text, w, a);
        }
    }
}

void drawBottom(const LiveState& s, const ScreenNotes& notes, int top) {
    const int w = COLS;
    put(top, 1, lensLine(s), w, s.autofocusRunning ? colour(kYellow) | A_BOLD : A_BOLD);
    put(top + 1, 1, dofLine(s).value_or("DoF — (needs lens data)"), w);
    put(top + 2, 1, blurLine(s), w);
    put(top + 3, 1, regionsLine(s), w);
    const std::string& status = notes.status.empty() ? s.status : notes.status;
    put(top + 4, 1, status, w, notes.statusIsError ? colour(kRed) | A_BOLD : A_NORMAL);
}

}  // namespace

void initColours() {
    if (!has_colors()) return;
    start_color();
    use_default_colors();
    gColours = true;
    init_pair(kGreen, COLOR_GREEN, -1);
    init_pair(kRed, COLOR_RED, -1);
    init_pair(kYellow, COLOR_YELLOW, -1);
    init_pair(kCyan, COLOR_CYAN, -1);
    init_pair(kHeatInCoc, COLOR_BLACK, COLOR_GREEN);
    init_pair(kHeatNear, COLOR_BLACK, COLOR_YELLOW);
    // Orange and grey need 256 colours; eight-colour terminals get magenta and a dim cell.
    const bool rich = COLORS >= 256;
    init_pair(kHeatFar, COLOR_BLACK, rich ? 208 : COLOR_MAGENTA);
    init_pair(kHeatBeyond, COLOR_WHITE, COLOR_RED);
    init_pair(kHeatUnknown, rich ? 250 : -1, rich ? 238 : -1);
    gGreyCells = rich;
}

void drawScreen(const LiveState* state, const ScreenNotes& notes) {
    erase();
    const int w = COLS, h = LINES;
    const attr_t bar = A_REVERSE;
    attron(bar);
    mvhline(0, 0, ' ', w);
    mvhline(h - 1, 0, ' ', w);
    attroff(bar);
    put(h - 1, 1, "←/→ focus  a autofocus  c continuous  r reset  g grid  p peaking  q quit", w,
        bar);
    if (!state) {
        put(0, 1, "infocus live: waiting for the first frame…", w, bar | A_BOLD);
        if (!notes.status.empty()) put(2, 1, notes.status, w, colour(kRed) | A_BOLD);
        return;
    }
    const LiveState& s = *state;
    put(0, 1, titleLine(s, notes.fromSim, w - 2), w, bar | A_BOLD);
    drawMeter(s, 1);
    // The history window is what the state keeps: from its oldest point (10 s by default).
    double windowS = 10.0;
    if (!s.history.empty()) windowS = std::max(windowS, s.elapsedS - s.history.front().tS);
    drawHistory(s, 5, windowS);
    drawLegend(s, 7);
    const int bottomTop = h - kBottomRows;
    drawGrid(s, 8, bottomTop);
    drawBottom(s, notes, bottomTop);
    if (w < 80 || h < 24) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "terminal %d×%d: the view needs 80×24", w, h);
        move(h - 2, 0);
        clrtoeol();
        put(h - 2, 1, buf, w, colour(kRed) | A_BOLD);
    }
}

}  // namespace infocus::tui
