// SPDX-License-Identifier: MIT
/// @file json_fields.h
/// Fields the JSON writers share. Internal to infocus.
#pragma once

#include <nlohmann/json.hpp>

#include "infocus/image.h"

namespace infocus::output {

/// Writes a region's place as `col`, `row`, `x`, `y`, `w`, `h`, in that order, into @p o.
inline void putRegionPlace(nlohmann::ordered_json& o, int col, int row, const Rect& rect) {
    o["col"] = col;
    o["row"] = row;
    o["x"] = rect.x;
    o["y"] = rect.y;
    o["w"] = rect.w;
    o["h"] = rect.h;
}

}  // namespace infocus::output
