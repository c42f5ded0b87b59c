// SPDX-License-Identifier: MIT
// The live pipeline end to end: a recording replayed at its own pace (`DIR,pace=original,loop=1`)
// through LivePipeline as `infocus live` runs it, beside the same pipeline with an OpenCV
// composition in place of infocus's measurement (live_detail::openMeasuredBy); and the web
// view's cost: the same pipeline with 4 in-process clients of /stream.mjpg and /events.
#include <stdlib.h>
#include <sys/resource.h>
#include <time.h>
#include <turbojpeg.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <memory>
#include <thread>

#include "bench/bench.h"
#include "infocus/frame.h"
#include "infocus/live.h"
#include "infocus/recording.h"
#include "infocus/synth.h"
#include "infocus_config.h"
#include "src/pipeline/live/measure_hook.h"
#if HAVE_WEB
#include <httplib.h>

#include "src/live/web/web.h"
#include "src/live/web/web_encode.h"
#endif

namespace infocus::bench {

namespace {

using Clock = std::chrono::steady_clock;
using MeasureFn = live_detail::MeasureOverride;

// The first frame's timestamp in the recordings: far from CLOCK_MONOTONIC's present, so the
// pipeline counts latency from each frame's arrival, as it does for any recording.
constexpr int64_t kFirstTimestampNs = 1'000'000'000;
// The peaking mask's share of edge pixels left unmarked, as the live view's percentile peaking.
constexpr double kPeakingPercentile = 0.97;
// The preview a face showing the picture asks for (the web view's and the window's size).
constexpr int kPreviewLongSide = 640;
// A run lasts its seconds and until this many states were seen, but no more than kMaxExtraS
// seconds longer.
constexpr size_t kMinStates = 3;
constexpr double kMaxExtraS = 30.0;

struct LiveCase {
    int width, height;
    double fps;
    PixelFormat format;
};

// A natural-like texture (dead leaves) with a few slanted squares, @p panPx wider than the frame
// so each frame can show it moved by a pixel: frames differ as a camera's do, and the blur
// tracker has edges to follow. Blurred by a 3 px disc (near focus), 1 grey level of noise.
Image<uint8_t> makeScene(int w, int h) {
    synth::SharpCanvas canvas = synth::makeCanvas(w, h, 1);
    synth::paintDeadLeaves(canvas, 2024, 4.0, 120.0 * h / 1080.0);
    for (int i = 0; i < 12; ++i)
        synth::paint(canvas,
                     synth::squareScene(w * (0.1 + 0.07 * i), h * (0.2 + 0.12 * (i % 5)),
                                        90.0 * h / 1080.0, 5.0 + 7.0 * i, i % 2 ? 30.0f : 220.0f));
    return synth::toLuma8(synth::renderSharp(canvas, {synth::Psf::disc(3.0), 1, 1.0, 7}).pixels);
}

// Frame @p i: the scene's columns x0..x0+w-1, as YUYV (neutral chroma) or as a 4:2:2 q85 JPEG
// of the same picture, as a webcam sends.
Result<Frame> makeFrame(const Image<uint8_t>& scene, int x0, const LiveCase& c, tjhandle tj) {
    const Size size{c.width, c.height};
    if (c.format == PixelFormat::MJPEG) {
        const cv::Mat grey(c.height, c.width, CV_8U, const_cast<uint8_t*>(scene.row(0) + x0),
                           static_cast<size_t>(scene.width()));
        cv::Mat bgr;
        cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
        unsigned char* out = nullptr;
        unsigned long bytes = 0;
        if (tjCompress2(tj, bgr.data, c.width, static_cast<int>(bgr.step), c.height, TJPF_BGR, &out,
                        &bytes, TJSAMP_422, 85, 0) != 0)
            return makeError(ErrorKind::Io, std::string("JPEG encoding of a bench frame failed: ") +
                                                tjGetErrorStr2(tj));
        Frame f = makeCompressedFrame(PixelFormat::MJPEG, size, out, bytes);
        tjFree(out);
        return f;
    }
    auto frame = allocateFrame(PixelFormat::YUYV, size);
    if (!frame) return frame.error();
    for (int y = 0; y < c.height; ++y) {
        const uint8_t* in = scene.row(y) + x0;
        uint8_t* out = mutablePlane(*frame, 0) + y * frame->planes[0].stride;
        for (int x = 0; x < c.width; ++x) {
            out[2 * x] = in[x];
            out[2 * x + 1] = 128;
        }
    }
    return frame;
}

// Writes one second of @p c (one frame a pixel further along the pan, timestamps at the
// nominal interval, sequence numbers consecutive), or @p seconds when shorter, into @p dir.
Status writeRecording(const std::string& dir, const LiveCase& c, double seconds) {
    const int n = std::max(2, static_cast<int>(c.fps * std::min(1.0, seconds)));
    const int64_t intervalNs = static_cast<int64_t>(1e9 / c.fps + 0.5);
    const Image<uint8_t> scene = makeScene(c.width + n, c.height);
    SourceInfo info;
    info.sourceString = "infocus bench";
    info.driver = "bench";
    info.format = c.format;
    info.size = {c.width, c.height};
    info.fps = c.fps;
    auto writer = RecordingWriter::create(dir, makeRecordingHeader(info, nullptr));
    if (!writer) return writer.error();
    tjhandle tj = tjInitCompress();
    Status st;
    for (int i = 0; i < n && st; ++i) {
        auto frame = makeFrame(scene, i, c, tj);
        if (!frame) {
            st = frame.error();
            break;
        }
        frame->timestampNs = kFirstTimestampNs + i * intervalNs;
        frame->sequence = static_cast<uint64_t>(i);
        st = (*writer)->append(*frame);
    }
    tjDestroy(tj);
    if (!st) return st;
    return (*writer)->close();
}

double cpuSeconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
}

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    const auto k = std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())));
    std::nth_element(v.begin(), v.begin() + static_cast<ptrdiff_t>(k), v.end());
    return v[k];
}

