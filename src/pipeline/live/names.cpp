// SPDX-License-Identifier: MIT
// The live pipeline's names: trends and peaking modes as the faces and the state JSON write them.
#include <string>

#include "infocus/live.h"

namespace infocus {

std::string_view trendName(Trend t) {
    switch (t) {
        case Trend::Sharper:
            return "sharper";
        case Trend::Worse:
            return "worse";
        case Trend::Steady:
            break;
    }
    return "steady";
}

std::string_view peakingModeName(PeakingMode m) {
    switch (m) {
        case PeakingMode::Coc:
            return "coc";
        case PeakingMode::Percentile:
            return "percentile";
        case PeakingMode::Off:
            break;
    }
    return "off";
}

Result<PeakingMode> parsePeakingMode(std::string_view name) {
    for (PeakingMode m : {PeakingMode::Off, PeakingMode::Coc, PeakingMode::Percentile})
        if (name == peakingModeName(m)) return m;
    return makeError(ErrorKind::Usage,
                     "peaking mode '" + std::string(name) + "' is not one of off, coc, percentile");
}

}  // namespace infocus
