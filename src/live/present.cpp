// SPDX-License-Identifier: MIT
#include "src/live/present.h"

#include <array>
#include <cmath>
#include <cstdio>

#include "infocus/blur.h"

namespace infocus::present {

namespace {

std::string format(const char* fmt, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, fmt, v);
    return buf;
}

constexpr std::array<KeyBinding, 9> kBindings = {{
    {"←/→", Action::FocusUp, "move the lens one step down / up its range"},
    {"Shift ←/→", Action::FocusUpFast, "ten steps"},
    {"a", Action::Autofocus, "autofocus"},
    {"c", Action::ToggleContinuous, "continuous autofocus on ↔ off"},
    {"r", Action::ResetPeak, "forget the peak"},
    {"g", Action::NextGrid, "grid 16×9 → 8×6 → 4×3"},
    {"p", Action::NextPeaking, "peaking off → coc → percentile"},
    {"m", Action::ToggleMagnifier, "magnifier 1:1 ↔ 2:1 (window)"},
    {"q/Esc", Action::Quit, "quit"},
}};

}  // namespace

Heat heatOf(const LiveRegion& region, double cocPx) {
    if (!showsBlur(region) || !(cocPx > 0.0)) return Heat::Unknown;
    const double ratio = *region.blurPx / cocPx;
    if (ratio <= 1.0) return Heat::InCoc;
    if (ratio <= 2.0) return Heat::Near;
    if (ratio <= 4.0) return Heat::Far;
    return Heat::Beyond;
}

std::string_view heatName(Heat heat) {
    switch (heat) {
        case Heat::InCoc:
            return "in_coc";
        case Heat::Near:
            return "near";
        case Heat::Far:
            return "far";
        case Heat::Beyond:
            return "beyond";
        case Heat::Unknown:
            break;
    }
    return "unknown";
}

bool showsBlur(const LiveRegion& region) {
    return region.blurPx && region.confidence >= kLowBlurConfidence;
}

std::pair<int, int> nextGrid(int cols, int rows) {
    if (cols == 16 && rows == 9) return {8, 6};
    if (cols == 8 && rows == 6) return {4, 3};
    return {16, 9};
}

PeakingMode nextPeaking(PeakingMode m) {
    switch (m) {
        case PeakingMode::Off:
            return PeakingMode::Coc;
        case PeakingMode::Coc:
            return PeakingMode::Percentile;
        case PeakingMode::Percentile:
            break;
    }
    return PeakingMode::Off;
}

std::string distanceText(double metres) {
    if (std::isinf(metres)) return "infinity";
    const double a = std::abs(metres);
    if (a < 1.0) return format("%.0f mm", metres * 1e3);
    if (a < 10.0) return format("%.2f m", metres);
    if (a < 100.0) return format("%.1f m", metres);
    return format("%.0f m", metres);
}

std::string distanceText(std::optional<double> metres) {
    return metres ? distanceText(*metres) : std::string("—");
}

std::string autofocusText(const LiveAutofocus& af) {
    const std::string state(liveAutofocusStateName(af.state));
    if (af.state == LiveAutofocusState::Failed) return "AF failed: " + af.reason;
    if (af.mode == LiveAutofocusMode::Continuous) return "AF continuous: " + state;
    if (af.mode == LiveAutofocusMode::Off && af.state == LiveAutofocusState::Idle) return "";
    if (af.state == LiveAutofocusState::Focused)
        return "AF focused in " + std::to_string(af.frames) + " frames";
    return "AF " + state + " · " + std::to_string(af.frames) + " frames";
}

std::span<const KeyBinding> keyBindings() {
    return kBindings;
}

Action actionForKey(Key key, char ch) {
    switch (key) {
        case Key::Left:
            return Action::FocusDown;
        case Key::Right:
            return Action::FocusUp;
        case Key::ShiftLeft:
            return Action::FocusDownFast;
        case Key::ShiftRight:
            return Action::FocusUpFast;
        case Key::Escape:
            return Action::Quit;
        case Key::Char:
            break;
    }
    switch (ch) {
        case 'a':
            return Action::Autofocus;
        case 'c':
            return Action::ToggleContinuous;
        case 'r':
            return Action::ResetPeak;
        case 'g':
            return Action::NextGrid;
        case 'p':
            return Action::NextPeaking;
        case 'm':
            return Action::ToggleMagnifier;
        case 'q':
        case 'Q':
            return Action::Quit;
        default:
            return Action::None;
    }
}

Status apply(Action action, LiveControls& controls, const LiveState* state) {
    switch (action) {
        case Action::FocusDown:
            return controls.focusStep(-1);
        case Action::FocusUp:
            return controls.focusStep(1);
        case Action::FocusDownFast:
            return controls.focusStep(-10);
        case Action::FocusUpFast:
            return controls.focusStep(10);
        case Action::Autofocus:
            return controls.autofocus();
        case Action::ToggleContinuous:
            return controls.setContinuousAutofocus(
                !(state && state->autofocus.mode == LiveAutofocusMode::Continuous));
        case Action::ResetPeak:
            controls.resetPeak();
            return {};
        case Action::NextGrid:
            if (!state) return {};
            {
                const auto [cols, rows] = nextGrid(state->cols, state->rows);
                return controls.setGrid(cols, rows);
            }
        case Action::NextPeaking:
            if (!state) return {};
            return controls.setPeaking(nextPeaking(state->peaking));
        case Action::None:
        case Action::Quit:
        case Action::ToggleMagnifier:
            break;
    }
    return {};
}

std::string keyHelp() {
    std::string out;
    for (const KeyBinding& b : keyBindings()) {
        out += std::string(b.keys);
        // Pad by code points, not bytes: the arrows are one column each.
        int cols = 0;
        for (unsigned char c : b.keys)
            if ((c & 0xC0) != 0x80) ++cols;
        out.append(cols < 11 ? 11 - cols : 1, ' ');
        out += std::string(b.help) + "\n";
    }
    return out;
}

}  // namespace infocus::present
