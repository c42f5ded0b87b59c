// SPDX-License-Identifier: MIT
// The `infocus analyze` JSONL record (DESIGN.md "analyze JSONL"): writing and reading it back.
#include <nlohmann/json.hpp>

#include "infocus/analysis.h"

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

Result<FrameAnalysis> parseJsonLine(std::string_view line) {
    const auto fail = [](const std::string& why) {
        return makeError(ErrorKind::Corrupt,
                         "analysis record: " + why +
                             "; expected one JSON object per line as written by 'infocus analyze'");
    };
    const Json j = Json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.is_object()) return fail("not a JSON object");
    try {
        FrameAnalysis a;
        a.frame = j.at("frame").get<uint64_t>();
        a.timestampNs = j.value("timestamp_ns", int64_t{0});
        a.width = j.at("width").get<int>();
        a.height = j.at("height").get<int>();
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
        const auto opt = [](const Json& o, const char* key) -> std::optional<double> {
            if (!o.contains(key) || o[key].is_null()) return std::nullopt;
            return o[key].get<double>();
        };
        for (const Json& o : j.at("regions")) {
            RegionResult r;
            r.col = o.at("col").get<int>();
            r.row = o.at("row").get<int>();
            r.rect = {o.at("x").get<int>(), o.at("y").get<int>(), o.at("w").get<int>(),
                      o.at("h").get<int>()};
            r.sharpness = o.at("sharpness").get<double>();
            r.edgeWidthPx = opt(o, "edge_width_px");
            r.blurSigmaPx = opt(o, "blur_sigma_px");
            r.blurWidthPx = opt(o, "blur_width_px");
            r.confidence = o.value("confidence", 0.0);
            a.regions.push_back(r);
        }
        return a;
    } catch (const nlohmann::json::exception& e) {
        // nlohmann names the missing key or the type mismatch, after a tag for programmers
        // ("[json.exception.out_of_range.403] ") that a reader of the message does not need.
        const std::string what = e.what();
        const size_t tag = what.rfind("] ", what.find(' '));
        return fail(tag == std::string::npos ? what : what.substr(tag + 2));
    }
}

}  // namespace infocus
