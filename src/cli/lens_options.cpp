// SPDX-License-Identifier: MIT
// Parsing of the shared lens options: lengths with units, focus as distance or dioptres, presets.
#include "lens_options.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>

#include "infocus/dof.h"
#include "infocus/lens_presets.h"
#include "infocus/optics.h"
#include "src/core/read_number.h"

namespace infocus::cli {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())))
        s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())))
        s.remove_suffix(1);
    return s;
}

// Splits "50mm" into 50 and "mm"; no value when the text does not start with a number.
std::optional<std::pair<double, std::string>> splitNumber(std::string_view text) {
    text = trim(text);
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || !std::isfinite(v)) return std::nullopt;
    const std::string_view rest = trim(std::string_view(ptr, text.data() + text.size() - ptr));
    return std::pair{v, lower(rest)};
}

Error usage(std::string message) {
    return makeError(ErrorKind::Usage, std::move(message));
}

std::string quoted(std::string_view option, std::string_view text) {
    return std::string(option) + " " + std::string(text);
}

std::string listLenses() {
    std::string names;
    for (const auto& l : optics::lensPresets())
        names += (names.empty() ? "" : ", ") + std::string(l.name);
    return names;
}

std::string listSensors() {
    std::string names;
    for (const auto& s : optics::sensorPresets())
        names += (names.empty() ? "" : ", ") + std::string(s.name);
    return names;
}

}  // namespace

Result<double> parseLength(std::string_view text, std::string_view option) {
    const auto parts = splitNumber(text);
    if (!parts)
        return usage(quoted(option, text) + ": not a length; give a number with a unit, e.g. " +
                     std::string(option) + " 50mm");
    const auto& [v, unit] = *parts;
    if (unit.empty())
        return usage(quoted(option, text) + ": give a unit, e.g. " + std::string(option) + " " +
                     std::string(trim(text)) + "mm (units: " + std::string(kLengthUnitNames) + ")");
    if (const auto scale = metresPerUnit(unit)) return v * *scale;
    return usage(quoted(option, text) + ": unknown unit '" + unit + "'; use " +
                 std::string(kLengthUnitNames) + ", e.g. " + std::string(option) + " 50mm");
}

Result<double> parseFocus(std::string_view text, std::string_view option) {
    const std::string t = lower(trim(text));
    if (t == "inf" || t == "infinity" || t == "∞") return kInf;
    const auto parts = splitNumber(text);
    if (parts && (parts->second == "dpt" || parts->second == "d" || parts->second == "dioptre" ||
                  parts->second == "dioptres" || parts->second == "diopter" ||
                  parts->second == "diopters")) {
        const double dpt = parts->first;
        if (dpt < 0.0)
            return usage(quoted(option, text) + ": dioptres must be 0 (infinity) or more, e.g. " +
                         std::string(option) + " 0.4dpt (focus at 2.5 m)");
        return optics::distanceFromDioptres(dpt);
    }
    if (parts && parts->second.empty())
        return usage(quoted(option, text) + ": give a unit, e.g. " + std::string(option) + " " +
                     std::string(trim(text)) + "m, or dioptres as " + std::string(option) + " " +
                     std::string(trim(text)) + "dpt");
    auto d = parseLength(text, option);
    if (!d) return d;
    if (!(*d > 0.0))
        return usage(quoted(option, text) + ": the focus distance must be positive, e.g. " +
                     std::string(option) + " 2.5m");
    return d;
}

Result<double> parseFNumber(std::string_view text, std::string_view option) {
    std::string_view t = trim(text);
    if (!t.empty() && (t.front() == 'f' || t.front() == 'F')) {
        t.remove_prefix(1);
        if (!t.empty() && t.front() == '/') t.remove_prefix(1);
    }
    const auto parts = splitNumber(t);
    if (!parts || !parts->second.empty())
        return usage(quoted(option, text) + ": not an f-number; write it as " +
                     std::string(option) + " 8 or " + std::string(option) + " f/8");
    if (!(parts->first > 0.0))
        return usage(quoted(option, text) + ": the f-number must be positive, e.g. " +
                     std::string(option) + " 2.8");
    return parts->first;
}

