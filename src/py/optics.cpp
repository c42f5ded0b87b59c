// SPDX-License-Identifier: MIT
// infocus.Lens with depth of field and depth from blur: the thin-lens model of src/optics, metres
// throughout (infinity is math.inf).
#include <pybind11/stl.h>

#include <cmath>
#include <string>

#include "infocus/dof.h"
#include "infocus/lens_presets.h"
#include "infocus/optics.h"
#include "py_infocus.h"

namespace infocus::py {

namespace {

std::string presetNames() {
    std::string names;
    for (const auto& l : optics::lensPresets())
        names += (names.empty() ? "" : ", ") + std::string(l.name);
    return names;
}

Lens makeLens(double focalLength, double fNumber, std::optional<double> pixelPitch,
              std::optional<double> coc, std::optional<double> focus) {
    Lens l;
    l.thin = {focalLength, fNumber};
    if (!l.thin.valid())
        throw pb::value_error(
            "Lens: focal length and f-number must be finite and positive, e.g. "
            "infocus.Lens(50e-3, 8) for 50 mm f/8 (lengths in metres)");
    if (pixelPitch && !(*pixelPitch > 0.0 && std::isfinite(*pixelPitch)))
        throw pb::value_error("Lens: pixel_pitch must be positive metres, e.g. 1.4e-6");
    if (coc && !(*coc > 0.0 && std::isfinite(*coc)))
        throw pb::value_error("Lens: coc must be positive metres, e.g. 30e-6");
    if (focus && !(*focus > 0.0))
        throw pb::value_error(
            "Lens: focus must be a positive distance in metres (math.inf for "
            "infinity)");
    l.pixelPitch = pixelPitch;
    l.coc = coc;
    l.focusDistance = focus;
    return l;
}

double focusOf(const Lens& l, std::optional<double> focus) {
    if (focus) return *focus;
    if (l.focusDistance) return *l.focusDistance;
    throw pb::value_error(
        "give the focus distance, e.g. focus=2.0 (metres), or set it on the "
        "Lens");
}

double cocOf(const Lens& l, std::optional<double> coc) {
    if (coc) return *coc;
    if (l.coc) return *l.coc;
    throw pb::value_error(
        "give the circle of confusion, e.g. coc=30e-6 (metres), or make the "
        "Lens from a preset that names its sensor");
}

}  // namespace

void registerOptics(pb::module_& m) {
    pb::class_<optics::DofLimits>(m, "DofLimits", "Near and far limits of sharpness, metres.")
        .def_readonly("near", &optics::DofLimits::nearLimit)
        .def_readonly("far", &optics::DofLimits::farLimit, "math.inf beyond the hyperfocal.")
        .def_property_readonly("total", &optics::DofLimits::total);

    pb::class_<optics::DofResult>(m, "DepthOfField",
                                  "Depth of field on the thin-lens model; distances in metres "
                                  "from the chosen origin.")
        .def_readonly("focus_distance", &optics::DofResult::focusDistance)
        .def_readonly("focus_from_lens", &optics::DofResult::focusFromLens)
        .def_readonly("sensor_distance", &optics::DofResult::sensorDistance)
        .def_readonly("magnification", &optics::DofResult::magnification)
        .def_readonly("hyperfocal", &optics::DofResult::hyperfocal, "H = f^2/(N c) + f.")
        .def_readonly("hyperfocal_simple", &optics::DofResult::hyperfocalSimple)
        .def_readonly("hyperfocal_near", &optics::DofResult::hyperfocalNear)
        .def_readonly("exact", &optics::DofResult::exact, "Exact thin-lens DofLimits.")
        .def_readonly("approximate", &optics::DofResult::approximate,
                      "The common approximation's DofLimits.")
        .def_property_readonly(
            "near", [](const optics::DofResult& r) { return r.exact.nearLimit; }, "exact.near.")
        .def_property_readonly(
            "far", [](const optics::DofResult& r) { return r.exact.farLimit; }, "exact.far.")
        .def_readonly("front_depth", &optics::DofResult::frontDepth)
        .def_readonly("rear_depth", &optics::DofResult::rearDepth)
        .def_readonly("airy_disc", &optics::DofResult::airyDisc, "2.44 lambda N, metres.")
        .def_readonly("diffraction_limited", &optics::DofResult::diffractionLimited)
        .def_readonly("with_diffraction", &optics::DofResult::withDiffraction,
                      "DofLimits with the Airy disc in the blur budget, or None.");

    pb::class_<optics::DepthRoots>(m, "DepthRoots",
                                   "The two object distances a blur width allows, metres.")
        .def_readonly("defocus_blur", &optics::DepthRoots::defocusBlur,
                      "Blur after the floor was removed, metres on the sensor.")
        .def_readonly("near", &optics::DepthRoots::nearRoot, "In front of the focus.")
        .def_readonly("far", &optics::DepthRoots::farRoot,
                      "Behind the focus (math.inf at the limit), or None past it.");

    pb::class_<Lens>(m, "Lens",
                     "A thin lens: focal length and f-number, with the pixel pitch, circle of "
                     "confusion and focus distance where known. Metres throughout.")
        .def(pb::init(&makeLens), pb::arg("focal_length"), pb::arg("f_number"),
             pb::arg("pixel_pitch") = pb::none(), pb::arg("coc") = pb::none(),
             pb::arg("focus") = pb::none())
        .def_static(
            "preset",
            [](const std::string& name, std::optional<double> focus) {
                const optics::LensPreset* p = optics::findLensPreset(name);
                if (!p)
                    throw pb::value_error("Lens.preset('" + name + "'): unknown preset; choose " +
                                          presetNames());
                const optics::SensorPreset* s = optics::findSensorPreset(p->sensor);
                Lens l = makeLens(p->focalLength, p->fNumber,
                                  p->pixelPitch > 0.0 ? std::optional(p->pixelPitch) : std::nullopt,
                                  s ? std::optional(s->coc()) : std::nullopt, focus);
                l.name = std::string(p->name);
                return l;
            },
            pb::arg("name"), pb::arg("focus") = pb::none(),
            "A lens by its preset name (e.g. 'rpi-cam3'), with its sensor's pitch and circle of "
            "confusion.")
        .def_static(
            "presets",
            [] {
                std::vector<std::string> names;
                for (const auto& l : optics::lensPresets())
                    names.emplace_back(l.name);
                return names;
            },
            "The preset names.")
        .def_property_readonly(
            "focal_length", [](const Lens& l) { return l.thin.focalLength; }, "Metres.")
        .def_property_readonly(
            "f_number", [](const Lens& l) { return l.thin.fNumber; }, "N.")
        .def_property_readonly(
            "aperture", [](const Lens& l) { return l.thin.aperture(); }, "f/N, metres.")
        .def_readonly("pixel_pitch", &Lens::pixelPitch, "Metres per pixel, or None.")
        .def_readonly("coc", &Lens::coc, "Circle of confusion, metres, or None.")
        .def_readonly("focus", &Lens::focusDistance, "Focus distance from the lens, or None.")
        .def_readonly("name", &Lens::name, "The preset's name ('' when given by hand).")
        .def(
            "hyperfocal",
            [](const Lens& l, std::optional<double> coc) {
                return optics::hyperfocalDistance(l.thin, cocOf(l, coc));
            },
            pb::arg("coc") = pb::none(), "H = f^2/(N c) + f, metres from the lens.")
        .def(
            "depth_of_field",
            [](const Lens& l, std::optional<double> focus, std::optional<double> coc,
               const std::string& origin, double wavelength) {
                optics::DofInput in;
                in.lens = l.thin;
                in.focusDistance = focusOf(l, focus);
                in.coc = cocOf(l, coc);
                if (origin == "sensor")
                    in.from = optics::DistanceOrigin::Sensor;
                else if (origin != "lens")
                    throw pb::value_error("origin='" + origin + "': use 'lens' or 'sensor'");
                in.wavelength = wavelength;
                const auto r = optics::depthOfField(in);
                if (!r)
                    throw pb::value_error(
                        "depth_of_field: focus " + std::to_string(in.focusDistance) +
                        " m is too close for this lens (a thin lens needs the focus beyond f, "
                        "and 4f between object and sensor from the sensor); focus farther");
                return *r;
            },
            pb::arg("focus") = pb::none(), pb::arg("coc") = pb::none(), pb::arg("origin") = "lens",
            pb::arg("wavelength") = optics::kDefaultWavelength,
            "Near and far limits of sharpness at `focus` (metres, math.inf allowed) for the "
            "circle of confusion `coc`; distances from the lens or the sensor.")
        .def(
            "depth_from_blur",
            [](const Lens& l, std::optional<double> blur, std::optional<double> blurPx,
               std::optional<double> focus, double floor) -> std::optional<optics::DepthRoots> {
                if (blur.has_value() == blurPx.has_value())
                    throw pb::value_error(
                        "give the blur one way: blur= (metres on the sensor) or "
                        "blur_px= (pixels, with the Lens's pixel_pitch)");
                if (blurPx && !l.pixelPitch)
                    throw pb::value_error(
                        "blur_px needs the Lens's pixel_pitch, e.g. "
                        "infocus.Lens(4.74e-3, 1.8, pixel_pitch=1.4e-6)");
                const double b = blur ? *blur : *blurPx * *l.pixelPitch;
                const double fl = blur ? floor : floor * *l.pixelPitch;
                return optics::depthFromBlur(l.thin, focusOf(l, focus), b, fl);
            },
            pb::arg("blur") = pb::none(), pb::arg("blur_px") = pb::none(),
            pb::arg("focus") = pb::none(), pb::arg("floor") = 0.0,
            "The two distances whose defocus blurs to this width (a disc diameter, metres on "
            "the sensor, or pixels with blur_px), the in-focus `floor` (same unit) removed in "
            "quadrature; None for a focus inside f or a negative blur.")
        .def(
            "blur_width",
            [](const Lens& l, double distance, std::optional<double> focus) {
                const auto zs =
                    optics::sensorDistanceForFocus(l.thin.focalLength, focusOf(l, focus));
                if (!zs) throw pb::value_error("blur_width: the focus is inside the focal length");
                return optics::blurWidth(l.thin, *zs, distance);
            },
            pb::arg("distance"), pb::arg("focus") = pb::none(),
            "Blur disc diameter on the sensor (metres) of an object `distance` metres away.")
        .def("__repr__", [](const Lens& l) {
            return "Lens(" + std::to_string(l.thin.focalLength) + ", " +
                   std::to_string(l.thin.fNumber) + (l.name.empty() ? "" : ", '" + l.name + "'") +
                   ")";
        });
}

}  // namespace infocus::py
