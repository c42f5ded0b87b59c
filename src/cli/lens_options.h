// SPDX-License-Identifier: MIT
/// @file lens_options.h
/// The shared lens options of the CLI (docs/design.md, Lens options): --focal, --fnumber, --focus,
/// --pixel-pitch, --coc, --lens PRESET. Values arrive as text and are parsed here, so a bad value
/// gets a message that says what to type instead. Everything comes out in SI units.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <string_view>

#include "infocus/error.h"
#include "infocus/lens_presets.h"
#include "infocus/units.h"

namespace infocus::cli {

/// Parses a length with a unit ("50mm", "1.4um", "2.5 m", "3cm", "550nm") into metres. A bare
/// number is a usage error naming @p option and an example with a unit.
Result<double> parseLength(std::string_view text, std::string_view option);

/// Parses a focus setting into metres from the lens or sensor: a distance with a unit, "inf" /
/// "infinity", or dioptres ("0.4dpt", "0.4D"; 0 dpt is infinity).
Result<double> parseFocus(std::string_view text, std::string_view option);

/// Parses an f-number: "8", "f/8", "f8", "F2.8". Must be positive.
Result<double> parseFNumber(std::string_view text, std::string_view option);

/// Which lens options a command offers.
struct LensOptionSet {
    bool coc = false;   ///< --coc, --sensor, --coc-px
    bool pitch = true;  ///< --pixel-pitch
};

/// Lens values after parsing; unset where the user gave nothing and no preset supplied it.
struct LensValues {
    std::optional<double> focalLength;  ///< metres
    std::optional<double> fNumber;
    std::optional<double> focusDistance;  ///< metres (∞ allowed)
    std::optional<double> pixelPitch;     ///< metres per pixel
    std::optional<double> coc;            ///< metres
    std::string cocSource;                ///< how the CoC was chosen, for the output
    const optics::LensPreset* preset = nullptr;
};

/// The lens options of one subcommand: add() registers them, resolve() parses and checks them.
class LensOptions {
public:
    /// Adds the options in @p set to @p app, under the headings "Lens" and "Circle of
    /// confusion".
    void add(CLI::App* app, LensOptionSet set);

    /// Parses what was given, fills gaps from --lens, and checks f > 0, N > 0, pitch > 0, c > 0.
    /// Fails with ErrorKind::Usage and a message that names the option and a fix.
    Result<LensValues> resolve() const;

private:
    std::string focal_, fNumber_, focus_, pitch_, coc_, cocPx_, sensor_, lens_;
};

}  // namespace infocus::cli
