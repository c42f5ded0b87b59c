// SPDX-License-Identifier: MIT
/// @file screen.h
/// Draws one LiveState on the ncurses standard screen: title, meter, history, region heat map,
/// optics, status and help, laid out for the terminal's current size (80×24 and up).
#pragma once

#include <string>

#include "src/live/tui/tui.h"

namespace infocus::tui {

/// What the screen shows beside the state.
struct ScreenNotes {
    bool fromSim = false;  ///< the title says the source is the simulated camera
    std::string status;    ///< replaces the state's status (a control's error); empty: the state's
    bool statusIsError = false;
};

/// Sets up the colour pairs; call once after the screen is initialised.
void initColours();

/// Erases the screen and draws @p state (null: waiting for the first frame). Does not refresh.
void drawScreen(const LiveState* state, const ScreenNotes& notes);

}  // namespace infocus::tui
