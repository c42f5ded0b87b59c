// SPDX-License-Identifier: MIT
// The `infocus analyze` JSONL record (docs/design.md, analyze JSONL): writing and reading it back.
#include <cmath>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "infocus/analysis_output.h"
#include "json_fields.h"
#include "src/core/read_number.h"

namespace infocus {

namespace {

using Json = nlohmann::ordered_json;

Json optionalNumber(const std::optional<double>& v) {
    return v ? Json(*v) : Json(nullptr);
}

}  // namespace

std::string toJsonLine(const FrameAnalysis& a) {
    Json j;
    j["frame"] = a.frame;
    j["timestamp_ns"] = a.timestampNs;
    // A position that is not a number is not known: JSON has no NaN, and an object holding null
    // would be refused when the line is read back.
    if (a.lens && std::isfinite(a.lens->value)) {
        Json lens;
        lens["value"] = a.lens->value;
        lens["unit"] = a.lens->unit;
        if (a.lens->dioptres && std::isfinite(*a.lens->dioptres))
            lens["dioptres"] = *a.lens->dioptres;
        j["lens_position"] = lens;
    } else {
        j["lens_position"] = nullptr;
    }
    j["width"] = a.width;
    j["height"] = a.height;
    if (!a.metric.empty()) j["metric"] = a.metric;
    if (a.noiseSigma) {
        j["noise_sigma"] = *a.noiseSigma;
    } else if (!a.noiseReason.empty()) {
        j["noise_sigma"] = nullptr;
        j["noise_reason"] = a.noiseReason;
    }
    // A frame without an Ok region has no score (docs/design.md).
    if (a.regions.empty() || hasMeasurableRegion(a))
        j["frame_sharpness"] = a.frameSharpness;
    else
        j["frame_sharpness"] = nullptr;
    Json regions = Json::array();
    for (const auto& r : a.regions) {
        Json o;
        output::putRegionPlace(o, r.col, r.row, r.rect);
        const bool ok = r.status == RegionStatus::Ok;
        o["sharpness"] = ok ? Json(r.sharpness) : Json(nullptr);
        o["edge_width_px"] = optionalNumber(ok ? r.edgeWidthPx : std::nullopt);
        o["blur_sigma_px"] = optionalNumber(ok ? r.blurSigmaPx : std::nullopt);
        o["blur_width_px"] = optionalNumber(ok ? r.blurWidthPx : std::nullopt);
        o["mtf50_cy_px"] = optionalNumber(ok ? r.mtf50CyPx : std::nullopt);
        o["mtf50p_cy_px"] = optionalNumber(ok ? r.mtf50pCyPx : std::nullopt);
        o["confidence"] = ok ? r.confidence : 0.0;
        o["status"] = regionStatusName(r.status);
        if (!ok) o["reason"] = r.statusReason;
        regions.push_back(std::move(o));
    }
    j["regions"] = std::move(regions);
    return j.dump();
}

namespace {

// A field of a record that is of the right JSON type but not a value analyze writes (a negative
// width, a confidence of 7): named by parseJsonLine with the others.
struct BadField {
    std::string why;
};

// The integer @p key of @p o within [@p lo, @p hi] (jsonInteger), or BadField naming it.
int64_t integer(const Json& o, const char* key, int64_t lo, int64_t hi) {
    const Json& v = o.at(key);
    if (const auto x = jsonInteger(v, lo, hi)) return *x;
    // Appended piece by piece: GCC 12 warns (-Wrestrict) on a chain of + here.
    std::string why = "\"";
    why += key;
    why += "\" must be a whole number from ";
    why += std::to_string(lo);
    why += " to ";
    why += std::to_string(hi);
    why += " (it is ";
    why += v.dump();
    why += ")";
    throw BadField{why};
}

// @p key in quotes, as the record spells it (appended piece by piece: GCC 12 warns on a chain).
std::string quoted(const char* key) {
    std::string q = "\"";
    q += key;
    q += "\"";
    return q;
}

// @p v of the wrong JSON type for @p field, which must be @p want ("a number"): a BadField
// naming both, where nlohmann would say "type must be number, but is null" and no more.
[[noreturn]] void wrongType(const std::string& field, const char* want, const Json& v) {
    std::string why = field;
    why += " must be ";
    why += want;
    why += " (it is ";
    why += v.dump();
    why += ")";
    throw BadField{why};
}

// The value of @p key in @p o, which must be there and be of type @p is (want in words).
const Json& typed(const Json& o, const char* key, bool (Json::*is)() const noexcept,
                  const char* want) {
    const Json& v = o.at(key);
    if (!(v.*is)()) wrongType(quoted(key), want, v);
    return v;
}

// The number @p key of @p o within [@p lo, @p hi], or empty when absent or null.
std::optional<double> number(const Json& o, const char* key, double lo, double hi) {
    if (!o.contains(key) || o[key].is_null()) return std::nullopt;
    if (!o[key].is_number()) wrongType(quoted(key), "a number or null", o[key]);
    const double v = o[key].get<double>();
    if (v >= lo && v <= hi) return v;
    std::string why = "\"";
    why += key;
    why += "\" must be ";
    why += Json(lo).dump();
    why += hi == std::numeric_limits<double>::max() ? std::string(" or more")
                                                    : " to " + Json(hi).dump();
    why += " (it is ";
    why += o[key].dump();
    why += ")";
    throw BadField{why};
}

}  // namespace

Result<FrameAnalysis> parseJsonLine(std::string_view line) {
    const auto fail = [](const std::string& why) {
        return makeError(ErrorKind::Corrupt,
                         "analysis record: " + why +
                             "; expected one JSON object per line as written by 'infocus analyze'");
    };
    const Json j = Json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.is_object()) return fail("not a JSON object");
    constexpr int64_t kIntMax = std::numeric_limits<int>::max();
    constexpr double kHuge = std::numeric_limits<double>::max();
    size_t region = 0;  // the region being read, 1-based; 0 while the frame's fields are read
    // A failure, named by the region being read (if any).
    const auto failHere = [&](const std::string& why) {
        return fail((region ? "region " + std::to_string(region) + ": " : std::string()) + why);
    };
    try {
        FrameAnalysis a;
        a.frame = static_cast<uint64_t>(integer(j, "frame", 0, INT64_MAX));
        a.timestampNs = j.contains("timestamp_ns")
                            ? integer(j, "timestamp_ns", INT64_MIN, INT64_MAX)
                            : int64_t{0};
        a.width = static_cast<int>(integer(j, "width", 1, kIntMax));
        a.height = static_cast<int>(integer(j, "height", 1, kIntMax));
        if (j.contains("metric"))
            a.metric = typed(j, "metric", &Json::is_string, "a string").get<std::string>();
        if (j.contains("frame_sharpness") && !j["frame_sharpness"].is_null())
            a.frameSharpness =
                typed(j, "frame_sharpness", &Json::is_number, "a number").get<double>();
        if (j.contains("noise_sigma") && j["noise_sigma"].is_number())
            a.noiseSigma = j["noise_sigma"].get<double>();
        if (j.contains("noise_reason"))
            a.noiseReason =
                typed(j, "noise_reason", &Json::is_string, "a string").get<std::string>();
        if (j.contains("lens_position") && j["lens_position"].is_object()) {
            const Json& l = j["lens_position"];
            LensPosition p;
            // A position the camera could not read (NaN) is written as null: say which field.
            const Json& value = l.at("value");
            if (value.is_null())
                throw BadField{
                    "\"lens_position\" \"value\" is null: the lens position of the "
                    "frame was not known; give frames whose lens position was read"};
            if (!value.is_number()) wrongType("\"lens_position\" \"value\"", "a number", value);
            p.value = value.get<double>();
            p.unit = typed(l, "unit", &Json::is_string, "a string").get<std::string>();
            if (l.contains("dioptres") && l["dioptres"].is_number())
                p.dioptres = l["dioptres"].get<double>();
            a.lens = p;
        }
        // A number or an object iterates too (as itself or its values): check the shape first.
        const Json& regions = typed(j, "regions", &Json::is_array, "an array of regions");
        for (const Json& o : regions) {
            ++region;
            if (!o.is_object()) wrongType("the region", "an object", o);
            RegionResult r;
            r.col = static_cast<int>(integer(o, "col", 0, kIntMax));
            r.row = static_cast<int>(integer(o, "row", 0, kIntMax));
            r.rect = {static_cast<int>(integer(o, "x", 0, kIntMax)),
                      static_cast<int>(integer(o, "y", 0, kIntMax)),
                      static_cast<int>(integer(o, "w", 1, kIntMax)),
                      static_cast<int>(integer(o, "h", 1, kIntMax))};
            if (o.contains("status")) {
                const std::string st =
                    typed(o, "status", &Json::is_string, "a string").get<std::string>();
                if (st == "dark")
                    r.status = RegionStatus::Dark;
                else if (st == "clipped")
                    r.status = RegionStatus::Clipped;
                else if (st != "ok")
                    throw BadField{"\"status\" is \"" + st +
                                   "\"; analyze writes \"ok\", \"dark\" or \"clipped\""};
                if (o.contains("reason"))
                    r.statusReason =
                        typed(o, "reason", &Json::is_string, "a string").get<std::string>();
            }
            // A region that could not be measured has no score.
            if (r.status == RegionStatus::Ok || !o.at("sharpness").is_null())
                r.sharpness = typed(o, "sharpness", &Json::is_number, "a number").get<double>();
            // Widths are lengths: a negative one is no blur analyze measures.
            r.edgeWidthPx = number(o, "edge_width_px", 0.0, kHuge);
            r.blurSigmaPx = number(o, "blur_sigma_px", 0.0, kHuge);
            r.blurWidthPx = number(o, "blur_width_px", 0.0, kHuge);
            // Written since the SFR was measured: older records lack them.
            if (o.contains("mtf50_cy_px")) r.mtf50CyPx = number(o, "mtf50_cy_px", 0.0, kHuge);
            if (o.contains("mtf50p_cy_px")) r.mtf50pCyPx = number(o, "mtf50p_cy_px", 0.0, kHuge);
            r.confidence = number(o, "confidence", 0.0, 1.0).value_or(0.0);
            a.regions.push_back(r);
        }
        return a;
    } catch (const BadField& e) {
        return failHere(e.why);
    } catch (const nlohmann::json::exception& e) {
        // nlohmann names the missing key or the type mismatch, after a tag for programmers
        // ("[json.exception.out_of_range.403] ") that a reader of the message does not need.
        const std::string what = e.what();
        const size_t tag = what.rfind("] ", what.find(' '));
        return failHere(tag == std::string::npos ? what : what.substr(tag + 2));
    }
}

}  // namespace infocus
