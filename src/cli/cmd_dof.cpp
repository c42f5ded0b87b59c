// SPDX-License-Identifier: MIT
// `infocus dof`: a depth-of-field calculator on the thin-lens model (and its inverse: the focus
// and f-number for a wanted near/far pair).
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "infocus/dof.h"
#include "lens_options.h"

namespace infocus::cli {

namespace {

constexpr const char* kName = "dof";

struct DofArgs {
    LensOptions lens;
    std::string from = "lens";
    std::string wavelength = "550nm";
    std::string nearText, farText;
    bool json = false;
};

using Json = nlohmann::ordered_json;

// JSON has no infinity: an infinite distance is null, as DESIGN.md specifies for far_m.
Json metres(double v) {
    return std::isfinite(v) ? Json(v) : Json(nullptr);
}

std::string lensLine(const optics::ThinLens& lens) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%g mm f/%.3g", lens.focalLength * 1e3, lens.fNumber);
    return buf;
}

Json resultJson(const optics::DofResult& r, const optics::DofInput& in,
                const std::string& cocSource) {
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
    return j;
}

void printTable(const optics::DofResult& r, const optics::DofInput& in,
                const std::string& cocSource) {
    const std::string origin = in.from == optics::DistanceOrigin::Sensor ? "sensor" : "lens";
    std::printf("%s focused at %s (distances from the %s)\n", lensLine(in.lens).c_str(),
                formatDistance(r.focusDistance).c_str(), origin.c_str());
    std::printf("circle of confusion %s (%s)\n\n", formatSensorLength(in.coc).c_str(),
                cocSource.c_str());
    std::printf("  near limit        %s\n", formatDistance(r.exact.nearLimit).c_str());
    std::printf("  far limit         %s\n", formatDistance(r.exact.farLimit).c_str());
    std::printf("  depth of field    %s", formatDistance(r.exact.total()).c_str());
    std::printf("  (%s in front, %s behind)\n", formatDistance(r.frontDepth).c_str(),
                formatDistance(r.rearDepth).c_str());
    std::printf("  hyperfocal        %s  (focus there: sharp from %s to infinity)\n",
                formatDistance(r.hyperfocal).c_str(), formatDistance(r.hyperfocalNear).c_str());
    std::printf("\n  exact thin-lens limits; H = f²/(Nc) + f. Common approximations:\n");
    std::printf("  H' = f²/(Nc)      %s\n", formatDistance(r.hyperfocalSimple).c_str());
    std::printf("  near ≈ H'u/(H'+u) %s\n", formatDistance(r.approximate.nearLimit).c_str());
    std::printf("  far  ≈ H'u/(H'−u) %s\n", formatDistance(r.approximate.farLimit).c_str());
    const double airyInCoc = r.airyDisc / in.coc;
    char ratio[32];  // two decimals; past 1000 an exponent (f/1e300 gave 300 digits)
    std::snprintf(ratio, sizeof ratio, airyInCoc < 1e3 ? "%.2f" : "%.3g", airyInCoc);
    std::printf("\n  diffraction       Airy disc %s at %g nm (2.44 λN), %s × the CoC\n",
                formatSensorLength(r.airyDisc).c_str(), in.wavelength * 1e9, ratio);
    if (r.withDiffraction)
        std::printf("  with diffraction  %s to %s  (defocus² + Airy² ≤ CoC²)\n",
                    formatDistance(r.withDiffraction->nearLimit).c_str(),
                    formatDistance(r.withDiffraction->farLimit).c_str());
    if (r.diffractionLimited)
        std::printf(
            "  warning: at f/%g the Airy disc is larger than the circle of confusion: "
            "nothing is sharp to this standard; open the aperture\n",
            in.lens.fNumber);
}

int runDof(const DofArgs& args) {
    auto lens = args.lens.resolve();
    if (!lens) return reportError(kName, lens.error());
    optics::DofInput in;
    if (args.from == "sensor")
        in.from = optics::DistanceOrigin::Sensor;
    else if (args.from != "lens")
        return usageError(kName, "--from " + args.from + ": choose --from lens or --from sensor");
    auto wavelength = parseLength(args.wavelength, "--wavelength");
    if (!wavelength) return reportError(kName, wavelength.error());
    if (!(*wavelength > 0.0))
        return usageError(kName, "--wavelength must be positive, e.g. --wavelength 550nm");
    in.wavelength = *wavelength;
    if (!lens->focalLength)
        return usageError(kName, "give the focal length, e.g. --focal 50mm (or --lens PRESET)");
    if (!lens->coc) lens->cocSource = "full-frame diagonal/1500 by default; set --coc or --sensor";
    const double coc = lens->coc.value_or(optics::findSensorPreset("full-frame")->coc());
    const double f = *lens->focalLength;

    const bool planning = !args.nearText.empty() || !args.farText.empty();
    if (planning) {
        if (args.nearText.empty() || args.farText.empty())
            return usageError(kName, "give both limits, e.g. --near 2m --far 5m (or --far inf)");
        auto nearD = parseFocus(args.nearText, "--near");
        if (!nearD) return reportError(kName, nearD.error());
        auto farD = parseFocus(args.farText, "--far");
        if (!farD) return reportError(kName, farD.error());
        if (!(*nearD < *farD))
            return usageError(kName, "--near must be closer than --far, e.g. --near 2m --far 5m");
        const auto plan = optics::planFocus(f, *nearD, *farD, coc, in.from);
        if (!plan)
            return usageError(kName, "--near " + args.nearText +
                                         " is too close for this lens: no sharp image forms "
                                         "there; give a near limit well beyond the focal length");
        in.lens = {f, plan->fNumber};
        in.focusDistance = plan->focusDistance;
    } else {
        if (!lens->fNumber)
            return usageError(kName,
                              "give the aperture, e.g. --fnumber 8 (or --near/--far to "
                              "have it computed)");
        if (!lens->focusDistance)
            return usageError(kName, "give the focus distance, e.g. --focus 10m");
        in.lens = {f, *lens->fNumber};
        in.focusDistance = *lens->focusDistance;
    }
    in.coc = coc;
    const auto r = optics::depthOfField(in);
    if (!r)
        return usageError(kName, "--focus " + formatDistance(in.focusDistance) +
                                     " is too close for a " + formatDistance(f) +
                                     " lens measured from the " + args.from +
                                     " (a thin lens needs 4f between object and sensor); "
                                     "focus farther");
    if (args.json) {
        Json j = resultJson(*r, in, lens->cocSource);
        if (planning) {
            j["wanted_near_m"] = metres(*parseFocus(args.nearText, "--near"));
            j["wanted_far_m"] = metres(*parseFocus(args.farText, "--far"));
        }
        std::cout << j.dump() << std::endl;
        return 0;
    }
    if (planning)
        std::printf("For sharpness from %s to %s: focus at %s and stop down to f/%.3g\n\n",
                    formatDistance(*parseFocus(args.nearText, "--near")).c_str(),
                    formatDistance(*parseFocus(args.farText, "--far")).c_str(),
                    formatDistance(in.focusDistance).c_str(), in.lens.fNumber);
    printTable(*r, in, lens->cocSource);
    return 0;
}

}  // namespace

