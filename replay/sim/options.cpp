// SPDX-License-Identifier: MIT
// The simulated camera's lens and the parsing of its source-string options.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "infocus/sim.h"
#include "replay/playback.h"

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
    const auto sizeOf = [](const std::string& v) -> std::optional<Size> {
        int w = 0, h = 0;
        char x = 0;
        if (std::sscanf(v.c_str(), "%d%c%d", &w, &x, &h) != 3 || (x != 'x' && x != 'X') || w <= 0 ||
            h <= 0)
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
            if (v.empty() || *end) return bad(key, value, "give an angle in degrees, e.g. 30");
            (key == "tilt" ? c.tiltDeg : c.edgeAngleDeg) = d;
        } else if (key == "axis") {
            if (value == "x")
                c.tiltAxis = SimAxis::X;
            else if (value == "y")
                c.tiltAxis = SimAxis::Y;
            else
                return bad(key, value, "use x or y");
        } else if (key == "size" || key == "sensor") {
            auto s = sizeOf(value);
            if (!s) return bad(key, value, "give WIDTHxHEIGHT, e.g. 1280x720");
            (key == "size" ? c.size : c.lens.sensorSize) = *s;
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
            auto v = replay::parseNumber(value);
            if (!v || std::floor(*v) != *v) return bad(key, value, "give a non-negative integer");
            c.seed = static_cast<uint64_t>(*v);
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
            if (!v || *v <= 0) return bad(key, value, "give a positive f-number, e.g. 1.8");
            c.lens.fNumber = *v;
        } else if (key == "pitch") {
            auto m = length(value);
            if (!m) return bad(key, value, "give the sensor pixel pitch with a unit, e.g. 1.4um");
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
    if (c.format == PixelFormat::YUYV && c.size.width % 2)
        return makeError(ErrorKind::Usage, "sim: format=YUYV needs an even width");
    return c;
}

}  // namespace infocus
