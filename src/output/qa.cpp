// SPDX-License-Identifier: MIT
// The verdicts of `infocus check` for people (a table), for programs (JSON) and for CI servers
// (JUnit XML), and the through-focus results of `stack --mtf` (docs/qa.md).
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "infocus/qa.h"

namespace infocus::qa {

namespace {

using Json = nlohmann::ordered_json;

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}

std::string withUnit(double v, const std::string& unit) {
    return unit.empty() ? num(v) : num(v) + " " + unit;
}

Json orNull(const std::optional<double>& v) {
    return v && std::isfinite(*v) ? Json(*v) : Json(nullptr);
}

// XML text with its five special characters escaped.
std::string xml(const std::string& s) {
    std::string out;
    for (char c : s) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            case '\'':
                out += "&apos;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

std::string frameName(const Verdict& v, size_t count) {
    return count == 1 && v.frame == 0 ? std::string("frame 0") : "frame " + std::to_string(v.frame);
}

}  // namespace

std::string verdictTable(const std::vector<Verdict>& verdicts, const std::string& source) {
    std::ostringstream out;
    int passed = 0;
    for (const Verdict& v : verdicts) {
        passed += v.pass;
        out << frameName(v, verdicts.size()) << " of " << source << ": "
            << (v.pass ? "PASS" : "FAIL");
        if (!v.reason.empty()) out << " (" << v.reason << ")";
        out << "\n";
        char line[256];
        std::snprintf(line, sizeof line, "  %-22s %16s %18s  %s\n", "criterion", "measured",
                      "limit", "result");
        out << line;
        for (const Criterion& c : v.criteria) {
            const std::string measured = c.measured ? withUnit(*c.measured, c.unit) : "-";
            const std::string limit = (c.isMinimum ? ">= " : "<= ") + withUnit(c.limit, c.unit);
            std::snprintf(line, sizeof line, "  %-22s %16s %18s  %s", c.name.c_str(),
                          measured.c_str(), limit.c_str(), c.pass ? "pass" : "FAIL");
            out << line;
            if (!c.pass && !c.reason.empty()) out << " (" << c.reason << ")";
            out << "\n";
        }
    }
    if (verdicts.size() > 1)
        out << "summary: " << passed << " of " << verdicts.size()
            << " frames passed: " << (passed == static_cast<int>(verdicts.size()) ? "PASS" : "FAIL")
            << "\n";
    return out.str();
}

std::string verdictJson(const std::vector<Verdict>& verdicts, const std::string& source) {
    Json j;
    j["source"] = source;
    int passed = 0;
    Json frames = Json::array();
    for (const Verdict& v : verdicts) {
        passed += v.pass;
        Json f;
        f["frame"] = v.frame;
        f["pass"] = v.pass ? 1 : 0;
        f["reason"] = v.reason.empty() ? Json(nullptr) : Json(v.reason);
        Json cs = Json::array();
        for (const Criterion& c : v.criteria)
            cs.push_back({{"name", c.name},
                          {"unit", c.unit},
                          {"kind", c.isMinimum ? "min" : "max"},
                          {"limit", c.limit},
                          {"measured", orNull(c.measured)},
                          {"pass", c.pass ? 1 : 0},
                          {"reason", c.reason.empty() ? Json(nullptr) : Json(c.reason)}});
        f["criteria"] = std::move(cs);
        Json rs = Json::array();
        for (const RegionVerdict& r : v.regions)
            rs.push_back({{"x", r.rect.x},
                          {"y", r.rect.y},
                          {"w", r.rect.w},
                          {"h", r.rect.h},
                          {"zone", std::string(zoneName(r.zone))},
                          {"mtf50_cy_px", orNull(r.mtf50CyPx)},
                          {"pass", r.pass ? 1 : 0}});
        f["regions"] = std::move(rs);
        frames.push_back(std::move(f));
    }
    j["frames"] = std::move(frames);
    j["frames_passed"] = passed;
    j["frames_failed"] = static_cast<int>(verdicts.size()) - passed;
    j["pass"] = !verdicts.empty() && passed == static_cast<int>(verdicts.size()) ? 1 : 0;
    return j.dump();
}

std::string verdictJunit(const std::vector<Verdict>& verdicts, const std::string& source) {
    int tests = 0, failures = 0;
    std::ostringstream cases;
    for (const Verdict& v : verdicts) {
        const std::string cls = "infocus.check." + xml(frameName(v, verdicts.size()));
        // A frame that no criterion can judge (too dark, no edge) is a failing case of its own.
        if (!v.reason.empty()) {
            ++tests, ++failures;
            cases << "    <testcase classname=\"" << cls << "\" name=\"measurable\">\n"
                  << "      <failure message=\"" << xml(v.reason) << "\"/>\n    </testcase>\n";
        }
        for (const Criterion& c : v.criteria) {
            ++tests;
            cases << "    <testcase classname=\"" << cls << "\" name=\"" << xml(c.name)
                  << (c.unit.empty() ? "" : " (" + xml(c.unit) + ")") << "\">";
            const std::string text =
                (c.measured ? "measured " + withUnit(*c.measured, c.unit) : "not measured") +
                ", limit " + (c.isMinimum ? ">= " : "<= ") + withUnit(c.limit, c.unit);
            if (!c.pass) {
                ++failures;
                cases << "\n      <failure message=\"" << xml(text)
                      << (c.reason.empty() ? "" : ": " + xml(c.reason)) << "\"/>\n    ";
            } else {
                cases << "<system-out>" << xml(text) << "</system-out>";
            }
            cases << "</testcase>\n";
        }
    }
    std::ostringstream out;
    out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        << "<testsuites tests=\"" << tests << "\" failures=\"" << failures << "\">\n"
        << "  <testsuite name=\"infocus check " << xml(source) << "\" tests=\"" << tests
        << "\" failures=\"" << failures << "\" errors=\"0\">\n"
        << cases.str() << "  </testsuite>\n</testsuites>\n";
    return out.str();
}

std::string throughFocusTable(const ThroughFocus& tf) {
    std::ostringstream out;
    char line[256];
    out << "MTF50 through focus (axis: " << tf.axisUnit << "), best focus and depth of focus "
        << "per region\n";
    std::snprintf(line, sizeof line, "  %4s %4s %-8s %12s %10s %24s\n", "col", "row", "zone",
                  "best", "MTF50", "depth of focus");
    out << line;
    for (const RegionFocus& r : tf.regions) {
        if (!r.bestPosition) {
            std::snprintf(line, sizeof line, "  %4d %4d %-8s %12s\n", r.col, r.row,
                          std::string(zoneName(r.zone)).c_str(), "-");
            out << line;
            continue;
        }
        std::string dof = "-";
        if (r.dofLow) dof = num(*r.dofLow) + " .. " + num(*r.dofHigh);
        std::snprintf(line, sizeof line, "  %4d %4d %-8s %12.5g %10.4f %24s  (>= %.3f cy/px)\n",
                      r.col, r.row, std::string(zoneName(r.zone)).c_str(), *r.bestPosition,
                      *r.bestMtf50, dof.c_str(), r.thresholdCyPx);
        out << line;
    }
    out << "regions with a peak: " << tf.regionsWithPeak << " of " << tf.regions.size() << "\n";
    if (tf.tiltAcross) {
        out << "tilt across the frame: " << num(*tf.tiltAcross) << " " << tf.axisUnit;
        if (tf.tiltAcrossUm) out << " (" << num(*tf.tiltAcrossUm) << " µm)";
        out << ", rising towards " << num(*tf.tiltDirectionDeg) << "° (from +x towards +y)\n";
        out << "field curvature (corner minus centre): " << num(*tf.fieldCurvature) << " "
            << tf.axisUnit;
        if (tf.fieldCurvatureUm) out << " (" << num(*tf.fieldCurvatureUm) << " µm)";
        out << "\n";
    } else {
        out << "tilt and field curvature: too few regions with a peak (6 needed)\n";
    }
    return out.str();
}

std::string throughFocusJson(const ThroughFocus& tf) {
    Json j;
    j["axis_unit"] = tf.axisUnit;
    j["axis"] = tf.axis;
    Json rs = Json::array();
    for (const RegionFocus& r : tf.regions) {
        Json m = Json::array();
        for (const auto& v : r.mtf50)
            m.push_back(orNull(v));
        rs.push_back({{"col", r.col},
                      {"row", r.row},
                      {"zone", std::string(zoneName(r.zone))},
                      {"mtf50_cy_px", std::move(m)},
                      {"best_position", orNull(r.bestPosition)},
                      {"best_mtf50_cy_px", orNull(r.bestMtf50)},
                      {"dof_threshold_cy_px", r.bestPosition ? Json(r.thresholdCyPx) : Json()},
                      {"dof_low", orNull(r.dofLow)},
                      {"dof_high", orNull(r.dofHigh)}});
    }
    j["regions"] = std::move(rs);
    j["regions_with_peak"] = tf.regionsWithPeak;
    j["tilt_across"] = orNull(tf.tiltAcross);
    j["tilt_across_um"] = orNull(tf.tiltAcrossUm);
    j["tilt_direction_deg"] = orNull(tf.tiltDirectionDeg);
    j["field_curvature"] = orNull(tf.fieldCurvature);
    j["field_curvature_um"] = orNull(tf.fieldCurvatureUm);
    return j.dump();
}

}  // namespace infocus::qa
