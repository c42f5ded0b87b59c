// SPDX-License-Identifier: MIT
// `infocus live`: the live focus assistant. Parses the options, opens the live pipeline, hands it
// to the faces the person chose (src/live/faces.h) and picks the exit status.
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <iostream>
#include <memory>

#include "commands.h"
#include "infocus/devices.h"
#include "infocus/live.h"
#include "lens_options.h"
#include "parse.h"
#include "src/live/faces.h"
#include "src/live/present.h"

namespace infocus::cli {

namespace {

constexpr const char* kName = "live";

struct LiveArgs {
    std::string source;
    std::string ui;
    std::string grid = "16x9";
    std::string roi;
    std::string metric;
    std::string transfer = "linear";
    std::string peaking = "off";
    std::string af = "off";
    bool noBlur = false;
    bool centreWeighted = false;
    std::optional<double> seconds;
    uint64_t frames = 0;
    std::string listen = "127.0.0.1:8080";
    std::string token;
    LensOptions lens;
};

std::atomic<bool> gStop{false};

extern "C" void onLiveSignal(int) {
    gStop.store(true);
}

// The first camera infocus can read; sim: when there is none.
std::string defaultSource() {
    std::vector<UnlistedBackend> unlisted;
    for (const DeviceInfo& d : listDevices(unlisted)) {
        if (d.mediaController) continue;
        for (const auto& f : d.formats)
            if (f.format != PixelFormat::Invalid) return d.sourceString;
    }
    std::cerr << "infocus live: no camera found; showing the simulated camera (sim:). Name a "
                 "source to use another, e.g. infocus live /dev/video0\n";
    return "sim:";
}

// The pipeline's options from the command line; a usage error names the option.
Result<LiveOptions> liveOptions(const LiveArgs& args) {
    auto values = args.lens.resolve();
    if (!values) return values.error();
    LiveOptions o;
    const auto grid = parseGrid(args.grid);
    if (!grid) return makeError(ErrorKind::Usage, gridUsage(args.grid));
    o.analysis.cols = grid->first;
    o.analysis.rows = grid->second;
    o.analysis.metric = args.metric;
    o.analysis.measureBlur = !args.noBlur;
    o.analysis.centreWeighted = args.centreWeighted;
    if (!parseTransfer(args.transfer, o.analysis))
        return makeError(ErrorKind::Usage, transferUsage(args.transfer));
    if (!args.roi.empty()) {
        o.scoreRoi = parseRoi(args.roi);
        if (!o.scoreRoi || o.scoreRoi->w <= 0 || o.scoreRoi->h <= 0)
            return makeError(ErrorKind::Usage, "--roi " + args.roi +
                                                   " is not a region; give x,y,w,h in pixels, "
                                                   "e.g. --roi 600,300,200,200");
    }
    auto peaking = parsePeakingMode(args.peaking);
    if (!peaking) return peaking.error();
    o.peaking = *peaking;
    if (values->focalLength && values->fNumber)
        o.lens.lens = optics::ThinLens{*values->focalLength, *values->fNumber};
    o.lens.pixelPitchM = values->pixelPitch;
    o.lens.cocM = values->coc;
    o.lens.focusDistanceM = values->focusDistance;
    return o;
}

// Starts the autofocus --af asks for; an error names the option.
Status startAutofocus(LiveAutofocusMode mode, LiveControls& controls) {
    Status st;
    if (mode == LiveAutofocusMode::Once) st = controls.autofocus();
    if (mode == LiveAutofocusMode::Continuous) st = controls.setContinuousAutofocus(true);
    if (!st)
        return makeError(st.error().kind, "--af " + std::string(liveAutofocusModeName(mode)) +
                                              ": " + st.error().message);
    return st;
}

int runLive(const LiveArgs& args) {
    auto options = liveOptions(args);
    if (!options) return reportError(kName, options.error());
    auto af = parseLiveAutofocusMode(args.af);
    if (!af) return reportError(kName, makeError(ErrorKind::Usage, "--af: " + af.error().message));
    const std::string ui =
        args.ui.empty() ? defaultFace(isatty(STDOUT_FILENO) && isatty(STDIN_FILENO)) : args.ui;
    auto choice = parseFaces(ui);
    if (!choice) return reportError(kName, choice.error());
    const std::string source = args.source.empty() ? defaultSource() : args.source;
    FaceSettings settings;
    settings.listen = args.listen;
    settings.token = args.token;
    settings.fromSim = args.source.empty() && source == "sim:";
    // The faces are made and checked (a display, an address) before the camera opens.
    auto faces = FaceSet::make(*choice, settings, *options);
    if (!faces) return reportError(kName, faces.error());
    auto pipeline = LivePipeline::open(source, *options);
    if (!pipeline) return reportError(kName, pipeline.error());
    LivePipeline& p = **pipeline;

    struct sigaction sa {};
    sa.sa_handler = onLiveSignal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);

