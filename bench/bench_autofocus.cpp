// SPDX-License-Identifier: MIT
// Autofocus: frames from the command to "in focus" for the blur-width autofocus, against the
// Raspberry Pi's contrast-detect schedule (libcamera's rpi af.cpp: coarse 1 dpt steps from the far
// end, fine 0.25 dpt steps about the best, early stop below 0.75 × the best contrast, a parabola
// through the best three), on the simulated camera, whose scenes know their true depth.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench/bench.h"
#include "infocus/luma.h"
#include "infocus/metrics.h"
#include "infocus/optics.h"
#include "infocus/sim.h"
#include "infocus/source.h"
#include "src/pipeline/live/autofocus.h"
#include "src/pipeline/live/autofocus_baseline.h"

namespace infocus::bench {

namespace {

using live_detail::SourceTap;

struct Case {
    std::string scene;  // the sim's scene options
    std::string lens;   // focal and f-number options
    double start;       // dioptres
};

struct Outcome {
    int frames = 0;
    double errorDpt = 0.0;
    bool inFocus = false;
};

// The truth: the subject's depths (the middle half, as autofocus takes it) sampled every 8 px; a
// lens holds the subject in focus when it lies within a third of the depth of focus (or 0.02 dpt)
// of their median, or of a surface that fills a third of the subject or more (steps: either
// step the subject straddles), with the blur of that depth inside the circle of confusion.
Outcome judge(const SimRenderer& r, double dpt, int frames) {
    const SimConfig& c = r.config();
    std::vector<double> depths;
    const int w = c.size.width, h = c.size.height;
    for (int y = h / 4; y < 3 * h / 4; y += 8)
        for (int x = w / 4; x < 3 * w / 4; x += 8)
            depths.push_back(1.0 / r.depthAtM(x, y));
    std::sort(depths.begin(), depths.end());
    std::vector<double> truths{depths[depths.size() / 2]};
    for (size_t i = 0; i < depths.size();) {
        size_t j = i;
        while (j < depths.size() && depths[j] == depths[i])
            ++j;
        if (3 * (j - i) >= depths.size()) truths.push_back(depths[i]);
        i = j;
    }
    const double pitch = c.lens.pixelPitchM(w);
    const double cocPx = std::hypot(w, h) / 1500.0;
    Outcome o;
    o.frames = frames;
    o.errorDpt = std::numeric_limits<double>::infinity();
    for (const double truth : truths) {
        const double zs = 1.0 / (1.0 / c.lens.focalLengthM - truth);
        const double dofThird =
            (2.0 / 3.0) * cocPx * pitch / (c.lens.focalLengthM / c.lens.fNumber * zs);
        const double error = std::abs(dpt - truth);
        // The subject's blur with the lens there: the disc of that depth.
        const double zsLens = 1.0 / (1.0 / c.lens.focalLengthM - dpt);
        const double blurPx = c.lens.focalLengthM / c.lens.fNumber * zsLens * error / pitch;
        const bool in = error <= std::max(0.02, dofThird) && blurPx <= cocPx;
        if ((in && !o.inFocus) || (in == o.inFocus && error < o.errorDpt)) {
            o.errorDpt = error;
            o.inFocus = in;
        }
    }
    return o;
}

std::optional<Outcome> runCase(const Case& k, bool baseline) {
    char text[256];
    std::snprintf(text, sizeof text, "sim:%s,%s,focus=%.3fdpt,size=640x360,pace=fast",
                  k.scene.c_str(), k.lens.c_str(), k.start);
    auto spec = parseSourceSpec(text);
    if (!spec) return std::nullopt;
    auto config = parseSimOptions(spec->options);
    if (!config) return std::nullopt;
    auto truth = SimRenderer::create(*config);
    auto source = openSource(*spec);
    if (!truth || !source) return std::nullopt;
    const SourceInfo info = (*source)->info();
    SourceTap tap(std::move(*source));
    if (!tap.start()) return std::nullopt;
    int frames = 0;
    double final = 0;
    if (baseline) {
        const live_detail::ContrastRun run = live_detail::runContrastSchedule(tap, std::nullopt);
        final = run.position;
        frames = run.frames;
    } else {
        live_detail::AfSetup setup;
        if (info.optics) {
            setup.lens = optics::ThinLens{info.optics->focalLengthM, info.optics->fNumber};
            setup.pixelPitchM = info.optics->pixelPitchM;
            setup.cocM = info.optics->sensorDiagonalM / 1500.0;
        }
        std::atomic<bool> stop{false};
        const LiveAutofocus af = live_detail::runAutofocusOnce(tap, setup, {}, stop);
        frames = af.frames;
        auto p = tap.lensPosition();
        final = p ? p->value : 0.0;
    }
    return judge(**truth, final, frames);
}

struct Summary {
    double median = 0, worst = 0, errorWorst = 0;
    int inFocus = 0, runs = 0;
};

Summary summarise(std::vector<Outcome> v) {
    Summary s;
    s.runs = static_cast<int>(v.size());
    if (v.empty()) return s;
    std::vector<int> f;
    for (const Outcome& o : v) {
        f.push_back(o.frames);
        s.errorWorst = std::max(s.errorWorst, o.errorDpt);
        s.inFocus += o.inFocus;
    }
    std::sort(f.begin(), f.end());
    const size_t n = f.size();
    s.median = n % 2 ? f[n / 2] : 0.5 * (f[n / 2 - 1] + f[n / 2]);
    s.worst = f.back();
    return s;
}

}  // namespace

void benchAutofocus(const BenchOptions& options, const RowSink& sink) {
    (void)options;
    const std::vector<std::string> scenes = {"scene=plane,distance=1m",
                                             "scene=tilted,distance=0.8m,tilt=30,axis=x",
                                             "scene=steps,distances=0.5m:0.8m:1.2m:2m"};
    const std::vector<std::string> lenses = {"focal=16mm,fnumber=1.4", "focal=4.74mm,fnumber=1.8"};
    const std::vector<double> starts = {0.1, 1.6, 3.3, 5.0, 6.6, 8.3, 9.9};
    std::vector<Outcome> ours, theirs;
    for (const auto& scene : scenes)
        for (const auto& lens : lenses)
            for (double start : starts) {
                const Case k{scene, lens, start};
                if (auto o = runCase(k, false)) ours.push_back(*o);
                if (auto o = runCase(k, true)) theirs.push_back(*o);
            }
    const Summary a = summarise(ours), b = summarise(theirs);
    BenchRow row{"autofocus", 640, 360, 0.0, std::nullopt, "contrast schedule (rpi af.cpp)", ""};
    AutofocusRun r;
    r.framesMedian = a.median;
    r.framesWorst = a.worst;
    r.errorDptWorst = a.errorWorst;
    r.inFocus = a.inFocus;
    r.runs = a.runs;
    r.baselineFramesMedian = b.median;
    r.baselineFramesWorst = b.worst;
    r.baselineErrorDptWorst = b.errorWorst;
    r.baselineInFocus = b.inFocus;
    row.autofocus = r;
    row.note =
        "sim plane 1 m, tilted 30 deg at 0.8 m, steps 0.5-2 m; 16 mm f/1.4 and 4.74 mm f/1.8; "
        "starts 0.1-9.9 dpt (7); 640x360; the sim's lens: travel 20 ms, settle 10 ms, 2 frames "
        "late; frames from the command to the last one autofocus reads, delay and settle "
        "included";
    sink(row);
}

}  // namespace infocus::bench
