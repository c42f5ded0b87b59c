// SPDX-License-Identifier: MIT
// The live pipeline's names: trends, peaking and autofocus modes as the faces and the state JSON
// write them.
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

std::string_view liveAutofocusModeName(LiveAutofocusMode m) {
    switch (m) {
        case LiveAutofocusMode::Once:
            return "once";
        case LiveAutofocusMode::Continuous:
            return "continuous";
        case LiveAutofocusMode::Off:
            break;
    }
    return "off";
}

Result<LiveAutofocusMode> parseLiveAutofocusMode(std::string_view name) {
    for (auto m : {LiveAutofocusMode::Off, LiveAutofocusMode::Once, LiveAutofocusMode::Continuous})
        if (name == liveAutofocusModeName(m)) return m;
    return makeError(ErrorKind::Usage, "autofocus mode '" + std::string(name) +
                                           "' is not one of off, once, continuous");
}

std::string_view liveAutofocusStateName(LiveAutofocusState s) {
    switch (s) {
        case LiveAutofocusState::Probing:
            return "probing";
        case LiveAutofocusState::Moving:
            return "moving";
        case LiveAutofocusState::Refining:
            return "refining";
        case LiveAutofocusState::Focused:
            return "focused";
        case LiveAutofocusState::Holding:
            return "holding";
        case LiveAutofocusState::Failed:
            return "failed";
        case LiveAutofocusState::Idle:
            break;
    }
    return "idle";
}

}  // namespace infocus