    if (Status st = p.start(); !st) return reportError(kName, st.error());
    if (Status st = startAutofocus(*af, p); !st) {
        p.stop();
        return reportError(kName, st.error());
    }
    RunLimits limits;
    limits.seconds = args.seconds;
    if (args.frames > 0) limits.frames = args.frames;
    limits.stop = &gStop;
    const Status shown = faces->run(p, limits);
    const bool ended = p.ended();
    const Status end = p.endStatus();
    p.stop();
    if (!shown) return reportError(kName, shown.error());
    if (ended && !end) return reportError(kName, end.error());
    return 0;
}

// @p text with every line indented by two spaces.
std::string indented(const std::string& text) {
    std::string out;
    size_t from = 0;
    while (from < text.size()) {
        const size_t nl = text.find('\n', from);
        const size_t end = nl == std::string::npos ? text.size() : nl + 1;
        out += "  " + text.substr(from, end - from);
        from = end;
    }
    return out;
}

}  // namespace

Command addLiveCommand(CLI::App& app) {
    auto args = std::make_shared<LiveArgs>();
    CLI::App* sub = app.add_subcommand(
        "live",
        "The live focus assistant: a meter of sharpness and blur, per region, as you focus");
    sub->add_option("SOURCE", args->source,
                    "A camera, recording, file or sim: (default: the first camera, else sim:)");
    sub->add_option("--ui", args->ui,
                    "Faces, a comma list: one of tui (the terminal meter; the default on a "
                    "terminal), window (the picture with overlays and the meter), text (a line a "
                    "second; the default otherwise) or json (an object a second), and/or web (the "
                    "page at --listen)");
    sub->add_option("--listen", args->listen,
                    "The web view's ADDR:PORT (port 0: any free port); beyond loopback a token "
                    "is required")
        ->capture_default_str();
    sub->add_option("--token", args->token,
                    "The web view's token (default: generated when listening beyond loopback)");
    sub->add_option("--grid", args->grid, "Regions as columns x rows")->capture_default_str();
    sub->add_option("--roi", args->roi, "Score this region x,y,w,h instead of the whole frame");
    sub->add_option("--metric", args->metric, "Sharpness operator (default teng)");
    sub->add_option("--transfer", args->transfer,
                    "How grey levels encode light: linear, srgb, "
                    "rec709 or auto")
        ->capture_default_str();
    sub->add_option("--peaking", args->peaking, "Peaking mask: off, coc or percentile")
        ->capture_default_str();
    sub->add_option("--af", args->af,
                    "Autofocus at start: once (from the blur width), continuous (keep the "
                    "subject in focus) or off")
        ->capture_default_str();
    sub->add_flag("--no-blur", args->noBlur, "Sharpness only: skip the blur-width measurement");
    sub->add_flag("--centre-weighted", args->centreWeighted,
                  "Weight the whole-frame score towards the centre");
    sub->add_option("--seconds", args->seconds, "Stop after this many seconds")
        ->check(secondsIn(0, 1e9, "--seconds 10"));
    sub->add_option("--frames", args->frames, "Stop after this many analysed frames")
        ->check(frameCount(1));
    args->lens.add(sub, LensOptionSet{.coc = true, .pitch = true});
    sub->footer(
        "Keys (terminal and window):\n" + indented(present::keyHelp()) +
        "In the window the mouse wheel focuses too; drag a region to score it (a click scores\n"
        "the whole frame).\n"
        "Examples:\n"
        "  infocus live\n"
        "  infocus live sim:focal=16mm,fnumber=1.4,distance=1m,focus=0.5m --ui json --seconds 6\n"
        "  infocus live sim:focal=16mm,fnumber=1.4,distance=1m,focus=0.5m --af once --ui json\n"
        "  infocus live /dev/video0 --lens rpi-cam3 --coc-px 2\n"
        "  infocus live /dev/video0 --ui web --listen 0.0.0.0:8080");
    return {sub, [args] { return runLive(*args); }};
}

}  // namespace infocus::cli