// The OpenCV composition a focus tool would write: Laplacian variance per region
// (cv::Laplacian + cv::meanStdDev) and a peaking mask from the Sobel gradient's strongest
// edges, on the luma the pipeline hands over. Its buffers live as long as the pipeline.
MeasureFn opencvMeasure() {
    struct Buffers {
        cv::Mat lap, dx, dy, ax, ay, mag, mask;
    };
    auto b = std::make_shared<Buffers>();
    return [b](const Luma8& luma, std::span<const Rect> regions, std::vector<double>& scores) {
        const cv::Mat grey(luma.height, luma.width, CV_8U, const_cast<uint8_t*>(luma.data),
                           static_cast<size_t>(luma.stride));
        cv::Laplacian(grey, b->lap, CV_16S);
        for (size_t i = 0; i < regions.size(); ++i) {
            const Rect& r = regions[i];
            cv::Scalar mean, stddev;
            cv::meanStdDev(b->lap(cv::Rect(r.x, r.y, r.w, r.h)), mean, stddev);
            scores[i] = stddev[0] * stddev[0];
        }
        cv::Sobel(grey, b->dx, CV_16S, 1, 0);
        cv::Sobel(grey, b->dy, CV_16S, 0, 1);
        cv::convertScaleAbs(b->dx, b->ax);
        cv::convertScaleAbs(b->dy, b->ay);
        cv::add(b->ax, b->ay, b->mag);
        const int bins = 256;
        const float range[] = {0, 256};
        const float* ranges[] = {range};
        cv::Mat hist;
        cv::calcHist(&b->mag, 1, nullptr, cv::Mat(), hist, 1, &bins, ranges);
        const double wanted = kPeakingPercentile * static_cast<double>(b->mag.total());
        double seen = 0;
        int level = 0;
        while (level < 255 && (seen += hist.at<float>(level)) < wanted)
            ++level;
        cv::threshold(b->mag, b->mask, level, 255, cv::THRESH_BINARY);
    };
}

// What runs beside the pipeline during a run: started once the pipeline is, stopped before it.
struct RunBeside {
    std::function<Status(LivePipeline&)> start;
    std::function<void()> stop;
};

