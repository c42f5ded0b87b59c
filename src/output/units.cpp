// SPDX-License-Identifier: MIT
#include "infocus/units.h"

#include <cmath>
#include <cstdio>

namespace infocus {

std::string formatDistance(double metres) {
    if (std::isinf(metres)) return "infinity";
    char buf[64];
    const double a = std::abs(metres);
    if (a < 1.0)
        std::snprintf(buf, sizeof buf, "%.1f mm", metres * 1e3);
    else if (a < 10.0)
        std::snprintf(buf, sizeof buf, "%.3f m", metres);
    else if (a < 100.0)
        std::snprintf(buf, sizeof buf, "%.2f m", metres);
    else if (a < 1e4)
        std::snprintf(buf, sizeof buf, "%.1f m", metres);
    else if (a < 1e9)
        std::snprintf(buf, sizeof buf, "%.0f m", metres);
    else  // past any focus scale (a far limit of 1e300 m): digits would only hide the magnitude
        std::snprintf(buf, sizeof buf, "%.3g m", metres);
    return buf;
}

std::string formatSensorLength(double metres) {
    char buf[64];
    if (std::abs(metres) >= 1.0) return formatDistance(metres);  // no sensor is that large
    if (std::abs(metres) < 1e-3)
        std::snprintf(buf, sizeof buf, "%.1f µm", metres * 1e6);
    else
        std::snprintf(buf, sizeof buf, "%.2f mm", metres * 1e3);
    return buf;
}

}  // namespace infocus
