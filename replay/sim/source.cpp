// SPDX-License-Identifier: MIT
// The simulated camera as a FrameSource: its focus control (in dioptres, one settle frame),
// per-frame noise, pixel formats and real-time pacing.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <thread>

#include "infocus/sim.h"
#include "infocus/source.h"
#include "infocus/synth.h"
#include "replay/playback.h"
#include "replay/replay_sources.h"
#include "replay/sim/sim_module.h"

namespace infocus::replay {

namespace {

constexpr double kSimMaxDioptres = 10.0;  // closest focus 10 cm, like small camera modules

// Lens control of the simulated camera, in dioptres. A move shows from the second frame after
// it (one settle frame, as a real lens needs time to move).
class SimFocus final : public FocusControl {
public:
    explicit SimFocus(double initial) : target_(initial), current_(initial) {}
    FocusRange range() const override {
        return FocusRange{0.0, kSimMaxDioptres, 0.0, initial(), "dioptre"};
    }
    Result<LensPosition> get() override { return LensPosition{target_, "dioptre", target_}; }
    Status set(double value) override {
        if (!std::isfinite(value))
            return makeError(ErrorKind::Usage, "sim: focus value must be a finite number");
        target_ = std::clamp(value, 0.0, kSimMaxDioptres);
        applyAt_ = nextSequence_ + 1;
        return {};
    }
    int settleFrames() const override { return 1; }

    // The focus for the frame numbered @p sequence; called once per frame in order.
    double forFrame(uint64_t sequence) {
        if (sequence >= applyAt_) current_ = target_;
        nextSequence_ = sequence + 1;
        return current_;
    }
    double initial() const { return initial_; }
    void setInitial(double v) { initial_ = v; }

private:
    double target_, current_, initial_ = 0;
    uint64_t applyAt_ = 0, nextSequence_ = 0;
};

class SimSource final : public FrameSource {
public:
    SimSource(std::unique_ptr<SimRenderer> renderer, std::string text)
        : renderer_(std::move(renderer)),
          text_(std::move(text)),
          focus_(renderer_->config().focusDioptres) {
        focus_.setInitial(renderer_->config().focusDioptres);
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
        if (!cached_ || cachedFocus_ != dioptres) {
            cachedImage_ = renderer_->render(dioptres);
            cachedFocus_ = dioptres;
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
    double cachedFocus_ = 0;
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
