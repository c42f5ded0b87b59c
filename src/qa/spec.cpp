// SPDX-License-Identifier: MIT
// The spec file of `infocus check`: JSON whose every key is known, whose limits carry their unit
// in their name, and whose errors name the key and its line (docs/qa.md, "Spec").
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "infocus/qa.h"

namespace infocus::qa {

namespace {

using Json = nlohmann::json;

// A usage error in the spec, thrown inside parseSpec and turned into its Result there.
struct SpecError {
    std::string message;
};

// Where keys are in the text: nlohmann keeps no positions, so a key is found as "key" followed
// by a colon, after the position of the object that holds it.
class Locator {
public:
    explicit Locator(const std::string& text) : text_(text) {}
    // Offset of key @p key at or after @p from (npos when absent).
    size_t find(const std::string& key, size_t from) const {
        const std::string quoted = "\"" + key + "\"";
        for (size_t at = text_.find(quoted, from); at != std::string::npos;
             at = text_.find(quoted, at + 1)) {
            size_t k = at + quoted.size();
            while (k < text_.size() && std::isspace(static_cast<unsigned char>(text_[k])))
                ++k;
            if (k < text_.size() && text_[k] == ':') return at;
        }
        return std::string::npos;
    }
    // 1-based line of offset @p at.
    int line(size_t at) const {
        if (at == std::string::npos) return 0;
        return 1 + static_cast<int>(std::count(text_.begin(), text_.begin() + at, '\n'));
    }

private:
    const std::string& text_;
};

class Parser {
public:
    Parser(const std::string& text, const std::string& name) : loc_(text), name_(name) {}

    Spec parse(const Json& j) {
        if (!j.is_object()) fail("the spec is not a JSON object; write { \"key\": value, ... }", 0);
        Spec s;
        bool any = false;
        for (const auto& [key, v] : j.items()) {
            const size_t at = loc_.find(key, 0);
            if (key == "grid") {
                parseGrid(v, key, at, s);
            } else if (key == "min_confidence") {
                s.minConfidence = number(v, key, at, 0.0, 1.0, "a confidence from 0 to 1");
            } else if (key == "zones") {
                if (!v.is_object())
                    fail(keyText(key, at) + " is not an object; write {\"centre\": {...}}", at);
                for (const auto& [zone, limits] : v.items()) {
                    const size_t zat = loc_.find(zone, at);
                    int z = zone == "centre"    ? 0
                            : zone == "middle"  ? 1
                            : zone == "corners" ? 2
                                                : -1;
                    if (z < 0)
                        fail(
                            keyText(zone, zat) +
                                " is no zone; the zones are \"centre\", \"middle\" and \"corners\"",
                            zat);
                    s.zoneMin[z] = mtfObject(limits, zone, zat);
                    any = true;
                }
            } else if (key == "every_region") {
                s.everyRegionMin = mtfObject(v, key, at);
                any = true;
            } else if (key == "min_weighted_mtf50_cy_px" || key == "min_weighted_mtf50_lp_mm") {
                s.weightedMin = mtfValue(v, key, at);
                any = true;
            } else if (key == "min_corner_centre_ratio") {
                s.minCornerCentreRatio = number(v, key, at, 1e-9, 10.0, "a ratio above 0");
                any = true;
            } else if (key == "max_blur_width_px") {
                s.maxBlurWidthPx = number(v, key, at, 1e-9, 1e4, "a width in pixels above 0");
                any = true;
            } else if (key == "max_blur_width_um") {
                s.maxBlurWidthUm = number(v, key, at, 1e-9, 1e5, "a width in µm above 0");
                any = true;
            } else if (key == "max_tilt_deg") {
                s.maxTiltDeg = number(v, key, at, 1e-9, 89.9, "an angle above 0 and below 90");
                any = true;
            } else if (key == "max_tilt_um") {
                s.maxTiltUm = number(v, key, at, 1e-9, 1e5, "a length in µm above 0");
                any = true;
            } else if (key == "in_focus_distance_m") {
                parseRange(v, key, at, s);
                any = true;
            } else if (key == "min_confident_regions") {
                if (!v.is_number_integer() || v.get<long long>() < 1)
                    fail(keyText(key, at) + " is " + v.dump() + "; give a whole number from 1", at);
                s.minConfidentRegions = static_cast<int>(std::min(v.get<long long>(), 1LL << 20));
                any = true;
            } else if (key == "dof_threshold_mtf50_cy_px") {
                s.dofThresholdCyPx = cyPx(v, key, at);
            } else {
                fail(keyText(key, at) +
                         " is not a spec key; the keys are grid, min_confidence, zones, "
                         "every_region, min_weighted_mtf50_cy_px, min_weighted_mtf50_lp_mm, "
                         "min_corner_centre_ratio, max_blur_width_px, max_blur_width_um, "
                         "max_tilt_deg, max_tilt_um, in_focus_distance_m, "
                         "min_confident_regions, dof_threshold_mtf50_cy_px (docs/qa.md)",
                     at);
            }
        }
        if (!any)
            fail(
                "holds no limit; give at least one, e.g. \"zones\": {\"centre\": "
                "{\"min_mtf50_cy_px\": 0.25}}",
                0);
        return s;
    }

    [[noreturn]] void fail(const std::string& what, size_t at) const {
        const int line = loc_.line(at);
        throw SpecError{"spec " + name_ + (line > 0 ? " line " + std::to_string(line) : "") + ": " +
                        what};
    }

private:
    Locator loc_;
    std::string name_;

    static std::string keyText(const std::string& key, size_t) { return "\"" + key + "\""; }

