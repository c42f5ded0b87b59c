// SPDX-License-Identifier: MIT
// The simulated camera's lens and the parsing of its source-string options.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "infocus/sim.h"
#include "replay/lens_motion.h"
#include "replay/playback.h"
#include "src/core/read_number.h"

namespace infocus {

SimLens::SimLens() : SimLens(*optics::findLensPreset("rpi-cam3")) {}

SimLens::SimLens(const optics::LensPreset& preset)
    : focalLengthM(preset.focalLength),
      fNumber(preset.fNumber),
      sensorPixelPitchM(preset.pixelPitch),
      sensorSize{preset.sensorWidthPx, preset.sensorHeightPx} {}

namespace {

// What a bad value should have been; empty when the value was taken.
using Want = std::string;

// A length with a unit (readLength: m, cm, mm, um or µm, nm), positive. A bare number is
// ambiguous and refused.
std::optional<double> length(const std::string& v) {
    auto m = readLength(v);
    if (m && *m > 0) return m;
    return std::nullopt;
}

// WIDTHxHEIGHT within [1, @p most] each, read whole (sscanf's %d overflows undefinedly).
std::optional<Size> sizeOf(const std::string& v, int most) {
    const size_t x = v.find_first_of("xX");
    int w = 0, h = 0;
    if (x == std::string::npos || !readsWhole(std::string_view(v).substr(0, x), w) ||
        !readsWhole(std::string_view(v).substr(x + 1), h) || w < 1 || h < 1 || w > most || h > most)
        return std::nullopt;
    return Size{w, h};
}

// One of @p names for @p v, its value from @p values at the same index.
template <class T, size_t N>
std::optional<T> choice(const std::string& v, const std::array<const char*, N>& names,
                        const std::array<T, N>& values) {
    for (size_t i = 0; i < N; ++i)
        if (v == names[i]) return values[i];
    return std::nullopt;
}

Want scene(SimConfig& c, const std::string& v) {
    const auto s =
        choice<SimScene, 4>(v, {"plane", "steps", "tilted", "edges"},
                            {SimScene::Plane, SimScene::Steps, SimScene::Tilted, SimScene::Edges});
    if (!s) return "use plane, steps, tilted or edges";
    c.scene = *s;
    return {};
}

Want focus(SimConfig& c, const std::string& v) {
    if (v == "inf") {
        c.focusDioptres = 0;
    } else if (v.size() > 3 && v.compare(v.size() - 3, 3, "dpt") == 0) {
        auto d = replay::parseNumber(v.substr(0, v.size() - 3));
        if (!d) return "dioptres must be a number ≥ 0, e.g. 0.8dpt";
        c.focusDioptres = *d;
    } else if (auto m = length(v)) {
        c.focusDioptres = 1.0 / *m;
    } else {
        return "give a distance with a unit (1.2m) or dioptres (0.8dpt)";
    }
    return {};
}

Want distance(SimConfig& c, const std::string& v) {
    auto m = length(v);
    if (!m) return "give a distance with a unit, e.g. 1m or 80cm";
    c.distancesM = {*m};
    return {};
}

Want distances(SimConfig& c, const std::string& v) {
    c.distancesM.clear();
    size_t start = 0;
    while (start <= v.size()) {
        const size_t end = std::min(v.find(':', start), v.size());
        auto m = length(v.substr(start, end - start));
        if (!m) return "give distances with units separated by ':'";
        c.distancesM.push_back(*m);
        start = end + 1;
    }
    return {};
}

// An angle in degrees ("30" or "30deg") within ±@p most (exclusive when @p open).
std::optional<double> degrees(std::string v, double most, bool open) {
    if (v.size() > 3 && v.compare(v.size() - 3, 3, "deg") == 0) v.resize(v.size() - 3);
    char* end = nullptr;
    const double d = std::strtod(v.c_str(), &end);
    // NaN passes every comparison of the renderer and an infinite angle has no sine.
    if (v.empty() || *end || !(open ? std::abs(d) < most : std::abs(d) <= most))
        return std::nullopt;
    return d;
}

Want tilt(SimConfig& c, const std::string& v) {
    auto d = degrees(v, 80, true);
    if (!d) return "give the plane's tilt in degrees within ±80, e.g. 30";
    c.tiltDeg = *d;
    return {};
}

Want angle(SimConfig& c, const std::string& v) {
    auto d = degrees(v, 360, false);
    if (!d) return "give the edges' angle in degrees within ±360, e.g. 5";
    c.edgeAngleDeg = *d;
    return {};
}

Want axis(SimConfig& c, const std::string& v) {
    const auto a = choice<SimAxis, 2>(v, {"x", "y"}, {SimAxis::X, SimAxis::Y});
    if (!a) return "use x or y";
    c.tiltAxis = *a;
    return {};
}

Want size(SimConfig& c, const std::string& v) {
    // The dead-leaves texture's largest discs are a twentieth of the width: at 30 px they are
    // no larger than its smallest, and their mean area is 0 / 0.
    auto s = sizeOf(v, 8192);
    if (!s || s->width < 32 || s->height < 16)
        return "give WIDTHxHEIGHT from 32x16 to 8192x8192 pixels, e.g. 1280x720";
    c.size = *s;
    return {};
}

Want sensor(SimConfig& c, const std::string& v) {
    auto s = sizeOf(v, 100000);
    if (!s) return "give the sensor's WIDTHxHEIGHT in pixels, e.g. 4608x2592";
    c.lens.sensorSize = *s;
    return {};
}

Want fps(SimConfig& c, const std::string& v) {
    auto f = replay::parseNumber(v);
    if (!f || !(*f >= replay::kMinFps && *f <= replay::kMaxFps))
        return "give a frame rate from 0.000001 to 1000000";
    c.fps = *f;
    return {};
}

Want noise(SimConfig& c, const std::string& v) {
    auto n = replay::parseNumber(v);
    if (!n || *n > 1) return "give σ as a fraction of full scale, 0..1";
    c.noise = *n;
    return {};
}

Want seed(SimConfig& c, const std::string& v) {
    // Read as an integer: a double loses seeds past 2^53 and casts 2^64 undefinedly.
    if (!readsWhole(v, c.seed)) return "give a whole number from 0 to 18446744073709551615";
    return {};
}

Want format(SimConfig& c, const std::string& v) {
    const auto f = choice<PixelFormat, 4>(
        v, {"GREY", "grey", "YUYV", "yuyv"},
        {PixelFormat::GREY, PixelFormat::GREY, PixelFormat::YUYV, PixelFormat::YUYV});
    if (!f) return "use GREY or YUYV";
    c.format = *f;
    return {};
}

Want pace(SimConfig& c, const std::string& v) {
    const auto p = choice<bool, 2>(v, {"camera", "fast"}, {true, false});
    if (!p) return "use camera (real time at fps) or fast";
    c.paced = *p;
    return {};
}

Want focal(SimConfig& c, const std::string& v) {
    auto m = length(v);
    if (!m) return "give a focal length with a unit, e.g. 4.74mm";
    c.lens.focalLengthM = *m;
    return {};
}

Want fnumber(SimConfig& c, const std::string& v) {
    auto n = replay::parseNumber(v);
    if (!n || *n < 0.5 || *n > 128) return "give an f-number from 0.5 to 128, e.g. 1.8";
    c.lens.fNumber = *n;
    return {};
}

Want pitch(SimConfig& c, const std::string& v) {
    auto m = length(v);
    if (!m || *m < 0.1e-6 || *m > 1e-3)
        return "give the sensor pixel pitch from 0.1um to 1mm with a unit, e.g. 1.4um";
    c.lens.sensorPixelPitchM = *m;
    return {};
}

Want travel(SimConfig& c, const std::string& v) {
    auto t = replay::readDurationS(v);
    if (!t || *t > 60) return "give the lens's time over its whole range, 0 to 60 s, e.g. 20ms";
    c.lensTravelS = *t;
    return {};
}

Want settle(SimConfig& c, const std::string& v) {
    auto t = replay::readDurationS(v);
    if (!t || *t > 60) return "give the lens's settle time, 0 to 60 s, e.g. 10ms";
    c.lensSettleS = *t;
    return {};
}

Want delay(SimConfig& c, const std::string& v) {
    if (!readsWhole(v, c.delayFrames) || c.delayFrames < 0 || c.delayFrames > 100)
        return "give the frames between exposure and delivery, 0 to 100, e.g. 2";
    return {};
}

Want move(SimConfig& c, const std::string& v) {
    const size_t colon = v.find(':');
    const auto to = colon == std::string::npos ? std::nullopt : length(v.substr(0, colon));
    const auto t =
        colon == std::string::npos ? std::nullopt : replay::readDurationS(v.substr(colon + 1));
    if (!to || !t || !(*t > 0) || *t > 1e6)
        return "give the distance to reach and the time to reach it, e.g. 0.5m:4s";
    c.moveToM = *to;
    c.moveS = *t;
    return {};
}

// Every option of a sim: source string, in the order the help lists them.
struct SimOption {
    const char* key;
    Want (*apply)(SimConfig&, const std::string&);
};
constexpr SimOption kOptions[] = {
    {"scene", scene},   {"focus", focus},   {"distance", distance}, {"distances", distances},
    {"tilt", tilt},     {"axis", axis},     {"angle", angle},       {"size", size},
    {"fps", fps},       {"noise", noise},   {"seed", seed},         {"format", format},
    {"pace", pace},     {"focal", focal},   {"fnumber", fnumber},   {"pitch", pitch},
    {"sensor", sensor}, {"travel", travel}, {"settle", settle},     {"delay", delay},
    {"move", move},
};

}  // namespace

Result<SimConfig> parseSimOptions(const std::map<std::string, std::string>& options) {
    SimConfig c;
    for (const auto& [key, value] : options) {
        const SimOption* option = nullptr;
        for (const SimOption& o : kOptions)
            if (key == o.key) option = &o;
        if (!option) {
            std::string keys;
            for (const SimOption& o : kOptions)
                keys += std::string(keys.empty() ? "" : ", ") + o.key;
            return makeError(ErrorKind::Usage,
                             "sim: unknown option '" + key + "'; sim: takes " + keys);
        }
        if (Want want = option->apply(c, value); !want.empty())
            return makeError(ErrorKind::Usage, "sim: option " + key + "=" + value + ": " + want);
    }
    if (c.scene == SimScene::Steps && !options.count("distances"))
        c.distancesM = {0.3, 0.6, 1.2, 2.4, 4.8};
    // A focus nearer than the focal length has no image behind the lens.
    if (c.focusDioptres * c.lens.focalLengthM >= 1) {
        const auto it = options.find("focus");
        return makeError(ErrorKind::Usage,
                         "sim: option focus=" + (it != options.end() ? it->second : "") +
                             ": the lens focuses no nearer than its focal length; give a "
                             "farther focus, e.g. 1m");
    }
    // The diffraction blur in output pixels sets the renderer's margins: a sensor much
    // narrower than the output (pixels far below the pitch) would make them unbounded.
    const double sigmaPx =
        0.42 * kSimWavelengthM * c.lens.fNumber / c.lens.pixelPitchM(c.size.width);
    if (!(sigmaPx <= 16)) {
        std::string given;
        for (const char* k : {"fnumber", "pitch", "sensor", "size"})
            if (auto it = options.find(k); it != options.end())
                given += std::string(given.empty() ? "" : ", ") + k + "=" + it->second;
        return makeError(ErrorKind::Usage,
                         "sim: the lens's diffraction blur would have σ = " +
                             std::to_string(static_cast<int>(std::min(sigmaPx, 1e9))) +
                             " output pixels, more than 16 (" + given +
                             "); give a sensor= at least as wide as size=, or a smaller fnumber=");
    }
    if (c.format == PixelFormat::YUYV && c.size.width % 2)
        return makeError(ErrorKind::Usage, "sim: format=YUYV needs an even width");
    return c;
}

}  // namespace infocus
