// SPDX-License-Identifier: MIT
// Grey levels decoded to light and encoded again (BlurOptions::transfer): the ESF's profile is
// taken in light, what judges an edge in the frame's grey levels.
#include "internal.h"

namespace infocus::blur_detail {

namespace {

// Light (0..1) of the encoded value @p v (0..1) under @p tf.
double decodeLight(TransferFunction tf, double v) {
    switch (tf) {
        case TransferFunction::Srgb:  // IEC 61966-2-1
            return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
        case TransferFunction::Rec709:  // ITU-R BT.709, the inverse of its camera curve
            return v < 0.081 ? v / 4.5 : std::pow((v + 0.099) / 1.099, 1.0 / 0.45);
        case TransferFunction::Linear:
            break;
    }
    return v;
}

}  // namespace

double encodeLight(TransferFunction tf, double l) {
    l = std::clamp(l, 0.0, 1.0);
    switch (tf) {
        case TransferFunction::Srgb:
            return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
        case TransferFunction::Rec709:
            return l < 0.018 ? 4.5 * l : 1.099 * std::pow(l, 0.45) - 0.099;
        case TransferFunction::Linear:
            break;
    }
    return l;
}

Decoding decodingFor(TransferFunction tf) {
    if (tf == TransferFunction::Linear) return {};
    const auto make = [](TransferFunction t) {
        std::vector<double> table(255 * kDecodeSteps + 1);
        for (size_t i = 0; i < table.size(); ++i)
            table[i] = 255.0 * decodeLight(t, i / (255.0 * kDecodeSteps));
        return table;
    };
    static const std::vector<double> srgb = make(TransferFunction::Srgb);
    static const std::vector<double> rec709 = make(TransferFunction::Rec709);
    return {tf, tf == TransferFunction::Srgb ? &srgb : &rec709};
}

}  // namespace infocus::blur_detail
