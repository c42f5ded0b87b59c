// SPDX-License-Identifier: MIT
// The `infocus analyze` JSONL record (docs/design.md, analyze JSONL): writing and reading it back.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "infocus/output.h"
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
    if (a.lens) {
        Json lens;
        lens["value"] = a.lens->value;
        lens["unit"] = a.lens->unit;
        if (a.lens->dioptres) lens["dioptres"] = *a.lens->dioptres;
        j["lens_position"] = lens;
    } else {
        j["lens_position"] = nullptr;
    }
    j["width"] = a.width;
    j["height"] = a.height;
    if (!a.metric.empty()) j["metric"] = a.metric;
    if (a.noiseSigma) j["noise_sigma"] = *a.noiseSigma;
    j["frame_sharpness"] = a.frameSharpness;
    Json regions = Json::array();
    for (const auto& r : a.regions) {
        Json o;
        o["col"] = r.col;
        o["row"] = r.row;
        o["x"] = r.rect.x;
        o["y"] = r.rect.y;
        o["w"] = r.rect.w;
        o["h"] = r.rect.h;
        o["sharpness"] = r.sharpness;
        o["edge_width_px"] = optionalNumber(r.edgeWidthPx);
        o["blur_sigma_px"] = optionalNumber(r.blurSigmaPx);
        o["blur_width_px"] = optionalNumber(r.blurWidthPx);
        o["confidence"] = r.confidence;
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

// The number @p key of @p o within [@p lo, @p hi], or empty when absent or null.
std::optional<double> number(const Json& o, const char* key, double lo, double hi) {
    if (!o.contains(key) || o[key].is_null()) return std::nullopt;
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
        a.metric = j.value("metric", std::string());
        a.frameSharpness = j.value("frame_sharpness", 0.0);
        if (j.contains("noise_sigma") && j["noise_sigma"].is_number())
            a.noiseSigma = j["noise_sigma"].get<double>();
        if (j.contains("lens_position") && j["lens_position"].is_object()) {
            const Json& l = j["lens_position"];
            LensPosition p;
            p.value = l.at("value").get<double>();
            p.unit = l.at("unit").get<std::string>();
            if (l.contains("dioptres") && l["dioptres"].is_number())
                p.dioptres = l["dioptres"].get<double>();
            a.lens = p;
        }
        for (const Json& o : j.at("regions")) {
            ++region;
            RegionResult r;
            r.col = static_cast<int>(integer(o, "col", 0, kIntMax));
            r.row = static_cast<int>(integer(o, "row", 0, kIntMax));
            r.rect = {static_cast<int>(integer(o, "x", 0, kIntMax)),
                      static_cast<int>(integer(o, "y", 0, kIntMax)),
                      static_cast<int>(integer(o, "w", 1, kIntMax)),
                      static_cast<int>(integer(o, "h", 1, kIntMax))};
            r.sharpness = o.at("sharpness").get<double>();
            // Widths are lengths: a negative one is no blur analyze measures.
            r.edgeWidthPx = number(o, "edge_width_px", 0.0, kHuge);
            r.blurSigmaPx = number(o, "blur_sigma_px", 0.0, kHuge);
            r.blurWidthPx = number(o, "blur_width_px", 0.0, kHuge);
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
