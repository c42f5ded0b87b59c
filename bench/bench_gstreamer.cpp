// SPDX-License-Identifier: MIT
// The focusmeter element's cost inside a GStreamer pipeline: a live videotestsrc at 1080p60
// (GRAY8 and I420) played at its real rate into a clock-synchronised fakesink, once through
// focusmeter and once through identity, in this process; the difference in process CPU is what
// the element adds, and the sink's late buffers say whether it ever held the stream up.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>

#include "bench/bench.h"
#include "infocus_config.h"
#if HAVE_GSTREAMER
#include <gst/gst.h>
#endif

namespace infocus::bench {

namespace {

// A run lasts BenchOptions::liveSeconds, at most this long.
constexpr double kMaxSeconds = 10.0;
constexpr int kFps = 60;
// Later than this at the sink and a buffer counts as late (and is dropped), as a video sink's
// default max-lateness.
constexpr int64_t kMaxLatenessNs = 20'000'000;

#if HAVE_GSTREAMER

double cpuSeconds() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
           1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

struct PipelineRun {
    LiveRun run;            // frames: analysed (focusmeter) or rendered (identity)
    uint64_t rendered = 0;  // buffers the sink rendered
    uint64_t skipped = 0;   // frames focusmeter skipped (the last message's count)
    std::string error;      // empty when the run completed
};

// Plays @p filter between the source and the sink for @p frames frames at @p format.
PipelineRun play(const std::string& format, const std::string& filter, int frames) {
    PipelineRun out;
    const std::string desc =
        "videotestsrc is-live=true num-buffers=" + std::to_string(frames) +
        " ! video/x-raw,format=" + format +
        ",width=1920,height=1080,framerate=" + std::to_string(kFps) + "/1 ! " + filter +
        " ! fakesink name=sink sync=true qos=true max-lateness=" + std::to_string(kMaxLatenessNs);
    GError* err = nullptr;
    GstElement* pipeline = gst_parse_launch(desc.c_str(), &err);
    if (!pipeline || err) {
        out.error = err ? err->message : "cannot build the pipeline";
        if (err) g_error_free(err);
        if (pipeline) gst_object_unref(pipeline);
        return out;
    }
    GstBus* bus = gst_element_get_bus(pipeline);
    const double cpu0 = cpuSeconds();
    const auto t0 = std::chrono::steady_clock::now();
    gst_element_set_state(pipeline, GST_STATE_PLAYING);
    uint64_t analysed = 0;
    for (bool done = false; !done;) {
        GstMessage* m = gst_bus_timed_pop(bus, 30 * GST_SECOND);
        if (!m) {
            out.error = "no end of stream within 30 s of the last message";
            break;
        }
        switch (GST_MESSAGE_TYPE(m)) {
            case GST_MESSAGE_EOS:
                done = true;
                break;
            case GST_MESSAGE_ERROR: {
                GError* e = nullptr;
                gst_message_parse_error(m, &e, nullptr);
                out.error = e ? e->message : "pipeline error";
                if (e) g_error_free(e);
                done = true;
                break;
            }
            case GST_MESSAGE_ELEMENT: {
                const GstStructure* s = gst_message_get_structure(m);
                if (s && gst_structure_has_name(s, "infocus")) {
                    ++analysed;
                    guint64 skipped = 0;
                    if (gst_structure_get_uint64(s, "skipped", &skipped)) out.skipped = skipped;
                }
                break;
            }
            default:
                break;
        }
        gst_message_unref(m);
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu = cpuSeconds() - cpu0;
    GstElement* sink = gst_bin_get_by_name(GST_BIN(pipeline), "sink");
    if (sink) {
        GstStructure* stats = nullptr;
        g_object_get(sink, "stats", &stats, nullptr);
        guint64 rendered = 0, dropped = 0;
        if (stats) {
            gst_structure_get_uint64(stats, "rendered", &rendered);
            gst_structure_get_uint64(stats, "dropped", &dropped);
            gst_structure_free(stats);
        }
        out.rendered = rendered;
        out.run.dropped = dropped;
        gst_object_unref(sink);
    }
    gst_element_set_state(pipeline, GST_STATE_NULL);
    gst_object_unref(bus);
    gst_object_unref(pipeline);
    out.run.frames = filter.starts_with("identity") ? out.rendered : analysed;
    out.run.fps = wall > 0 ? static_cast<double>(out.run.frames) / wall : 0.0;
    out.run.cpuCores = wall > 0 ? cpu / wall : 0.0;
    return out;
}

// Makes focusmeter known: the build tree's plugin when this is a build tree's bench, else the
// one GStreamer finds installed.
bool findFocusmeter() {
    const std::filesystem::path built =
        std::filesystem::path(INFOCUS_BUILD_ROOT) / "src" / "gstreamer" / "libgstinfocus.so";
    std::error_code ec;
    if (std::filesystem::exists(built, ec)) {
        if (GstPlugin* p = gst_plugin_load_file(built.c_str(), nullptr)) gst_object_unref(p);
    }
    GstElementFactory* f = gst_element_factory_find("focusmeter");
    if (!f) return false;
    gst_object_unref(f);
    return true;
}

#endif

}  // namespace

void benchGstreamer([[maybe_unused]] const BenchOptions& options, const RowSink& sink) {
    for (const char* format : {"GRAY8", "I420"}) {
        BenchRow row;
        row.what = "gstreamer";
        row.width = 1920;
        row.height = 1080;
        row.format = format;
        row.nominalFps = kFps;
        row.baseline = "identity";
#if HAVE_GSTREAMER
        const double seconds = std::min(options.liveSeconds, kMaxSeconds);
        const int frames = std::max(1, static_cast<int>(std::lround(seconds * kFps)));
        // focusmeter as it comes (interval 100 ms), then asked for every frame.
        constexpr int64_t kIntervals[] = {100'000'000, 0};
        static const bool ready = [] {
            gst_init(nullptr, nullptr);
            return findFocusmeter();
        }();
        if (!ready) {
            row.note =
                "focusmeter not found: build with -Dgstreamer=enabled, or install the plugin";
            sink(row);
            continue;
        }
        const PipelineRun base = play(format, "identity", frames);
        for (const int64_t interval : kIntervals) {
            BenchRow r = row;
            r.intervalNs = interval;
            const PipelineRun meter =
                play(format, "focusmeter interval=" + std::to_string(interval), frames);
            if (!meter.error.empty() || !base.error.empty()) {
                r.note = "pipeline failed: " + (meter.error.empty() ? base.error : meter.error);
                sink(r);
                continue;
            }
            r.live = meter.run;
            r.liveBaseline = base.run;
            r.note = "videotestsrc is-live=true, " + std::to_string(frames) +
                     " frames; focusmeter skipped " + std::to_string(meter.skipped) +
                     ", rendered " + std::to_string(meter.rendered) + " (identity " +
                     std::to_string(base.rendered) + ")";
            sink(r);
        }
#else
        row.note = "GStreamer not built in (meson feature gstreamer)";
        sink(row);
#endif
    }
}

}  // namespace infocus::bench
