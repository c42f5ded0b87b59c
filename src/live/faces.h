// SPDX-License-Identifier: MIT
/// @file faces.h
/// The faces of `infocus live` this build has, chosen by name: the one place that knows which
/// were built (as drivers/sources.cpp is for camera backends). The web page and the window are
/// modules loaded when asked for, so that no other command loads their libraries.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "infocus/error.h"
#include "infocus/live.h"
#include "src/live/face.h"

namespace infocus {

/// The faces of one run: at most one that holds the terminal or a window (tui, window, text,
/// json), and the web page beside it or alone.
struct FaceChoice {
    std::string blocking;  ///< "tui", "window", "text", "json", or empty (the page alone)
    bool web = false;
};

/// Parses --ui's comma list. ErrorKind::Usage when it names no face, an unknown one, two that
/// hold the terminal, or one this infocus was built without (naming those it has).
Result<FaceChoice> parseFaces(std::string_view ui);

/// The face when none is named: the terminal meter on a terminal where it was built, else the
/// text lines.
std::string defaultFace(bool onTerminal);

/// The faces this infocus was built with, in the order the help lists them.
std::vector<std::string> builtFaces();

/// The faces of one run, made and prepared; runs them over a started pipeline.
class FaceSet {
public:
    /// Makes the faces of @p choice (loading the web and window modules) and prepares each on
    /// @p options before the source opens. ErrorKind::Usage when a face cannot run here (no
    /// display, a missing module, a bad address), naming the faces that can.
    static Result<FaceSet> make(const FaceChoice& choice, const FaceSettings& settings,
                                LiveOptions& options);
    FaceSet(FaceSet&&) noexcept;
    FaceSet& operator=(FaceSet&&) noexcept;
    ~FaceSet();

    /// Starts the background faces, runs the blocking one (or waits, for the page alone) until
    /// @p limits end the run, the face is closed or @p view ends, and stops them all.
    Status run(LiveView& view, const RunLimits& limits);

private:
    FaceSet() = default;
    std::unique_ptr<Face> blocking_;
    std::unique_ptr<Face> web_;
};

}  // namespace infocus
