// SPDX-License-Identifier: MIT
// The simulated camera as a FrameSource: its focus control (in dioptres, a lens that travels),
// per-frame noise, pixel formats and real-time pacing.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>
#include <thread>

#include "infocus/sim.h"
#include "infocus/source.h"
#include "infocus/synth.h"
#include "replay/lens_motion.h"
#include "replay/playback.h"
#include "replay/replay_sources.h"
#include "replay/sim/sim_module.h"

namespace infocus::replay {

namespace {

constexpr double kSimMaxDioptres = 10.0;  // closest focus 10 cm, like small camera modules

// Lens control of the simulated camera, in dioptres: a lens that travels and settles, seen
// through a pipeline that delivers each frame some frames after its exposure (lens_motion.h).
// set() comes from the caller's thread while next() renders on the capture thread.
class SimFocus final : public FocusControl {
public:
    SimFocus(double initial, const SimConfig& c)
        : initial_(initial),
          motion_(initial, 0.0, kSimMaxDioptres, {c.lensTravelS, c.lensSettleS, c.delayFrames},
                  c.fps) {}
    FocusRange range() const override {
        return FocusRange{0.0, kSimMaxDioptres, 0.0, initial_, "dioptre"};
    }
    Result<LensPosition> get() override {
        std::lock_guard lock(mutex_);
        const double t = motion_.target();
        return LensPosition{t, "dioptre", t};
    }
    Status set(double value) override {
        if (!std::isfinite(value))
            return makeError(ErrorKind::Usage, "sim: focus value must be a finite number");
        std::lock_guard lock(mutex_);
        motion_.command(std::clamp(value, 0.0, kSimMaxDioptres));
        return {};
    }
    int settleFrames() const override { return framesToSettle(0.0, kSimMaxDioptres); }
    int framesToSettle(double from, double to) const override {
        const auto clamp = [](double v) {
            return std::isfinite(v) ? std::clamp(v, 0.0, kSimMaxDioptres) : 0.0;
        };
        std::lock_guard lock(mutex_);
        return motion_.framesToSettle(clamp(from), clamp(to));
    }

    // The lens position at the exposure of frame @p sequence; frames come in order.
    double forFrame(uint64_t sequence) {
        std::lock_guard lock(mutex_);
        return motion_.positionAt(sequence);
    }
    // Frame @p sequence has been handed to the caller.
    void delivered(uint64_t sequence) {
        std::lock_guard lock(mutex_);
        motion_.delivered(sequence);
    }

private:
    double initial_;
    mutable std::mutex mutex_;
    LensMotion motion_;
};

class SimSource final : public FrameSource {
public:
    SimSource(std::unique_ptr<SimRenderer> renderer, std::string text)
        : renderer_(std::move(renderer)),
          text_(std::move(text)),
          focus_(renderer_->config().focusDioptres, renderer_->config()) {
        const SimConfig& c = renderer_->config();
        // A table of Gaussian samples indexed by a per-frame random stream: cheap per pixel
        // and deterministic for a seed.
        if (c.noise > 0) noise_.emplace(c.noise * 255.0, c.seed ^ 0x5eedull);
    }

    SourceInfo info() const override {
        const SimConfig& c = renderer_->config();
        SourceInfo i;
        i.sourceString = text_;
        i.device = "sim";
        i.driver = "sim";
        i.format = c.format;
        i.size = c.size;
        i.fps = c.fps;
        i.transfer = {TransferFunction::Linear, "the simulated camera renders linear light"};
        if (c.lens.sensorPixelPitchM > 0 && c.size.width > 0) {
            SourceOptics o;
            o.focalLengthM = c.lens.focalLengthM;
            o.fNumber = c.lens.fNumber;
            o.pixelPitchM = c.lens.pixelPitchM(c.size.width);
            o.sensorDiagonalM = o.pixelPitchM * std::hypot(c.size.width, c.size.height);
            i.optics = o;
        }
        return i;
    }
    Status start() override {
        started_ = true;
        wallStart_ = std::chrono::steady_clock::now();
        startSeq_ = sequence_;
        return {};
    }
    Result<Frame> next() override {
        if (!started_) return makeError(ErrorKind::Usage, "sim: next() called before start()");
        const SimConfig& c = renderer_->config();
        const uint64_t seq = sequence_++;
        const double dioptres = focus_.forFrame(seq);
        // Simulated time: the frame's exposure, whatever the machine's speed.
        const double timeS = static_cast<double>(seq) / c.fps;
        const double scale = renderer_->depthScaleAt(timeS);
        if (!cached_ || cachedFocus_ != dioptres || cachedScale_ != scale) {
            cachedImage_ = renderer_->render(dioptres, timeS);
            cachedFocus_ = dioptres;
            cachedScale_ = scale;
            cached_ = true;
        }
        auto frame = allocateFrame(c.format, c.size);
        if (!frame) return frame.error();
        uint64_t state = c.seed * 0x9E3779B97F4A7C15ull + seq * 0xD1B54A32D192ED03ull + 1;
        const bool yuyv = c.format == PixelFormat::YUYV;
        for (int y = 0; y < c.size.height; ++y) {
            const float* in = cachedImage_.row(y);
            uint8_t* out = mutablePlane(*frame, 0) + y * frame->planes[0].stride;
            for (int x = 0; x < c.size.width; ++x) {
                float v = in[x];
                if (noise_) v += noise_->next(state);
                const auto q = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
                if (yuyv) {
                    out[2 * x] = q;
                    out[2 * x + 1] = 128;
                } else {
                    out[x] = q;
                }
            }
        }
        frame->sequence = seq;
        frame->timestampNs = saturatedNs(static_cast<double>(seq) * 1e9 / c.fps);
        frame->lens = LensPosition{dioptres, "dioptre", dioptres};
        if (c.paced) {
            const auto due =
                wallStart_ +
                std::chrono::nanoseconds(static_cast<int64_t>((seq - startSeq_) * 1e9 / c.fps));
            std::this_thread::sleep_until(due);
        }
        ++stats_.delivered;
        focus_.delivered(seq);
        return frame;
    }
    void stop() override { started_ = false; }
    SourceStats stats() const override { return stats_; }
    FocusControl* focusControl() override { return &focus_; }

private:
    std::unique_ptr<SimRenderer> renderer_;
    std::string text_;
    SimFocus focus_;
    std::optional<synth::NoiseTable> noise_;
    bool started_ = false;
    uint64_t sequence_ = 0, startSeq_ = 0;
    std::chrono::steady_clock::time_point wallStart_;
    bool cached_ = false;
    double cachedFocus_ = 0, cachedScale_ = 1;
    Image<float> cachedImage_;
    SourceStats stats_;
};

}  // namespace

Result<std::unique_ptr<FrameSource>> makeSimSource(const SourceSpec& spec) {
    auto config = parseSimOptions(spec.options);
    if (!config) return config.error();
    auto renderer = SimRenderer::create(*config);
    if (!renderer) return renderer.error();
    return std::unique_ptr<FrameSource>(
        std::make_unique<SimSource>(std::move(*renderer), spec.text));
}

}  // namespace infocus::replay
