// SPDX-License-Identifier: MIT
/// @file present.h
/// How every face of `infocus live` presents the state and reads a person's keys: the heat class
/// of a region, the grid and peaking cycles, distances for people, and the key → control map.
/// The terminal and the window call these; the page reads the heat class from the state JSON.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>

#include "infocus/error.h"
#include "infocus/live.h"

namespace infocus::present {

/// How a region's blur compares with the circle of confusion (the heat map's colours).
enum class Heat {
    Unknown,  ///< no blur reading, or its confidence is under kLowBlurConfidence
    InCoc,    ///< blur ≤ 1× CoC
    Near,     ///< ≤ 2×
    Far,      ///< ≤ 4×
    Beyond,   ///< more
};

/// The heat class of @p region against @p cocPx (pixels; ≤ 0: every reading is Unknown).
Heat heatOf(const LiveRegion& region, double cocPx);

/// "unknown", "in_coc", "near", "far", "beyond": the state JSON's `heat`.
std::string_view heatName(Heat heat);

/// Whether @p region has a blur reading confident enough to show as a number.
bool showsBlur(const LiveRegion& region);

/// The grid the grid key goes to from @p cols × @p rows: 16×9 → 8×6 → 4×3 → 16×9 (any other
/// grid → 16×9).
std::pair<int, int> nextGrid(int cols, int rows);

/// The peaking mode after @p m in the cycle off → coc → percentile → off.
PeakingMode nextPeaking(PeakingMode m);

/// A distance for a live view, 2–3 significant digits so that it does not flicker: "512 mm",
/// "1.00 m", "12.5 m", "230 m", "infinity".
std::string distanceText(double metres);

/// distanceText, or "—" when @p metres is empty.
std::string distanceText(std::optional<double> metres);

/// Autofocus in a few words for a status line: "" when off and idle; "AF moving · 4 frames",
/// "AF focused in 7 frames", "AF continuous: holding", "AF failed: <reason>".
std::string autofocusText(const LiveAutofocus& af);

/// What a key asks of the live view. Quit and ToggleMagnifier are the face's own to carry out.
enum class Action {
    None,
    Quit,
    FocusDown,      ///< the lens one step down its control's range
    FocusUp,        ///< one step up
    FocusDownFast,  ///< ten steps down
    FocusUpFast,    ///< ten steps up
    Autofocus,
    ToggleContinuous,  ///< continuous autofocus on ↔ off
    ResetPeak,
    NextGrid,
    NextPeaking,
    ToggleMagnifier,
};

/// A key a face reads, named without its toolkit's codes.
enum class Key { Char, Left, Right, ShiftLeft, ShiftRight, Escape };

/// One line of the key map: the keys as a person reads them, the action, what it does.
struct KeyBinding {
    std::string_view keys;  ///< "←/→", "a", …
    Action action;
    std::string_view help;
};

/// The key map shared by the terminal and the window, in the order the help lists it.
std::span<const KeyBinding> keyBindings();

/// The action of @p key (@p ch is the character when @p key is Key::Char); Action::None when
/// the key means nothing.
Action actionForKey(Key key, char ch = 0);

/// Carries out @p action on @p controls, given the newest state @p state (may be null: grid and
/// peaking then do nothing). Quit, ToggleMagnifier and None do nothing here.
Status apply(Action action, LiveControls& controls, const LiveState* state);

/// The key map as help text, one "keys  what it does" line each.
std::string keyHelp();

}  // namespace infocus::present