// Replays @p dir through the live pipeline for @p seconds and watches every state.
Result<LiveRun> runLive(const std::string& dir, double seconds, MeasureFn measure,
                        int previewLongSide = kPreviewLongSide, const RunBeside& beside = {}) {
    LiveOptions options;
    options.peaking = PeakingMode::Percentile;
    options.peakingPercentile = kPeakingPercentile;
    options.previewLongSide = previewLongSide;
    auto pipeline =
        live_detail::openMeasuredBy(dir + ",pace=original,loop=1", options, std::move(measure));
    if (!pipeline) return pipeline.error();
    LivePipeline& p = **pipeline;

    const double cpu0 = cpuSeconds();
    // The source's clock starts inside start(): each frame is due at start + (its timestamp −
    // the first's), and a camera would have captured it then.
    const auto t0 = Clock::now();
    if (Status st = p.start(); !st) return st.error();
    if (beside.start)
        if (Status st = beside.start(p); !st) {
            p.stop();
            return st.error();
        }
    std::vector<double> latencies;
    LiveStageTimes stages;  // sums over the states seen
    std::shared_ptr<const LiveState> last;
    // A short run on a busy machine still waits for a few states, within a bound.
    const auto enough = [&] {
        const auto ran = Clock::now() - t0;
        return (ran >= std::chrono::duration<double>(seconds) && latencies.size() >= kMinStates) ||
               ran >= std::chrono::duration<double>(seconds + kMaxExtraS);
    };
    while (!enough()) {
        auto s = p.waitForState(last ? std::optional<uint64_t>(last->frame) : std::nullopt,
                                std::chrono::milliseconds(500));
        const auto now = Clock::now();
        if (!s) {
            if (p.ended()) break;
            continue;
        }
        const auto due = t0 + std::chrono::nanoseconds(s->timestampNs - kFirstTimestampNs);
        latencies.push_back(std::chrono::duration<double, std::milli>(now - due).count());
        const LiveStageTimes& st = s->stages;
        for (auto [sum, v] : {std::pair{&stages.captureS, st.captureS},
                              {&stages.lumaS, st.lumaS},
                              {&stages.noiseS, st.noiseS},
                              {&stages.sharpnessS, st.sharpnessS},
                              {&stages.blurS, st.blurS},
                              {&stages.stateS, st.stateS},
                              {&stages.picturesS, st.picturesS},
                              {&stages.publishS, st.publishS}})
            *sum += v;
        last = std::move(s);
    }
    const auto tEnd = Clock::now();
    if (beside.stop) beside.stop();
    p.stop();
    const auto t1 = Clock::now();
    const double cpu1 = cpuSeconds();
    if (!last) {
        Status end = p.endStatus();
        if (!end) return end.error();
        return makeError(ErrorKind::Io, "the live pipeline analysed no frame of " + dir);
    }
    LiveRun run;
    run.frames = last->frame + 1;
    run.fps = static_cast<double>(run.frames) / std::chrono::duration<double>(tEnd - t0).count();
    run.dropped = last->dropped + last->skipped;
    run.latencyP50Ms = percentile(latencies, 0.5);
    run.latencyP99Ms = percentile(latencies, 0.99);
    run.cpuCores = (cpu1 - cpu0) / std::chrono::duration<double>(t1 - t0).count();
    const double n = static_cast<double>(latencies.size());
    for (double* v : {&stages.captureS, &stages.lumaS, &stages.noiseS, &stages.sharpnessS,
                      &stages.blurS, &stages.stateS, &stages.picturesS, &stages.publishS})
        *v /= n;
    run.stages = stages;
    return run;
}

#if HAVE_WEB
double threadCpuS() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}

// In-process clients of the web view: each reads /stream.mjpg and /events for the whole run and
// counts what arrives (parts by their X-Frame header, events by their id line).
class WebClients {
public:
    Status start(LivePipeline& p, int clients) {
        WebOptions o;
        o.listen = "127.0.0.1:0";
        auto server = WebServer::start(p, o);
        if (!server) return server.error();
        server_ = std::move(*server);
        counts_ = std::vector<Count>(static_cast<size_t>(2 * clients));
        t0_ = Clock::now();
        for (int i = 0; i < 2 * clients; ++i)
            threads_.emplace_back([this, i] {
                const bool stream = i % 2 == 0;
                read(stream ? "/stream.mjpg" : "/events",
                     stream ? "X-Frame: " : "id: ", counts_[static_cast<size_t>(i)]);
            });
        return {};
    }

