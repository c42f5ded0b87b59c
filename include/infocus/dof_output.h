// SPDX-License-Identifier: MIT
/// @file dof_output.h
/// `infocus dof`: a depth-of-field answer as JSON or text. Lengths for
/// people come from units.h.
#pragma once

#include <optional>
#include <ostream>
#include <string>

#include "infocus/dof.h"
#include "infocus/units.h"

namespace infocus {

/// The limits asked of `infocus dof --near --far`, metres (far may be ∞).
struct DofWanted {
    double nearDistance = 0.0;
    double farDistance = 0.0;
};

/// @p r for input @p in as one JSON object (no trailing newline), metres and null for infinity;
/// with @p wanted also the limits asked for.
std::string dofJson(const optics::DofResult& r, const optics::DofInput& in,
                    std::string_view cocSource, const std::optional<DofWanted>& wanted = {});

/// Writes @p r for people: with @p wanted first the focus and f-number that cover it, then the
/// limits, the hyperfocal distance, the common approximations and the diffraction budget.
void writeDofText(std::ostream& out, const optics::DofResult& r, const optics::DofInput& in,
                  std::string_view cocSource, const std::optional<DofWanted>& wanted = {});

}  // namespace infocus
