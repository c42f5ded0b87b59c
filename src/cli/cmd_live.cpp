// SPDX-License-Identifier: MIT
// `infocus live`: the live focus assistant. Opens the live pipeline and hands it to the faces the
// user chose (the terminal meter, a line of text or a JSON object a second, the web view).
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <thread>

#include "commands.h"
#include "infocus/devices.h"
#include "infocus/live.h"
#include "infocus/output.h"
#include "infocus/units.h"
#include "infocus_config.h"
#include "lens_options.h"
#include "parse.h"
#if HAVE_TUI
#include "src/live/tui/tui.h"
#endif
#if HAVE_WEB
#include "src/live/web/web.h"
#endif
#if HAVE_WINDOW
#include "src/live/window/window.h"
#endif

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
    bool noBlur = false;
    bool centreWeighted = false;
    std::optional<double> seconds;
    uint64_t frames = 0;
    std::string listen = "127.0.0.1:8080";
    std::string token;
    LensOptions lens;
};

// The faces of one run: at most one that holds the terminal or a window until the run ends
// (tui, text, json), plus the web view beside it. Empty `blocking` with `web`: the web view alone.
struct Faces {
    std::string blocking;
    bool web = false;
};

// Parses --ui's comma list; a usage message when it names no face, an unknown one or two
// blocking ones.
Result<Faces> parseFaces(const std::string& ui) {
    Faces f;
    std::stringstream list(ui);
    std::string face;
    const auto usage = [&](const std::string& why) {
        return makeError(ErrorKind::Usage, "--ui " + ui + ": " + why +
                                               "; use one of tui, window, text or json, and/or "
                                               "web, e.g. --ui web or --ui tui,web");
    };
    while (std::getline(list, face, ',')) {
        if (face == "web") {
            f.web = true;
        } else if (face == "tui" || face == "window" || face == "text" || face == "json") {
            if (!f.blocking.empty()) return usage("at most one of tui, window, text and json");
            f.blocking = face;
        } else {
            return usage("\"" + face + "\" is not a face");
        }
    }
    if (f.blocking.empty() && !f.web) return usage("no face named");
#if !HAVE_TUI
    if (f.blocking == "tui")
        return makeError(ErrorKind::Usage,
                         "this infocus was built without the terminal face (ncurses); use --ui "
                         "text or --ui json, or rebuild with libncurses-dev");
#endif
#if !HAVE_WEB
    if (f.web)
        return makeError(ErrorKind::Usage,
                         "this infocus was built without the web view (cpp-httplib); rebuild "
                         "with libcpp-httplib-dev");
#endif
    return f;
}

std::atomic<bool> gStop{false};

extern "C" void onLiveSignal(int) {
    gStop.store(true);
}

// The first camera infocus can read; sim: when there is none.
std::string defaultSource() {
    auto devices = listDevices();
    if (devices)
        for (const DeviceInfo& d : *devices) {
            if (d.mediaController) continue;
            for (const auto& f : d.formats)
                if (f.format != PixelFormat::Invalid) return d.sourceString;
        }
    std::cerr << "infocus live: no camera found; showing the simulated camera (sim:). Name a "
                 "source to use another, e.g. infocus live /dev/video0\n";
    return "sim:";
}

std::string distanceText(std::optional<double> m) {
    if (!m) return "-";
    if (std::isinf(*m)) return "infinity";
    return formatDistance(*m);
}