    void stop() {
        done_.store(true);
        for (std::thread& t : threads_)
            t.join();
        seconds_ = std::chrono::duration<double>(Clock::now() - t0_).count();
        server_->stop();
    }

    // Per-client rates over the run: stream parts a second, events a second, all bytes as Mbit/s.
    std::vector<double> streamFps() const { return rates(0); }
    std::vector<double> eventsPerS() const { return rates(1); }
    double mbitPerS() const {
        uint64_t bytes = 0;
        for (const Count& c : counts_)
            bytes += c.bytes;
        return seconds_ > 0 ? static_cast<double>(bytes) * 8e-6 / seconds_ : 0.0;
    }

private:
    struct Count {
        uint64_t items = 0, bytes = 0;
    };

    void read(const char* path, const std::string& marker, Count& count) {
        httplib::Client client("127.0.0.1", server_->port());
        client.set_read_timeout(5, 0);
        std::string tail;  // a marker may straddle two reads
        client.Get(path, [&](const char* data, size_t length) {
            count.bytes += length;
            std::string text = tail + std::string(data, length);
            for (size_t at = text.find(marker); at != std::string::npos;
                 at = text.find(marker, at + marker.size()))
                ++count.items;
            tail = text.substr(text.size() - std::min(text.size(), marker.size() - 1));
            return !done_.load();
        });
    }

    std::vector<double> rates(size_t first) const {
        std::vector<double> r;
        for (size_t i = first; i < counts_.size(); i += 2)
            r.push_back(seconds_ > 0 ? static_cast<double>(counts_[i].items) / seconds_ : 0.0);
        return r;
    }

    std::unique_ptr<WebServer> server_;
    std::vector<Count> counts_;
    std::vector<std::thread> threads_;
    std::atomic<bool> done_{false};
    Clock::time_point t0_;
    double seconds_ = 0.0;
};

// The web view's row: a 1080p30 recording at its pace, without clients and then with 4 clients
// of /stream.mjpg and /events, and the preview's JPEG encode cost at 960x540 (ms is that encode).
void benchLiveWeb(const BenchOptions& options, const RowSink& sink) {
    const LiveCase c{1920, 1080, 30.0, PixelFormat::YUYV};
    constexpr int kWebPreview = 960;
    constexpr int kClients = 4;
    BenchRow row{"live_web", c.width, c.height, 0.0, std::nullopt, "", ""};
    char text[640];
    // The encode: one core's CPU seconds per frame, times 30 frames a second.
    const Image<uint8_t> preview = makeScene(kWebPreview, kWebPreview * 9 / 16);
    int encoded = 0;
    const double cpu0 = threadCpuS();
    const auto w0 = Clock::now();
    while (std::chrono::duration<double>(Clock::now() - w0).count() <
               std::max(0.2, options.secondsPerCase) ||
           encoded < 10) {
        if (!web::encodeGreyJpeg(preview, WebOptions{}.jpegQuality)) break;
        ++encoded;
    }
    const double encodeS = (threadCpuS() - cpu0) / std::max(1, encoded);
    row.ms = encodeS * 1e3;

    namespace fs = std::filesystem;
    std::string tmpl = (fs::temp_directory_path() / "infocus-bench-web-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) {
        row.note = "could not make a temporary directory in " + fs::temp_directory_path().string();
        sink(row);
        return;
    }
    const std::string rec = tmpl + "/rec";
    std::string failed;
    std::optional<LiveRun> quiet, loaded;
    WebClients clients;
    if (Status st = writeRecording(rec, c, options.liveSeconds); !st) {
        failed = "recording: " + st.error().message;
    } else {
        auto q = runLive(rec, options.liveSeconds, {}, kWebPreview);
        const RunBeside beside{[&](LivePipeline& p) { return clients.start(p, kClients); },
                               [&] { clients.stop(); }};
        auto l = runLive(rec, options.liveSeconds, {}, kWebPreview, beside);
        if (q) quiet = *q;
        if (l) loaded = *l;
        if (!q) failed = q.error().message;
        if (!l) failed = l.error().message;
    }
    std::error_code ec;
    fs::remove_all(tmpl, ec);
    if (!failed.empty() || !quiet || !loaded) {
        row.note = "failed: " + failed;
        sink(row);
        return;
    }
    const auto list = [](const std::vector<double>& v) {
        std::string out;
        char one[16];
        for (double x : v) {
            std::snprintf(one, sizeof one, "%s%.1f", out.empty() ? "" : "/", x);
            out += one;
        }
        return out;
    };
    std::snprintf(
        text, sizeof text,
        "ms: JPEG q80 of a %dx%d preview, %.3f core at 30 fps (target <= 0.25); 1080p30 YUYV "
        "at its pace, %g s each, %d px preview: no clients %.1f fps, %llu dropped, %.2f cores; "
        "%d clients of /stream.mjpg and /events %.1f fps, %llu dropped, %.2f cores, stream fps "
        "%s, events/s %s, %.1f Mbit/s in all",
        kWebPreview, kWebPreview * 9 / 16, encodeS * 30.0, options.liveSeconds, kWebPreview,
        quiet->fps, static_cast<unsigned long long>(quiet->dropped), quiet->cpuCores, kClients,
        loaded->fps, static_cast<unsigned long long>(loaded->dropped), loaded->cpuCores,
        list(clients.streamFps()).c_str(), list(clients.eventsPerS()).c_str(), clients.mbitPerS());
    row.note = text;
    row.live = loaded;
    row.liveBaseline = quiet;
    sink(row);
}
#else
// Without the web view there is no row: nothing of it can be measured.
void benchLiveWeb(const BenchOptions&, const RowSink&) {}
#endif

}  // namespace

