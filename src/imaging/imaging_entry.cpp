// SPDX-License-Identifier: MIT
// The imaging module's exported entry point.
#include "src/imaging/imaging.h"

extern "C" __attribute__((visibility("default"))) const infocus::imaging::ImagingBackend*
infocus_imaging() {
    static const infocus::imaging::ImagingBackend kBackend{
        infocus::imaging::kImagingAbi,
        &infocus::imaging::composeAllInFocus,
        &infocus::imaging::focusMapColour,
    };
    return &kBackend;
}
