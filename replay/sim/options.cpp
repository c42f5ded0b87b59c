// SPDX-License-Identifier: MIT
// The simulated camera's lens and the parsing of its source-string options.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "infocus/sim.h"
#include "replay/playback.h"
#include "src/core/read_number.h"

namespace infocus {

SimLens::SimLens() : SimLens(*optics::findLensPreset("rpi-cam3")) {}

SimLens::SimLens(const optics::LensPreset& preset)
    : focalLengthM(preset.focalLength),
      fNumber(preset.fNumber),
      sensorPixelPitchM(preset.pixelPitch),
      sensorSize{preset.sensorWidthPx, preset.sensorHeightPx} {}

Result<SimConfig> parseSimOptions(const std::map<std::string, std::string>& options) {
    SimConfig c;
    const auto bad = [](const std::string& key, const std::string& value,
                        const std::string& want) -> Error {
        return makeError(ErrorKind::Usage, "sim: option " + key + "=" + value + ": " + want);
    };
    // A length with a unit: m, cm, mm or um. A bare number is ambiguous and refused.
    const auto length = [](const std::string& v) -> std::optional<double> {
        static const std::pair<const char*, double> kUnits[] = {
            {"mm", 1e-3}, {"cm", 1e-2}, {"um", 1e-6}, {"m", 1.0}};
        for (const auto& [unit, scale] : kUnits) {
            const size_t n = std::strlen(unit);
            if (v.size() > n && v.compare(v.size() - n, n, unit) == 0) {
                auto num = replay::parseNumber(v.substr(0, v.size() - n));
                if (num && *num > 0) return *num * scale;
                return std::nullopt;
            }
        }
        return std::nullopt;
    };
    // WIDTHxHEIGHT within [1, @p most] each, read whole (sscanf's %d overflows undefinedly).
    const auto sizeOf = [](const std::string& v, int most) -> std::optional<Size> {
        const size_t x = v.find_first_of("xX");
        int w = 0, h = 0;
        if (x == std::string::npos || !readsWhole(std::string_view(v).substr(0, x), w) ||
            !readsWhole(std::string_view(v).substr(x + 1), h) || w < 1 || h < 1 || w > most ||
            h > most)
            return std::nullopt;
        return Size{w, h};
    };
    for (const auto& [key, value] : options) {
        if (key == "scene") {
            if (value == "plane")
                c.scene = SimScene::Plane;
            else if (value == "steps")
                c.scene = SimScene::Steps;
            else if (value == "tilted")
                c.scene = SimScene::Tilted;
            else if (value == "edges")
                c.scene = SimScene::Edges;
            else
                return bad(key, value, "use plane, steps, tilted or edges");
        } else if (key == "focus") {
            if (value == "inf") {
                c.focusDioptres = 0;
            } else if (value.size() > 3 && value.compare(value.size() - 3, 3, "dpt") == 0) {
                auto d = replay::parseNumber(value.substr(0, value.size() - 3));
                if (!d) return bad(key, value, "dioptres must be a number ≥ 0, e.g. 0.8dpt");
                c.focusDioptres = *d;
            } else if (auto m = length(value)) {
                c.focusDioptres = 1.0 / *m;
            } else {
                return bad(key, value, "give a distance with a unit (1.2m) or dioptres (0.8dpt)");
            }
        } else if (key == "distance") {
            auto m = length(value);
            if (!m) return bad(key, value, "give a distance with a unit, e.g. 1m or 80cm");
            c.distancesM = {*m};
        } else if (key == "distances") {
            c.distancesM.clear();
            size_t start = 0;
            while (start <= value.size()) {
                const size_t end = std::min(value.find(':', start), value.size());
                auto m = length(value.substr(start, end - start));
                if (!m) return bad(key, value, "give distances with units separated by ':'");
                c.distancesM.push_back(*m);
                start = end + 1;
            }
        } else if (key == "tilt" || key == "angle") {
            std::string v = value;
            if (v.size() > 3 && v.compare(v.size() - 3, 3, "deg") == 0) v.resize(v.size() - 3);
            char* end = nullptr;
            const double d = std::strtod(v.c_str(), &end);
            // NaN passes every comparison of the renderer and an infinite angle has no sine.
            if (key == "tilt" && (v.empty() || *end || !(std::abs(d) < 80)))
                return bad(key, value, "give the plane's tilt in degrees within ±80, e.g. 30");
            if (key == "angle" && (v.empty() || *end || !(std::abs(d) <= 360)))
                return bad(key, value, "give the edges' angle in degrees within ±360, e.g. 5");
            (key == "tilt" ? c.tiltDeg : c.edgeAngleDeg) = d;
        } else if (key == "axis") {
            if (value == "x")
                c.tiltAxis = SimAxis::X;
            else if (value == "y")
                c.tiltAxis = SimAxis::Y;
            else
                return bad(key, value, "use x or y");
        } else if (key == "size") {
            // The dead-leaves texture's largest discs are a twentieth of the width: at 30 px
            // they are no larger than its smallest, and their mean area is 0 / 0.
            auto s = sizeOf(value, 8192);
            if (!s || s->width < 32 || s->height < 16)
                return bad(key, value,
                           "give WIDTHxHEIGHT from 32x16 to 8192x8192 pixels, e.g. 1280x720");
            c.size = *s;
        } else if (key == "sensor") {
            auto s = sizeOf(value, 100000);
            if (!s)
                return bad(key, value, "give the sensor's WIDTHxHEIGHT in pixels, e.g. 4608x2592");
            c.lens.sensorSize = *s;
        } else if (key == "fps") {
            auto v = replay::parseNumber(value);
            if (!v || !(*v >= replay::kMinFps && *v <= replay::kMaxFps))
                return bad(key, value, "give a frame rate from 0.000001 to 1000000");
            c.fps = *v;
        } else if (key == "noise") {
            auto v = replay::parseNumber(value);
            if (!v || *v > 1) return bad(key, value, "give σ as a fraction of full scale, 0..1");
            c.noise = *v;
        } else if (key == "seed") {
            // Read as an integer: a double loses seeds past 2^53 and casts 2^64 undefinedly.
            if (!readsWhole(value, c.seed))
                return bad(key, value, "give a whole number from 0 to 18446744073709551615");
        } else if (key == "format") {
            if (value == "GREY" || value == "grey")
                c.format = PixelFormat::GREY;
            else if (value == "YUYV" || value == "yuyv")
                c.format = PixelFormat::YUYV;
            else
                return bad(key, value, "use GREY or YUYV");
        } else if (key == "pace") {
            if (value == "camera")
                c.paced = true;
            else if (value == "fast")
                c.paced = false;
            else
                return bad(key, value, "use camera (real time at fps) or fast");
        } else if (key == "focal") {
            auto m = length(value);
            if (!m) return bad(key, value, "give a focal length with a unit, e.g. 4.74mm");
            c.lens.focalLengthM = *m;
        } else if (key == "fnumber") {
            auto v = replay::parseNumber(value);
            if (!v || *v < 0.5 || *v > 128)
                return bad(key, value, "give an f-number from 0.5 to 128, e.g. 1.8");
            c.lens.fNumber = *v;
        } else if (key == "pitch") {
            auto m = length(value);
            if (!m || *m < 0.1e-6 || *m > 1e-3)
                return bad(key, value,
                           "give the sensor pixel pitch from 0.1um to 1mm with a unit, e.g. 1.4um");
            c.lens.sensorPixelPitchM = *m;
        } else {
            return makeError(ErrorKind::Usage,
                             "sim: unknown option '" + key +
                                 "'; sim: takes scene, focus, distance, distances, tilt, axis, "
                                 "angle, size, fps, noise, seed, format, pace, focal, fnumber, "
                                 "pitch, sensor");
        }
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
