// SPDX-License-Identifier: MIT
// `infocus devices`: the cameras on this machine and what they offer for focusing.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>
#include <memory>

#include "commands.h"
#include "infocus/devices.h"

namespace infocus::cli {

namespace {

struct DevicesArgs {
    bool json = false;
};

std::string sizeText(Size s) {
    return std::to_string(s.width) + "x" + std::to_string(s.height);
}

std::string number(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
}

nlohmann::ordered_json controlJson(const DeviceControl& c) {
    nlohmann::ordered_json j;
    j["name"] = c.name;
    j["unit"] = c.unit;
    j["min"] = c.min;
    j["max"] = c.max;
    j["step"] = c.step;
    j["default"] = c.defaultValue;
    j["current"] = c.current ? nlohmann::ordered_json(*c.current) : nlohmann::ordered_json();
    // A lens sub-device's node; null for the camera's own controls.
    j["device"] = c.device.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(c.device);
    j["lens"] = c.lens.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(c.lens);
    return j;
}

std::string controlText(const DeviceControl& c) {
    std::string s = c.name + " " + number(c.min) + ".." + number(c.max);
    if (c.step > 0) s += " step " + number(c.step);
    s += " (" + c.unit + ")";
    if (c.current) s += ", now " + number(*c.current);
    if (!c.device.empty()) s += ", on " + c.device + (c.lens.empty() ? "" : " (" + c.lens + ")");
    return s;
}

void printText(const std::vector<DeviceInfo>& devices) {
    for (const auto& d : devices) {
        std::printf("%s  %s (%s, %s%s%s)\n", d.sourceString.c_str(), d.card.c_str(),
                    d.driver.c_str(), d.device.c_str(), d.bus.empty() ? "" : ", ", d.bus.c_str());
        if (d.mediaController) std::printf("    %s\n", mediaControllerNote().c_str());
        if (d.currentFormat) std::printf("    current: %s\n", d.currentFormat->c_str());
        if (d.currentTransfer)
            std::printf("    transfer function: %s (%s%s)\n",
                        d.currentTransfer->curve ? transferFunctionName(*d.currentTransfer->curve)
                                                 : "unknown",
                        d.currentTransfer->curve ? "from " : "", d.currentTransfer->origin.c_str());
        for (const auto& f : d.formats) {
            std::printf("    %-6s %s%s\n", f.fourcc.c_str(), f.description.c_str(),
                        f.format == PixelFormat::Invalid ? " (infocus cannot read it)" : "");
            std::string line;
            for (const auto& s : f.sizes) {
                if (!line.empty()) line += ", ";
                line += sizeText(s.size);
                if (!s.fps.empty()) line.append("@").append(number(s.fps.front()));
            }
            if (!line.empty()) std::printf("           %s\n", line.c_str());
        }
        if (d.focus)
            std::printf("    focus: %s\n", controlText(*d.focus).c_str());
        else
            std::printf("    focus: none (fixed or manual lens)\n");
        if (d.focusRelative) std::printf("    focus: relative moves (focus_relative)\n");
        if (d.autofocusContinuous || d.autofocusTrigger)
            std::printf("    autofocus:%s%s\n", d.autofocusContinuous ? " continuous" : "",
                        d.autofocusTrigger ? " one-shot" : "");
        for (const auto& c : d.controls) {
            std::printf("    %s\n", controlText(c).c_str());
            // Sharpening narrows every edge it is given (a 1 px σ reads a fifth to a third
            // narrow, docs/blur.md): say so where it is on, or may be (current value unknown).
            if (c.name == "sharpness" && c.current.value_or(c.defaultValue) > c.min)
                std::printf(
                    "      sharpening makes blur widths read narrow: set sharpness to %s "
                    "while measuring\n",
                    number(c.min).c_str());
        }
    }
}

int runDevices(const DevicesArgs& args) {
    std::vector<UnlistedBackend> unlisted;
    const std::vector<DeviceInfo> found = listDevices(unlisted);
    const std::vector<DeviceInfo>* devices = &found;
    // What could not be asked is said, and the rest still listed: a missing libcamera module
    // hides no V4L2 camera.
    for (const UnlistedBackend& u : unlisted)
        std::cerr << "infocus devices: " << u.backend << " cameras are not listed: " << u.why
                  << "\n";
    if (args.json) {
        auto all = nlohmann::ordered_json::array();
        for (const auto& d : *devices) {
            nlohmann::ordered_json j;
            j["backend"] = d.backend;
            j["source"] = d.sourceString;
            j["device"] = d.device;
            j["driver"] = d.driver;
            j["card"] = d.card;
            j["bus"] = d.bus;
            j["media_controller"] = d.mediaController;
            j["current_format"] = d.currentFormat ? nlohmann::ordered_json(*d.currentFormat)
                                                  : nlohmann::ordered_json();
            j["current_transfer"] =
                d.currentTransfer && d.currentTransfer->curve
                    ? nlohmann::ordered_json(transferFunctionName(*d.currentTransfer->curve))
                    : nlohmann::ordered_json();
            auto formats = nlohmann::ordered_json::array();
            for (const auto& f : d.formats) {
                nlohmann::ordered_json jf;
                jf["fourcc"] = f.fourcc;
                jf["readable"] = f.format != PixelFormat::Invalid;
                jf["description"] = f.description;
                auto sizes = nlohmann::ordered_json::array();
                for (const auto& s : f.sizes)
                    sizes.push_back(
                        {{"width_px", s.size.width}, {"height_px", s.size.height}, {"fps", s.fps}});
                jf["sizes"] = sizes;
                formats.push_back(jf);
            }
            j["formats"] = formats;
            j["focus"] = d.focus ? controlJson(*d.focus) : nlohmann::ordered_json();
            j["focus_relative"] = d.focusRelative;
            j["autofocus_continuous"] = d.autofocusContinuous;
            j["autofocus_trigger"] = d.autofocusTrigger;
            auto controls = nlohmann::ordered_json::array();
            for (const auto& c : d.controls)
                controls.push_back(controlJson(c));
            j["controls"] = controls;
            all.push_back(j);
        }
        std::cout << all.dump(2) << std::endl;
        return 0;
    }
    if (devices->empty()) {
        std::printf("%s\n", noCameraMessage().c_str());
        return 0;
    }
    printText(*devices);
    return 0;
}

}  // namespace

Command addDevicesCommand(CLI::App& app) {
    auto args = std::make_shared<DevicesArgs>();
    CLI::App* sub = app.add_subcommand(
        "devices", "List " + cameraKindsText() + ": formats, sizes, rates, focus");
    sub->add_flag("--json", args->json, "One JSON array of cameras instead of text");
    return {sub, [args] { return runDevices(*args); }};
}

}  // namespace infocus::cli