Command addDofCommand(CLI::App& app) {
    auto args = std::make_shared<DofArgs>();
    CLI::App* sub = app.add_subcommand(
        "dof", "Depth-of-field calculator: near and far limits of sharpness, hyperfocal distance");
    args->lens.add(sub, LensOptionSet{.coc = true, .pitch = true});
    CLI::Option_group* plan =
        sub->add_option_group("Wanted range", "Instead of --fnumber and --focus: what to set");
    plan->add_option("--near", args->nearText, "Nearest distance that must be sharp, e.g. 2m")
        ->type_name("DIST");
    plan->add_option("--far", args->farText, "Farthest distance that must be sharp, or inf")
        ->type_name("DIST");
    CLI::Option_group* out = sub->add_option_group("Output");
    out->add_option("--from", args->from,
                    "Measure distances from the lens, or from the sensor plane like a lens's "
                    "focus scale")
        ->capture_default_str()
        ->type_name("lens|sensor");
    out->add_option("--wavelength", args->wavelength, "Light wavelength for the Airy disc")
        ->capture_default_str()
        ->type_name("LENGTH");
    out->add_flag("--json", args->json, "One JSON object (metres; null for infinity)");
    sub->footer(
        "Give the lens, the aperture and where it is focused; get the nearest and farthest\n"
        "distances that look sharp, the hyperfocal distance and the diffraction budget.\n"
        "Or give --near and --far: get the focus distance and f-number that cover them.\n"
        "Lengths need units: 50mm, 10m, 0.03mm, 1.4um.\n\n"
        "Examples:\n"
        "  infocus dof --focal 50mm --fnumber 8 --focus 10m --coc 0.03mm\n"
        "  infocus dof --focal 24mm --fnumber 11 --focus 3m --sensor aps-c --from sensor\n"
        "  infocus dof --lens rpi-cam3 --focus 0.4dpt\n"
        "  infocus dof --focal 35mm --near 2m --far inf --sensor full-frame\n"
        "Near/far are exact for a thin lens; the common approximations are shown beside them.");
    return {sub, [args] { return runDof(*args); }};
}

}  // namespace infocus::cli