// One line a second for a log or a pipe.
std::string textLine(const LiveState& s) {
    char blur[32] = "-";
    if (s.blurPx) std::snprintf(blur, sizeof blur, "%.1f", *s.blurPx);
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "frame %llu  %.1f fps  %s %.5g  %5.1f%% of peak  %-7s%s  blur %s px",
                  static_cast<unsigned long long>(s.frame), s.fps, s.metric.c_str(), s.score,
                  s.percentOfPeak, std::string(trendName(s.trend)).c_str(),
                  s.pastPeak ? "  past the peak: back up" : "", blur);
    std::string line = buf;
    if (s.lens) {
        std::snprintf(buf, sizeof buf, "  lens %.4g %s", s.lens->value, s.lens->unit.c_str());
        line += buf;
    }
    if (s.inFocusDistanceM) line += "  in focus at " + distanceText(s.inFocusDistanceM);
    if (s.dofNearM) line += "  DoF " + distanceText(s.dofNearM) + " to " + distanceText(s.dofFarM);
    std::snprintf(buf, sizeof buf, "  dropped %llu  skipped %llu  latency %.1f/%.1f ms",
                  static_cast<unsigned long long>(s.dropped),
                  static_cast<unsigned long long>(s.skipped), s.latencyP50Ms, s.latencyP99Ms);
    line += buf;
    if (!s.status.empty()) line += "  (" + s.status + ")";
    return line;
}

// The text and JSON faces: the newest state once a second until the run ends; with @p print
// false (the web view alone) it only waits for the end.
int runPrinted(LivePipeline& p, const LiveArgs& args, bool json, bool print = true) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    auto nextPrint = start + std::chrono::seconds(1);
    std::optional<uint64_t> last;
    while (!gStop.load()) {
        auto s = p.waitForState(last, std::chrono::milliseconds(100));
        if (s) last = s->frame;
        const auto now = Clock::now();
        const bool framesDone = args.frames > 0 && last && *last + 1 >= args.frames;
        const bool timeDone =
            args.seconds && std::chrono::duration<double>(now - start).count() >= *args.seconds;
        if (print && (now >= nextPrint || framesDone)) {
            if (auto newest = p.state()) {
                std::cout << (json ? liveStateJson(*newest) : textLine(*newest)) << std::endl;
                if (!std::cout)
                    return reportError(kName, makeError(ErrorKind::Io, "cannot write to stdout"));
            }
            nextPrint += std::chrono::seconds(1);
        }
        if (framesDone || timeDone) break;
        if (!s && p.ended()) break;
        // An ended pipeline answers at once: wait without spinning.
        if (!s && !print) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return 0;
}

int runLive(LiveArgs args) {
    auto values = args.lens.resolve();
    if (!values) return reportError(kName, values.error());
    LiveOptions o;
    const auto grid = parseGrid(args.grid);
    if (!grid) return usageError(kName, gridUsage(args.grid));
    o.analysis.cols = grid->first;
    o.analysis.rows = grid->second;
    o.analysis.metric = args.metric;
    o.analysis.measureBlur = !args.noBlur;
    o.analysis.centreWeighted = args.centreWeighted;
    if (!parseTransfer(args.transfer, o.analysis))
        return usageError(kName, transferUsage(args.transfer));
    if (!args.roi.empty()) {
        o.scoreRoi = parseRoi(args.roi);
        if (!o.scoreRoi || o.scoreRoi->w <= 0 || o.scoreRoi->h <= 0)
            return usageError(kName, "--roi " + args.roi +
                                         " is not a region; give x,y,w,h in pixels, e.g. "
                                         "--roi 600,300,200,200");
    }
    auto peaking = parsePeakingMode(args.peaking);
    if (!peaking) return reportError(kName, peaking.error());
    o.peaking = *peaking;
    if (values->focalLength && values->fNumber)
        o.lens.lens = optics::ThinLens{*values->focalLength, *values->fNumber};
    o.lens.pixelPitchM = values->pixelPitch;
    o.lens.cocM = values->coc;
    o.lens.focusDistanceM = values->focusDistance;

    std::string uiList = args.ui;
    if (uiList.empty()) {
#if HAVE_TUI
        uiList = isatty(STDOUT_FILENO) && isatty(STDIN_FILENO) ? "tui" : "text";
#else
        uiList = "text";
#endif
    }
    auto faces = parseFaces(uiList);
    if (!faces) return reportError(kName, faces.error());
    const std::string ui = faces->blocking;
#if HAVE_WEB
    WebOptions wo;
    wo.listen = args.listen;
    if (!args.token.empty()) wo.token = args.token;
    if (faces->web) {
        if (auto a = parseListenAddress(args.listen); !a) return reportError(kName, a.error());
        o.previewLongSide = std::max(o.previewLongSide, wo.previewLongSide);
    }
#endif

    // The window: a display is checked before the camera opens, the picture kept at full size.
    if (ui == "window") {
#if HAVE_WINDOW
        if (Status st = windowDisplayCheck(); !st) {
            reportError(kName, st.error());
            return kExitUsage;
        }
        o.previewLongSide = std::max(o.previewLongSide, kWindowPreviewLongSide);
#else
        return usageError(kName,
                          "this infocus was built without the window view (SDL2, Dear ImGui); use "
                          "--ui tui or --ui web, or rebuild with libsdl2-dev and libimgui-dev");
#endif
    }

    const std::string source = args.source.empty() ? defaultSource() : args.source;
    auto pipeline = LivePipeline::open(source, o);
    if (!pipeline) return reportError(kName, pipeline.error());
    LivePipeline& p = **pipeline;

    struct sigaction sa {};
    sa.sa_handler = onLiveSignal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);

    if (Status st = p.start(); !st) return reportError(kName, st.error());