    double number(const Json& v, const std::string& key, size_t at, double lo, double hi,
                  const std::string& want) const {
        if (!v.is_number()) fail(keyText(key, at) + " is " + v.dump() + "; give " + want, at);
        const double d = v.get<double>();
        if (!(d >= lo && d <= hi))
            fail(keyText(key, at) + " is " + v.dump() + "; give " + want, at);
        return d;
    }

    // MTF50 in cycles per pixel: above 0 and at most 1 (twice Nyquist). A value above 1 is most
    // likely lp/mm under the wrong key.
    double cyPx(const Json& v, const std::string& key, size_t at) const {
        if (v.is_number() && v.get<double>() > 1.0)
            fail(keyText(key, at) + " is " + v.dump() +
                     ", more than 1 cycle per pixel (Nyquist is 0.5); for line pairs per mm use "
                     "the key ending in _lp_mm",
                 at);
        return number(v, key, at, 1e-9, 1.0, "MTF50 in cycles per pixel, above 0 and at most 1");
    }

    MtfLimit mtfValue(const Json& v, const std::string& key, size_t at) const {
        MtfLimit m;
        if (key.ends_with("_cy_px"))
            m.cyPx = cyPx(v, key, at);
        else
            m.lpMm = number(v, key, at, 1e-9, 1e4, "MTF50 in line pairs per mm, above 0");
        return m;
    }

    MtfLimit mtfObject(const Json& v, const std::string& key, size_t at) const {
        if (!v.is_object() || v.size() != 1)
            fail(keyText(key, at) +
                     " must hold one limit, {\"min_mtf50_cy_px\": 0.25} or {\"min_mtf50_lp_mm\": "
                     "80}",
                 at);
        const auto& [k, value] = *v.items().begin();
        const size_t kat = loc_.find(k, at);
        if (k != "min_mtf50_cy_px" && k != "min_mtf50_lp_mm")
            fail(keyText(k, kat) + " is not a limit of " + keyText(key, at) +
                     "; use min_mtf50_cy_px or min_mtf50_lp_mm",
                 kat);
        return mtfValue(value, k, kat);
    }

    void parseGrid(const Json& v, const std::string& key, size_t at, Spec& s) const {
        int c = 0, r = 0;
        char x = 0, extra = 0;
        if (!v.is_string() ||
            std::sscanf(v.get<std::string>().c_str(), "%d%c%d%c", &c, &x, &r, &extra) != 3 ||
            (x != 'x' && x != 'X') || c < 1 || r < 1 || c > kMaxGridSide || r > kMaxGridSide)
            fail(keyText(key, at) + " is " + v.dump() + "; give columns x rows, " + gridLimitText(),
                 at);
        s.cols = c, s.rows = r;
    }

    void parseRange(const Json& v, const std::string& key, size_t at, Spec& s) const {
        if (!v.is_object() || v.empty())
            fail(keyText(key, at) + " must be {\"min\": 0.4, \"max\": 0.6} (metres)", at);
        for (const auto& [k, value] : v.items()) {
            const size_t kat = loc_.find(k, at);
            if (k != "min" && k != "max")
                fail(keyText(k, kat) + " is not part of " + keyText(key, at) +
                         "; use \"min\" and \"max\"",
                     kat);
            const double d = number(value, k, kat, 1e-6, 1e9, "a distance in metres above 0");
            (k == "min" ? s.minInFocusM : s.maxInFocusM) = d;
        }
        if (s.minInFocusM && s.maxInFocusM && *s.minInFocusM > *s.maxInFocusM)
            fail(keyText(key, at) + " has min above max; swap them", at);
    }
};

}  // namespace

std::optional<std::string> Spec::needsPixelPitch() const {
    for (int z = 0; z < 3; ++z)
        if (zoneMin[z] && zoneMin[z]->lpMm)
            return "zones." + std::string(zoneName(static_cast<Zone>(z))) + ".min_mtf50_lp_mm";
    if (everyRegionMin && everyRegionMin->lpMm) return "every_region.min_mtf50_lp_mm";
    if (weightedMin && weightedMin->lpMm) return "min_weighted_mtf50_lp_mm";
    if (maxBlurWidthUm) return "max_blur_width_um";
    if (maxTiltUm) return "max_tilt_um";
    return std::nullopt;
}

Result<Spec> parseSpec(const std::string& text, const std::string& name) {
    Parser p(text, name);
    Json j;
    try {
        j = Json::parse(text);
    } catch (const Json::parse_error& e) {
        const size_t at = e.byte > 0 ? e.byte - 1 : 0;
        const int line = 1 + static_cast<int>(std::count(
                                 text.begin(), text.begin() + std::min(at, text.size()), '\n'));
        std::string what = e.what();
        if (const size_t k = what.find("] "); k != std::string::npos) what = what.substr(k + 2);
        return makeError(ErrorKind::Usage, "spec " + name + " line " + std::to_string(line) +
                                               ": not valid JSON (" + what + ")");
    }
    try {
        return p.parse(j);
    } catch (const SpecError& e) {
        return makeError(ErrorKind::Usage, e.message);
    }
}

Result<Spec> readSpec(const std::string& path) {
    // A spec that cannot be read is the caller's to fix, like a bad option: a usage error.
    std::ifstream in(path, std::ios::binary);
    if (!in)
        return makeError(ErrorKind::Usage,
                         "cannot read the spec " + path + "; give the path of a JSON spec file");
    std::ostringstream text;
    text << in.rdbuf();
    return parseSpec(text.str(), path);
}

}  // namespace infocus::qa
