// SPDX-License-Identifier: MIT
// The decoder module's exported entry point.
#include "replay/decoders/decoders.h"

extern "C" __attribute__((visibility("default"))) const infocus::replay::Decoders*
infocus_decoders() {
    static const infocus::replay::Decoders kDecoders{
        infocus::replay::kDecodersAbi,
        &infocus::replay::decodeImage,
        &infocus::replay::openVideoReader,
    };
    return &kDecoders;
}
