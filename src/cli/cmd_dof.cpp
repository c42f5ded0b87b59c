// SPDX-License-Identifier: MIT
// `infocus dof`: a depth-of-field calculator on the thin-lens model (and its inverse: the focus
// and f-number for a wanted near/far pair).
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "commands.h"
#include "infocus/dof.h"
#include "infocus/dof_output.h"
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
    std::optional<DofWanted> wanted;  // the limits asked for, when planning
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
        wanted = DofWanted{*nearD, *farD};
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
    if (args.json)
        std::cout << dofJson(*r, in, lens->cocSource, wanted) << std::endl;
    else
        writeDofText(std::cout, *r, in, lens->cocSource, wanted);
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