#if HAVE_WEB
    std::unique_ptr<WebServer> web;
    if (faces->web) {
        auto started = WebServer::start(p, wo);
        if (!started) {
            p.stop();
            return reportError(kName, started.error());
        }
        web = std::move(*started);
        std::cerr << "infocus live: open " << web->url() << std::endl;
    }
#endif
    int rc = 0;
#if HAVE_TUI
    if (ui == "tui") {
        TuiOptions to;
        to.seconds = args.seconds;
        if (args.frames > 0) to.frames = args.frames;
        to.stop = &gStop;
        to.fromSim = args.source.empty() && source == "sim:";
        if (Status st = runTui(p, to); !st) rc = reportError(kName, st.error());
    }
#endif
#if HAVE_WINDOW
    if (ui == "window") {
        WindowOptions win;
        win.seconds = args.seconds;
        if (args.frames > 0) win.frames = args.frames;
        win.stop = &gStop;
        // No window after all (SDL_CreateWindow failed): a usage error like no display.
        if (Status st = runWindow(p, win); !st)
            rc = st.error().kind == ErrorKind::Unsupported && !p.ended()
                     ? (reportError(kName, st.error()), kExitUsage)
                     : reportError(kName, st.error());
    }
#endif
    if (ui == "text" || ui == "json") rc = runPrinted(p, args, ui == "json");
    if (ui.empty()) rc = runPrinted(p, args, false, false);  // the web view alone
#if HAVE_WEB
    if (web) web->stop();
#endif
    const bool ended = p.ended();
    const Status end = p.endStatus();
    p.stop();
    if (rc != 0) return rc;
    if (ended && !end) return reportError(kName, end.error());
    return 0;
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
    sub->add_flag("--no-blur", args->noBlur, "Sharpness only: skip the blur-width measurement");
    sub->add_flag("--centre-weighted", args->centreWeighted,
                  "Weight the whole-frame score towards the centre");
    sub->add_option("--seconds", args->seconds, "Stop after this many seconds")
        ->check(secondsIn(0, 1e9, "--seconds 10"));
    sub->add_option("--frames", args->frames, "Stop after this many analysed frames")
        ->check(frameCount(1));
    args->lens.add(sub, LensOptionSet{.coc = true, .pitch = true});
    sub->footer(
        "Keys (tui): left/right focus (Shift x10), a autofocus, r reset peak, g grid, q quit.\n"
        "Keys (window): also the mouse wheel to focus, p peaking, m magnifier 1:1/2:1, drag a\n"
        "  region to score it (a click scores the whole frame), Esc quits.\n"
        "Examples:\n"
        "  infocus live\n"
        "  infocus live sim:focal=16mm,fnumber=1.4,distance=1m,focus=0.5m --ui json --seconds 6\n"
        "  infocus live /dev/video0 --lens rpi-cam3 --coc-px 2\n"
        "  infocus live /dev/video0 --ui web --listen 0.0.0.0:8080");
    return {sub, [args] { return runLive(*args); }};
}

}  // namespace infocus::cli
