// SPDX-License-Identifier: MIT
// Camera modules and lenses by their published specifications.
#include "infocus/lens_presets.h"

#include <algorithm>
#include <array>
#include <cctype>

namespace infocus::optics {

namespace {

// Raspberry Pi camera modules (v1 OV5647 3.60 mm f/2.9, v2 IMX219 3.04 mm f/2.0, Module 3 IMX708
// 4.74 mm f/1.8 and wide 2.75 mm f/2.2) and the HQ camera (IMX477) with the official 6 mm f/1.2
// CS-mount and 16 mm f/1.4 C-mount lenses.
const std::array<LensPreset, 7> kLenses{{
    {"rpi-cam1", "Raspberry Pi Camera Module v1, 3.60 mm f/2.9, 1.4 um pixels", 3.60e-3, 2.9,
     1.4e-6, 2592, 1944, "rpi-cam1"},
    {"rpi-cam2", "Raspberry Pi Camera Module v2, 3.04 mm f/2.0, 1.12 um pixels", 3.04e-3, 2.0,
     1.12e-6, 3280, 2464, "rpi-cam2"},
    {"rpi-cam3", "Raspberry Pi Camera Module 3, 4.74 mm f/1.8, 1.4 um pixels", 4.74e-3, 1.8, 1.4e-6,
     4608, 2592, "rpi-cam3"},
    {"rpi-cam3-wide", "Raspberry Pi Camera Module 3 Wide, 2.75 mm f/2.2, 1.4 um pixels", 2.75e-3,
     2.2, 1.4e-6, 4608, 2592, "rpi-cam3"},
    {"rpi-hq-6mm", "Raspberry Pi HQ Camera with the 6 mm f/1.2 lens, 1.55 um pixels", 6e-3, 1.2,
     1.55e-6, 4056, 3040, "rpi-hq"},
    {"rpi-hq-16mm", "Raspberry Pi HQ Camera with the 16 mm f/1.4 lens, 1.55 um pixels", 16e-3, 1.4,
     1.55e-6, 4056, 3040, "rpi-hq"},
    {"full-frame-50mm", "a 50 mm f/1.8 lens on a 36 x 24 mm sensor", 50e-3, 1.8, 0.0, 0, 0,
     "full-frame"},
}};

bool equalsIgnoreCase(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) ==
                      std::tolower(static_cast<unsigned char>(y));
           });
}

}  // namespace

std::span<const LensPreset> lensPresets() {
    return kLenses;
}

const LensPreset* findLensPreset(std::string_view name) {
    for (const auto& l : kLenses)
        if (equalsIgnoreCase(l.name, name)) return &l;
    return nullptr;
}

}  // namespace infocus::optics
