// SPDX-License-Identifier: MIT
// `infocus depth`: per-region depth from blur width and the in-focus plane, from `analyze` output
// (JSONL) or straight from a source.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "infocus/analysis.h"
#include "infocus/depth_map.h"
#include "infocus/output.h"
#include "infocus/pipeline.h"
#include "infocus/plane_fit.h"
#include "lens_options.h"
#include "parse.h"

namespace infocus::cli {

namespace {

constexpr const char* kName = "depth";

struct DepthArgs {
    std::string input;
    LensOptions lens;
    DepthMapOptions depth;
    std::string grid = "16x9";
    uint64_t frames = 1;
    std::string transfer = "linear";
    bool json = false;
};

using Json = nlohmann::ordered_json;

Json metresOrNull(const std::optional<double>& v) {
    return v && std::isfinite(*v) ? Json(*v) : Json(nullptr);
}

// What one frame needs beyond its measurements: a complete lens with a focus distance.
struct FrameLens {
    optics::ThinLens lens;
    double focus = 0.0;  // metres from the lens
    double pitch = 0.0;  // metres per pixel
    std::string focusSource;
};

Result<FrameLens> lensFor(const LensValues& v, const FrameAnalysis& a) {
    const auto usage = [](const std::string& m) { return makeError(ErrorKind::Usage, m); };
    if (!v.focalLength)
        return usage("give the focal length, e.g. --focal 4.74mm (or --lens rpi-cam3)");
    if (!v.fNumber) return usage("give the aperture, e.g. --fnumber 1.8 (or --lens PRESET)");
    if (!v.pixelPitch)
        return usage(
            "give the pixel pitch of the analysed image, e.g. --pixel-pitch 1.4um (for a "
            "downscaled image, the sensor pitch times the scale factor)");
    FrameLens fl;
    fl.lens = {*v.focalLength, *v.fNumber};
    fl.pitch = *v.pixelPitch;
    if (v.focusDistance) {
        fl.focus = *v.focusDistance;
        fl.focusSource = "--focus";
    } else if (const auto focus = focusFromLensPosition(a)) {
        fl.focus = *focus;
        fl.focusSource = "lens position of the frame";
    } else {
        return usage("give the focus distance, e.g. --focus 0.5m or --focus 2dpt (frame " +
                     std::to_string(a.frame) + " carries no lens position in dioptres)");
    }
    if (!(fl.focus > fl.lens.focalLength))
        return usage("the focus distance " + formatDistance(fl.focus) +
                     " is at or inside the focal length; focus farther, e.g. --focus 1m");
    return fl;
}

std::string lengthOrDash(const std::optional<double>& v) {
    if (!v) return "-";
    return formatDistance(*v);
}

Status processFrame(const FrameAnalysis& a, const DepthArgs& args, const LensValues& values) {
    auto fl = lensFor(values, a);
    if (!fl) return fl.error();
    const DepthMap map = depthMap(
        a, optics::CameraGeometry{fl->lens, fl->focus, fl->pitch, 0.5 * a.width, 0.5 * a.height},
        args.depth);
    const auto& fit = map.plane;
    const auto& planes = map.scenes;
    const double farLimitPx = map.farRootLimitPx;

    if (args.json) {
        Json j;
        j["frame"] = a.frame;
        j["width"] = a.width;
        j["height"] = a.height;
        j["focus_m"] = metresOrNull(fl->focus);
        j["focus_source"] = fl->focusSource;
        j["focal_length_m"] = fl->lens.focalLength;
        j["f_number"] = fl->lens.fNumber;
        j["pixel_pitch_um"] = fl->pitch * 1e6;
        j["blur_floor_px"] = args.depth.blurFloorPx;
        j["far_root_limit_px"] = farLimitPx;
        Json regions = Json::array();
        for (const auto& d : map.regions) {
            const RegionResult& r = a.regions[d.region];
            Json o;
            o["col"] = r.col;
            o["row"] = r.row;
            o["x"] = r.rect.x;
            o["y"] = r.rect.y;
            o["w"] = r.rect.w;
            o["h"] = r.rect.h;
            o["blur_width_px"] = metresOrNull(r.blurWidthPx);
            o["confidence"] = r.confidence;
            if (d.roots) {
                o["defocus_px"] = d.roots->defocusBlur / fl->pitch;
                o["near_m"] = d.roots->nearRoot;
                o["far_m"] = metresOrNull(d.roots->farRoot);
            } else {
                o["defocus_px"] = nullptr;
                o["near_m"] = nullptr;
                o["far_m"] = nullptr;
            }
            o["side"] = d.side;
            regions.push_back(std::move(o));
        }
        j["regions"] = std::move(regions);
        if (fit) {
            Json p;
            p["p0_px"] = fit->p[0];
            p["p1"] = fit->p[1];
            p["p2"] = fit->p[2];
            p["gradient"] = fit->gradient;
            p["line_angle_deg"] = fit->lineAngleDeg;
            if (fit->inFocusLine) {
                const auto& s = *fit->inFocusLine;
                p["in_focus_line_px"] = {s.x0, s.y0, s.x1, s.y1};
            } else {
                p["in_focus_line_px"] = nullptr;
            }
            p["rms_residual_px"] = fit->rmsResidual;
            p["samples"] = fit->samples;
            p["inliers"] = fit->inliers;
            Json hyps = Json::array();
            if (planes)
                for (const auto& s : *planes)
                    hyps.push_back({{"a", s.a},
                                    {"b", s.b},
                                    {"c", s.c},
                                    {"tilt_deg", s.tiltDeg},
                                    {"axis_deg", s.axisAngleDeg},
                                    {"recedes_towards_deg", s.recedesTowardsDeg},
                                    {"depth_on_axis_m", metresOrNull(s.depthOnAxis)}});
            p["scene_planes"] = std::move(hyps);
            j["plane"] = std::move(p);
        } else {
            j["plane"] = nullptr;
        }
        std::cout << j.dump() << std::endl;
        return {};
    }

    std::printf("frame %llu  %dx%d  %g mm f/%g  focus %s (%s)  pitch %.3g um\n",
                static_cast<unsigned long long>(a.frame), a.width, a.height,
                fl->lens.focalLength * 1e3, fl->lens.fNumber, formatDistance(fl->focus).c_str(),
                fl->focusSource.c_str(), fl->pitch * 1e6);
    std::printf("  blur beyond %.1f px has no far root (a point at infinity blurs that much)\n\n",
                farLimitPx);
    std::printf("  col row   blur px  conf   near root     far root   side\n");
    for (const auto& d : map.regions) {
        const RegionResult& r = a.regions[d.region];
        char blur[32];
        if (r.blurWidthPx)
            std::snprintf(blur, sizeof blur, "%8.2f", *r.blurWidthPx);
        else
            std::snprintf(blur, sizeof blur, "%8s", "-");
        std::printf("  %3d %3d  %s  %4.2f  %10s  %11s   %s\n", r.col, r.row, blur, r.confidence,
                    d.roots ? formatDistance(d.roots->nearRoot).c_str() : "-",
                    d.roots ? lengthOrDash(d.roots->farRoot).c_str() : "-",
                    d.side > 0 ? "+" : (d.side < 0 ? "-" : " "));
    }
    if (!fit) {
        std::printf(
            "\n  in-focus plane: not enough regions with a blur measurement (need 3 "
            "not on one line)\n\n");
        return {};
    }
    std::printf("\n  in-focus plane  |p0 + p1 x + p2 y| fitted to %d of %d regions, rms %.2f px\n",
                fit->inliers, fit->samples, fit->rmsResidual);
    std::printf("  blur gradient   %.4g px per px; zero line at %.1f deg from the x axis\n",
                fit->gradient, fit->lineAngleDeg);
    if (fit->inFocusLine)
        std::printf("  in-focus line   (%.0f, %.0f) to (%.0f, %.0f) px\n", fit->inFocusLine->x0,
                    fit->inFocusLine->y0, fit->inFocusLine->x1, fit->inFocusLine->y1);
    else
        std::printf("  in-focus line   outside the image: every region is on one side of focus\n");
    if (planes) {
        for (int k = 0; k < 2; ++k) {
            const auto& s = (*planes)[k];
            std::printf(
                "  %s  tilt %.2f deg about an axis at %.1f deg, receding towards %.0f "
                "deg; on axis at %s (aX+bY+cZ=1: a=%.4g b=%.4g c=%.4g /m)\n",
                k == 0 ? "if + is beyond focus " : "if + is before focus", s.tiltDeg,
                s.axisAngleDeg, s.recedesTowardsDeg, formatDistance(s.depthOnAxis).c_str(), s.a,
                s.b, s.c);
        }
        std::printf(
            "  one focus setting cannot tell which side is nearer: regions marked + "
            "share a side; a second focus setting decides it\n");
    }
    std::printf("\n");
    return {};
}

bool isJsonlFile(const std::string& input) {
    std::error_code ec;
    return input.size() > 6 && input.ends_with(".jsonl") &&
           std::filesystem::is_regular_file(input, ec);
}

int runDepth(const DepthArgs& args) {
    auto values = args.lens.resolve();
    if (!values) return reportError(kName, values.error());
    if (const std::string u = depthMapOptionsUsage(args.depth); !u.empty())
        return usageError(kName, u);
    uint64_t frames = 0;
    bool warnedSharpened = false;
    const auto sink = [&](const FrameAnalysis& a) -> Status {
        ++frames;
        warnIfSharpened(kName, a, warnedSharpened);
        return processFrame(a, args, *values);
    };
    if (args.input == "-" || isJsonlFile(args.input)) {
        std::ifstream file;
        if (args.input != "-") file.open(args.input);
        std::istream& in = args.input == "-" ? std::cin : file;
        std::string line;
        uint64_t lineNo = 0;
        while (std::getline(in, line)) {
            ++lineNo;
            if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
            auto a = parseJsonLine(line);
            if (!a) {
                auto e = a.error();
                e.message = args.input + " line " + std::to_string(lineNo) + ": " + e.message;
                return reportError(kName, e);
            }
            if (const Status st = sink(*a); !st) return reportError(kName, st.error());
        }
    } else {
        AnalysisOptions options;
        const auto grid = parseGrid(args.grid);
        if (!grid) return usageError(kName, gridUsage(args.grid));
        options.cols = grid->first;
        options.rows = grid->second;
        if (!parseTransfer(args.transfer, options))
            return usageError(kName, transferUsage(args.transfer));
        const auto onStart = [&](const SourceInfo& info, const AnalysisOptions& used) {
            noteTransfer(kName, info, used);
        };
        if (const Status st = analyzeSource(args.input, options, args.frames, sink, {}, onStart);
            !st)
            return reportError(kName, st.error());
    }
    if (frames == 0)
        return reportError(
            kName, makeError(ErrorKind::Corrupt, "'" + args.input +
                                                     "' held no frame; give 'infocus analyze' "
                                                     "output or a source that delivers frames"));
    return 0;
}

}  // namespace

Command addDepthCommand(CLI::App& app) {
    auto args = std::make_shared<DepthArgs>();
    CLI::App* sub = app.add_subcommand(
        "depth", "Per-region depth from blur width, the in-focus line and the tilt of the scene");
    sub->add_option("INPUT", args->input, "analyze JSONL file, - (stdin), or a SOURCE")->required();
    args->lens.add(sub, LensOptionSet{.coc = false, .pitch = true});
    addDepthMapOptions(sub, args->depth);
    sub->add_option("--grid", args->grid, "Regions as columns x rows (SOURCE input)")
        ->capture_default_str();
    sub->add_option("--frames", args->frames, "Frames to analyse (SOURCE input; 0: all)")
        ->check(frameCount())
        ->capture_default_str();
    sub->add_option(
           "--transfer", args->transfer,
           "How grey levels encode light (SOURCE input): linear, srgb, rec709 or auto (the "
           "source's own)")
        ->capture_default_str();
    sub->add_flag("--json", args->json, "One JSON object per frame (JSONL)");
    sub->footer(
        "Each region's blur width b gives two depths, 1/z = 1/u +- b/(A z_s), in front of and\n"
        "behind the in-focus distance u. A robust fit of |p0 + p1 x + p2 y| to the blur map gives\n"
        "the in-focus line and the tilt of the scene; one focus setting cannot say which side of\n"
        "that line is nearer, so both readings are shown.\n\n"
        "Examples:\n"
        "  infocus analyze sim:scene=tilted,focus=0.5m -o tilt.jsonl\n"
        "  infocus depth tilt.jsonl --lens rpi-cam3 --pixel-pitch 5.04um --focus 0.5m\n"
        "    (sim: renders the 4608-pixel-wide sensor at 1280 wide: 1.4um x 3.6 per pixel)\n"
        "  infocus depth sim:scene=tilted --focal 25mm --fnumber 1.4 --pixel-pitch 3.45um "
        "--focus 2dpt --json");
    return {sub, [args] { return runDepth(*args); }};
}

}  // namespace infocus::cli