void LensOptions::add(CLI::App* app, LensOptionSet set) {
    CLI::Option_group* lens = app->add_option_group("Lens");
    lens->add_option("--focal", focal_, "Focal length, e.g. 50mm")->type_name("LENGTH");
    lens->add_option("--fnumber,-N", fNumber_, "Aperture as an f-number, e.g. 8 or f/8")
        ->type_name("N");
    lens->add_option("--focus", focus_, "Focus distance: 2.5m, 0.4dpt (dioptres) or inf")
        ->type_name("DIST");
    if (set.pitch)
        lens->add_option("--pixel-pitch", pitch_, "Pixel size, e.g. 1.4um")->type_name("LENGTH");
    lens->add_option(
            "--lens", lens_,
            "Camera preset for focal length, f-number, pixel size and sensor: " + listLenses())
        ->type_name("PRESET");
    if (set.coc) {
        CLI::Option_group* coc = app->add_option_group(
            "Circle of confusion", "One of these; default: full frame, 0.029 mm (diagonal/1500)");
        coc->add_option("--coc", coc_, "Largest blur that still looks sharp, e.g. 0.03mm")
            ->type_name("LENGTH");
        coc->add_option("--sensor", sensor_, "The sensor's diagonal/1500: " + listSensors())
            ->type_name("NAME");
        coc->add_option("--coc-px", cocPx_, "In pixels, with --pixel-pitch or --lens, e.g. 2")
            ->type_name("PIXELS");
    }
}

Result<LensValues> LensOptions::resolve() const {
    LensValues v;
    if (!lens_.empty()) {
        v.preset = optics::findLensPreset(lens_);
        if (!v.preset) return usage("--lens " + lens_ + ": unknown preset; choose " + listLenses());
        v.focalLength = v.preset->focalLength;
        v.fNumber = v.preset->fNumber;
        if (v.preset->pixelPitch > 0.0) v.pixelPitch = v.preset->pixelPitch;
    }
    if (!focal_.empty()) {
        auto f = parseLength(focal_, "--focal");
        if (!f) return f.error();
        if (!(*f > 0.0))
            return usage("--focal " + focal_ +
                         ": the focal length must be positive, e.g. --focal 50mm");
        v.focalLength = *f;
    }
    if (!fNumber_.empty()) {
        auto n = parseFNumber(fNumber_, "--fnumber");
        if (!n) return n.error();
        v.fNumber = *n;
    }
    if (!focus_.empty()) {
        auto u = parseFocus(focus_, "--focus");
        if (!u) return u.error();
        v.focusDistance = *u;
    }
    if (!pitch_.empty()) {
        auto p = parseLength(pitch_, "--pixel-pitch");
        if (!p) return p.error();
        if (!(*p > 0.0))
            return usage("--pixel-pitch " + pitch_ +
                         ": the pixel pitch must be positive, e.g. --pixel-pitch 1.4um");
        v.pixelPitch = *p;
    }
    const int cocChoices = !coc_.empty() + !sensor_.empty() + !cocPx_.empty();
    if (cocChoices > 1)
        return usage("give the circle of confusion one way: --coc, --sensor or --coc-px");
    if (!coc_.empty()) {
        auto c = parseLength(coc_, "--coc");
        if (!c) return c.error();
        if (!(*c > 0.0))
            return usage("--coc " + coc_ +
                         ": the circle of confusion must be positive, e.g. --coc 0.03mm");
        v.coc = *c;
        v.cocSource = "given";
    } else if (!sensor_.empty()) {
        const auto* s = optics::findSensorPreset(sensor_);
        if (!s) return usage("--sensor " + sensor_ + ": unknown sensor; choose " + listSensors());
        v.coc = s->coc();
        v.cocSource = std::string(s->name) + " diagonal/1500";
    } else if (!cocPx_.empty()) {
        const auto n = splitNumber(cocPx_);
        if (!n || !(n->second.empty() || n->second == "px") || !(n->first > 0.0))
            return usage("--coc-px " + cocPx_ +
                         ": give a positive number of pixels, e.g. --coc-px 2");
        if (!v.pixelPitch)
            return usage(
                "--coc-px needs the pixel size: add --pixel-pitch, e.g. --pixel-pitch 1.4um");
        v.coc = n->first * *v.pixelPitch;
        char buf[64];
        std::snprintf(buf, sizeof buf, "%g px of %g um", n->first, *v.pixelPitch * 1e6);
        v.cocSource = buf;
    } else if (v.preset) {
        const auto* s = optics::findSensorPreset(v.preset->sensor);
        if (s) {
            v.coc = s->coc();
            v.cocSource = std::string(s->name) + " diagonal/1500, from --lens";
        }
    }
    if (v.focalLength && v.focusDistance && *v.focusDistance <= *v.focalLength)
        return usage("--focus " + focus_ + " is at or inside the focal length (" +
                     formatDistance(*v.focalLength) +
                     "): no real image forms there; focus farther, e.g. --focus 1m");
    return v;
}

}  // namespace infocus::cli
