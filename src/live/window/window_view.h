// SPDX-License-Identifier: MIT
// What the window draws of one LiveState with Dear ImGui: the overlays on the picture (region
// heat map, in-focus line, ROI, magnifier inset) and the panel (meter, history, lens, optics,
// throughput, help). Also the window's layout and the small state machines of its keys.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "infocus/live.h"

struct ImDrawList;
struct ImFont;

namespace infocus::window {

/// The panel's width in window pixels; the picture takes the rest.
inline constexpr float kPanelWidth = 390.0f;

/// Where the picture sits in the window: letterboxed into the area left of the panel.
struct PictureRect {
    float x = 0, y = 0, w = 0, h = 0;  ///< window pixels
    float scale = 1;                   ///< window pixels per frame pixel
    /// Frame pixel under window point (wx, wy), unclamped.
    std::array<float, 2> toFrame(float wx, float wy) const {
        return {(wx - x) / scale, (wy - y) / scale};
    }
    bool contains(float wx, float wy) const {
        return wx >= x && wx < x + w && wy >= y && wy < y + h;
    }
};

/// The largest rectangle of @p frameW × @p frameH's aspect ratio centred in the area
/// (@p areaW × @p areaH at the window's origin); empty for an empty frame or area.
PictureRect letterbox(int frameW, int frameH, float areaW, float areaH);

/// What the window adds to the state's picture: the ROI being dragged and the magnifier inset.
struct OverlayNotes {
    std::optional<Rect> dragRoi;                ///< frame pixels, while the left button is held
    void* magnifierTexture = nullptr;           ///< SDL_Texture* of the state's magnifier crop
    std::optional<std::array<float, 2>> mouse;  ///< window pixels, over the picture
};

/// Draws the region heat map (blur against the circle of confusion, grey under the confidence
/// the engine trusts, the number where it fits),
/// the in-focus line, the ROI and the magnifier inset of @p s over the picture at @p pic.
void drawOverlays(ImDrawList& dl, const LiveState& s, const PictureRect& pic,
                  const OverlayNotes& notes);

/// What the panel shows besides the state.
struct PanelNotes {
    ImFont* bigFont = nullptr;  ///< the score's font; null: the default font scaled
    std::string status;         ///< a control's error, shown instead of the state's status
    double drawFps = 0;         ///< windows drawn per second
    std::string renderer;       ///< SDL's renderer (opengl, software, …)
    int magnifierZoom = 1;
};

/// Draws the panel (an ImGui window of kPanelWidth at the right of a @p windowW × @p windowH
/// window) for @p s, or a waiting note while @p s is null.
void drawPanel(const LiveState* s, const PanelNotes& notes, float windowW, float windowH);

}  // namespace infocus::window