std::string liveBaselineName() {
    return "the same pipeline, cv::Laplacian + cv::meanStdDev per region and a cv::Sobel peaking "
           "mask";
}

void benchLive(const BenchOptions& options, const RowSink& sink) {
    const LiveCase cases[] = {
        {1920, 1080, 60.0, PixelFormat::YUYV},
        {1920, 1080, 30.0, PixelFormat::MJPEG},
        {3840, 2160, 30.0, PixelFormat::YUYV},
    };
    namespace fs = std::filesystem;
    for (const LiveCase& c : cases) {
        BenchRow row{"live", c.width, c.height, 0.0, std::nullopt, liveBaselineName(), ""};
        row.format = c.format == PixelFormat::MJPEG ? "MJPEG" : "YUYV";
        row.nominalFps = c.fps;
        std::string tmpl = (fs::temp_directory_path() / "infocus-bench-live-XXXXXX").string();
        if (!mkdtemp(tmpl.data())) {
            row.note =
                "could not make a temporary directory in " + fs::temp_directory_path().string();
            sink(row);
            continue;
        }
        const std::string dir = tmpl;
        const std::string rec = dir + "/rec";
        std::string failed;
        if (Status st = writeRecording(rec, c, options.liveSeconds); !st) {
            failed = "recording: " + st.error().message;
        } else {
            auto ours = runLive(rec, options.liveSeconds, {});
            auto base = runLive(rec, options.liveSeconds, opencvMeasure());
            if (ours) row.live = *ours;
            if (base) row.liveBaseline = *base;
            if (!ours) failed = ours.error().message;
            if (!base) failed = base.error().message;
        }
        std::error_code ec;
        fs::remove_all(dir, ec);
        char note[400];
        const LiveStageTimes st = row.live ? row.live->stages : LiveStageTimes{};
        std::snprintf(note, sizeof note,
                      "%g s each, 16x9 grid, percentile peaking, %d px preview; latency from "
                      "a frame's due time to its state; infocus's ms a frame: capture %.2f "
                      "(CPU), luma %.2f, noise %.2f, sharpness %.2f, blur %.2f, state %.2f, "
                      "preview+peaking %.2f, publish %.3f",
                      options.liveSeconds, kPreviewLongSide, st.captureS * 1e3, st.lumaS * 1e3,
                      st.noiseS * 1e3, st.sharpnessS * 1e3, st.blurS * 1e3, st.stateS * 1e3,
                      st.picturesS * 1e3, st.publishS * 1e3);
        row.note = failed.empty() ? note : "failed: " + failed;
        sink(row);
    }
    benchLiveWeb(options, sink);
}

}  // namespace infocus::bench
