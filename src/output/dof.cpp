// SPDX-License-Identifier: MIT
// A depth-of-field answer as JSON, and as text for people.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "infocus/dof_output.h"
#include "print.h"

namespace infocus {

namespace {

using Json = nlohmann::ordered_json;
using output::print;

// JSON has no infinity: an infinite distance is null, as docs/design.md specifies for far_m.
Json metres(double v) {
    return std::isfinite(v) ? Json(v) : Json(nullptr);
}

std::string lensLine(const optics::ThinLens& lens) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%g mm f/%.3g", lens.focalLength * 1e3, lens.fNumber);
    return buf;
}

}  // namespace

std::string dofJson(const optics::DofResult& r, const optics::DofInput& in,
                    std::string_view cocSource, const std::optional<DofWanted>& wanted) {
    Json j;
    j["from"] = optics::distanceOriginName(in.from);
    j["focal_length_m"] = in.lens.focalLength;
    j["f_number"] = in.lens.fNumber;
    j["focus_m"] = metres(r.focusDistance);
    j["focus_from_lens_m"] = metres(r.focusFromLens);
    j["sensor_distance_m"] = r.sensorDistance;
    j["magnification"] = r.magnification;
    j["coc_um"] = in.coc * 1e6;
    j["coc_source"] = cocSource;
    j["hyperfocal_m"] = r.hyperfocal;
    j["hyperfocal_simple_m"] = r.hyperfocalSimple;
    j["hyperfocal_near_m"] = r.hyperfocalNear;
    j["near_m"] = metres(r.exact.nearLimit);
    j["far_m"] = metres(r.exact.farLimit);
    j["total_m"] = metres(r.exact.total());
    j["front_m"] = metres(r.frontDepth);
    j["rear_m"] = metres(r.rearDepth);
    j["approx_near_m"] = metres(r.approximate.nearLimit);
    j["approx_far_m"] = metres(r.approximate.farLimit);
    j["wavelength_um"] = in.wavelength * 1e6;
    j["airy_um"] = r.airyDisc * 1e6;
    j["diffraction_limited"] = r.diffractionLimited;
    j["diffraction_near_m"] = r.withDiffraction ? metres(r.withDiffraction->nearLimit) : Json();
    j["diffraction_far_m"] = r.withDiffraction ? metres(r.withDiffraction->farLimit) : Json();
    if (wanted) {
        j["wanted_near_m"] = metres(wanted->nearDistance);
        j["wanted_far_m"] = metres(wanted->farDistance);
    }
    return j.dump();
}

void writeDofText(std::ostream& out, const optics::DofResult& r, const optics::DofInput& in,
                  std::string_view cocSource, const std::optional<DofWanted>& wanted) {
    if (wanted)
        print(out, "For sharpness from %s to %s: focus at %s and stop down to f/%.3g\n\n",
              formatDistance(wanted->nearDistance).c_str(),
              formatDistance(wanted->farDistance).c_str(), formatDistance(in.focusDistance).c_str(),
              in.lens.fNumber);
    const std::string origin = in.from == optics::DistanceOrigin::Sensor ? "sensor" : "lens";
    print(out, "%s focused at %s (distances from the %s)\n", lensLine(in.lens).c_str(),
          formatDistance(r.focusDistance).c_str(), origin.c_str());
    print(out, "circle of confusion %s (%.*s)\n\n", formatSensorLength(in.coc).c_str(),
          static_cast<int>(cocSource.size()), cocSource.data());
    print(out, "  near limit        %s\n", formatDistance(r.exact.nearLimit).c_str());
    print(out, "  far limit         %s\n", formatDistance(r.exact.farLimit).c_str());
    print(out, "  depth of field    %s", formatDistance(r.exact.total()).c_str());
    print(out, "  (%s in front, %s behind)\n", formatDistance(r.frontDepth).c_str(),
          formatDistance(r.rearDepth).c_str());
    print(out, "  hyperfocal        %s  (focus there: sharp from %s to infinity)\n",
          formatDistance(r.hyperfocal).c_str(), formatDistance(r.hyperfocalNear).c_str());
    out << "\n  exact thin-lens limits; H = f²/(Nc) + f. Common approximations:\n";
    print(out, "  H' = f²/(Nc)      %s\n", formatDistance(r.hyperfocalSimple).c_str());
    print(out, "  near ≈ H'u/(H'+u) %s\n", formatDistance(r.approximate.nearLimit).c_str());
    print(out, "  far  ≈ H'u/(H'−u) %s\n", formatDistance(r.approximate.farLimit).c_str());
    const double airyInCoc = r.airyDisc / in.coc;
    char ratio[32];  // two decimals; past 1000 an exponent (f/1e300 gave 300 digits)
    std::snprintf(ratio, sizeof ratio, airyInCoc < 1e3 ? "%.2f" : "%.3g", airyInCoc);
    print(out, "\n  diffraction       Airy disc %s at %g nm (2.44 λN), %s × the CoC\n",
          formatSensorLength(r.airyDisc).c_str(), in.wavelength * 1e9, ratio);
    if (r.withDiffraction)
        print(out, "  with diffraction  %s to %s  (defocus² + Airy² ≤ CoC²)\n",
              formatDistance(r.withDiffraction->nearLimit).c_str(),
              formatDistance(r.withDiffraction->farLimit).c_str());
    if (r.diffractionLimited)
        print(out,
              "  warning: at f/%g the Airy disc is larger than the circle of confusion: "
              "nothing is sharp to this standard; open the aperture\n",
              in.lens.fNumber);
}

}  // namespace infocus
