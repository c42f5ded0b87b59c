// SPDX-License-Identifier: MIT
#include "replay/playback.h"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <thread>

namespace infocus::replay {

const std::set<std::string> kPlaybackKeys = {"pace", "fps", "loop", "start"};

std::optional<double> parseNumber(const std::string& text) {
    if (text.empty()) return std::nullopt;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size() || !std::isfinite(v) || v < 0) return std::nullopt;
    return v;
}

Result<PlaybackOptions> parsePlaybackOptions(const SourceSpec& spec,
                                             const std::set<std::string>& extraKeys) {
    const auto bad = [&](const std::string& why) -> Error {
        return makeError(ErrorKind::Usage, "source '" + spec.text + "': " + why);
    };
    for (const auto& [key, value] : spec.options) {
        if (kPlaybackKeys.count(key) || extraKeys.count(key)) continue;
        std::string valid;
        for (const auto* keys : {&kPlaybackKeys, &extraKeys})
            for (const auto& k : *keys)
                valid += (valid.empty() ? "" : ", ") + k;
        return bad("unknown option '" + key + "'; this source takes: " + valid);
    }
    PlaybackOptions o;
    if (auto it = spec.options.find("fps"); it != spec.options.end()) {
        auto v = parseNumber(it->second);
        if (!v || !(*v >= kMinFps && *v <= kMaxFps))
            return bad("fps=" + it->second + " must be a frame rate from 0.000001 to 1000000");
        o.fps = *v;
        o.pace = PlaybackOptions::Pace::Fps;
    }
    if (auto it = spec.options.find("pace"); it != spec.options.end()) {
        if (it->second == "fast") {
            o.pace = PlaybackOptions::Pace::Fast;
        } else if (it->second == "original") {
            o.pace = PlaybackOptions::Pace::Original;
        } else if (it->second == "fps") {
            if (o.fps <= 0) return bad("pace=fps needs fps=N as well");
            o.pace = PlaybackOptions::Pace::Fps;
        } else {
            return bad("pace=" + it->second + " is not one of original, fast, fps");
        }
    }
    if (auto it = spec.options.find("loop"); it != spec.options.end()) {
        if (it->second != "0" && it->second != "1")
            return bad("loop=" + it->second + " must be 0 or 1");
        o.loop = it->second == "1";
    }
    if (auto it = spec.options.find("start"); it != spec.options.end()) {
        std::string s = it->second;
        const bool seconds = !s.empty() && s.back() == 's';
        if (seconds) s.pop_back();
        auto v = parseNumber(s);
        // Past 2^53 a double holds no exact index, and a cast past size_t's range is undefined
        // (start=1e30 played from frame 0).
        constexpr double kMaxIndex = 9007199254740992.0;
        if (!v || (!seconds && (std::floor(*v) != *v || *v > kMaxIndex)))
            return bad("start=" + it->second +
                       " must be a frame index (start=120) or a time in seconds (start=2.5s)");
        if (seconds)
            o.startS = *v;
        else
            o.startFrame = static_cast<size_t>(*v);
    }
    return o;
}

namespace {

// a + b, or nullopt past the range of int64: timestamps come from files and may be anything.
std::optional<int64_t> checkedAdd(int64_t a, int64_t b) {
    int64_t sum;
    if (__builtin_add_overflow(a, b, &sum)) return std::nullopt;
    return sum;
}

// a - b, or nullopt past the range of int64.
std::optional<int64_t> checkedSub(int64_t a, int64_t b) {
    int64_t difference;
    if (__builtin_sub_overflow(a, b, &difference)) return std::nullopt;
    return difference;
}

class PlaybackSource final : public FrameSource {
public:
    PlaybackSource(std::unique_ptr<FrameReader> reader, PlaybackOptions options, size_t first)
        : reader_(std::move(reader)), options_(options), first_(first), next_(first) {
        info_ = reader_->info();
        if (options_.loop) info_.frameCount.reset();
        if (options_.pace == PlaybackOptions::Pace::Fps) info_.fps = options_.fps;
    }

    SourceInfo info() const override { return info_; }

    Status start() override {
        started_ = true;
        wallStart_ = std::chrono::steady_clock::now();
        delivered_ = 0;
        return {};
    }

    Result<Frame> next() override {
        if (!started_)
            return makeError(ErrorKind::Usage,
                             "source '" + info_.sourceString + "': next() called before start()");
        while (true) {
            if (next_ >= reader_->count()) {
                if (auto s = atEnd(); !s) return s.error();
                continue;
            }
            const size_t i = next_++;
            auto frame = reader_->read(i);
            if (!frame) {
                if (frame.error().kind == ErrorKind::EndOfStream) {
                    // A video shorter than its container claimed: its real end is here.
                    truncatedCount_ = i;
                    next_ = reader_->count();
                    continue;
                }
                ++stats_.errors;
                return frame.error();
            }
            if (auto s = adjust(*frame, i); !s) return s.error();
            if (auto s = pace(*frame, i); !s) return s.error();
            ++stats_.delivered;
            ++delivered_;
            return std::move(*frame);
        }
    }

    void stop() override { started_ = false; }
    SourceStats stats() const override { return stats_; }

private:
    size_t effectiveCount() const { return truncatedCount_ ? *truncatedCount_ : reader_->count(); }

    // Handles the end of the sequence: the trailing error once, then a loop or the end.
    Status atEnd() {
        if (!trailingReported_) {
            trailingReported_ = true;
            if (auto e = reader_->trailingError()) {
                ++stats_.errors;
                return *e;
            }
        }
        const size_t n = effectiveCount();
        if (!options_.loop || n == 0)
            return makeError(ErrorKind::EndOfStream, "end of " + info_.sourceString);
        // Shift the next pass by the span of this one plus one frame interval, so timestamps
        // and sequence numbers keep increasing across the loop.
        // Timestamps near the ends of int64 would wrap: the loop ends there with a message.
        const auto span = checkedSub(reader_->timestampNs(n - 1), reader_->timestampNs(first_));
        int64_t interval = 0;
        if (span && n - first_ > 1)
            interval = *span / static_cast<int64_t>(n - 1 - first_);
        else if (span)
            interval = saturatedNs(1e9 / (info_.fps > 0 ? info_.fps : 30.0));
        const auto step = span ? checkedAdd(*span, interval) : std::nullopt;
        const auto offset = step ? checkedAdd(tsOffset_, *step) : std::nullopt;
        if (!offset) return loopOverflow(n - 1);
        tsOffset_ = *offset;
        seqOffset_ += lastSeqInPass_ + 1 - firstSeqInPass_.value_or(0);
        firstSeqInPass_.reset();
        prevSeq_.reset();
        next_ = first_;
        return {};
    }

    // The error that ends a loop whose timestamps would pass int64 after frame @p i.
    Error loopOverflow(size_t i) const {
        return makeError(ErrorKind::Unsupported,
                         "source '" + info_.sourceString + "': loop=1 cannot go on after frame " +
                             std::to_string(i) +
                             ": the next pass's timestamps would pass the largest time a "
                             "timestamp holds (2^63 ns, about 292 years); replay it without "
                             "loop=1, or re-record it with ordinary timestamps");
    }

    Status adjust(Frame& f, size_t i) {
        const auto ts = checkedAdd(f.timestampNs, tsOffset_);
        if (!ts) return loopOverflow(i);
        if (!firstSeqInPass_) firstSeqInPass_ = f.sequence;
        lastSeqInPass_ = f.sequence;
        if (prevSeq_ && f.sequence > *prevSeq_ + 1) stats_.dropped += f.sequence - *prevSeq_ - 1;
        prevSeq_ = f.sequence;
        f.sequence += seqOffset_;
        f.timestampNs = *ts;
        return {};
    }

    Status pace(const Frame& f, size_t i) {
        using namespace std::chrono;
        int64_t dueNs = 0;  // since wallStart_
        switch (options_.pace) {
            case PlaybackOptions::Pace::Fast:
                return {};
            case PlaybackOptions::Pace::Original: {
                if (!firstTs_) firstTs_ = f.timestampNs;
                const auto d = checkedSub(f.timestampNs, *firstTs_);
                // Far before the first frame is simply due now; far after it, never.
                if (!d && f.timestampNs < *firstTs_) return {};
                if (!d)
                    return makeError(
                        ErrorKind::Unsupported,
                        "source '" + info_.sourceString +
                            "': pace=original cannot wait for frame " + std::to_string(i) +
                            ": its timestamp is further from the first frame's than 2^63 ns "
                            "(about 292 years); replay it with pace=fast or fps=N");
                dueNs = *d;
                break;
            }
            case PlaybackOptions::Pace::Fps:
                dueNs = saturatedNs(static_cast<double>(delivered_) * 1e9 / options_.fps);
                break;
        }
        // A relative sleep: wallStart_ plus a due time near 2^63 ns would wrap the clock.
        if (dueNs <= 0) return {};
        const nanoseconds elapsed = duration_cast<nanoseconds>(steady_clock::now() - wallStart_);
        if (elapsed.count() < dueNs) std::this_thread::sleep_for(nanoseconds(dueNs) - elapsed);
        return {};
    }

    std::unique_ptr<FrameReader> reader_;
    PlaybackOptions options_;
    SourceInfo info_;
    size_t first_ = 0;
    size_t next_ = 0;
    std::optional<size_t> truncatedCount_;
    bool started_ = false;
    bool trailingReported_ = false;
    std::chrono::steady_clock::time_point wallStart_;
    uint64_t delivered_ = 0;
    std::optional<int64_t> firstTs_;
    int64_t tsOffset_ = 0;
    uint64_t seqOffset_ = 0;
    std::optional<uint64_t> firstSeqInPass_;
    uint64_t lastSeqInPass_ = 0;
    std::optional<uint64_t> prevSeq_;
    SourceStats stats_;
};

}  // namespace

Result<std::unique_ptr<FrameSource>> makePlayback(std::unique_ptr<FrameReader> reader,
                                                  const PlaybackOptions& options) {
    const SourceInfo info = reader->info();
    const size_t n = reader->count();
    if (n == 0) {
        if (auto e = reader->trailingError()) return *e;
        return makeError(ErrorKind::NotFound,
                         "source '" + info.sourceString + "' holds no frames to play");
    }
    size_t first = 0;
    if (options.startFrame) {
        if (*options.startFrame >= n)
            return makeError(ErrorKind::Usage,
                             "source '" + info.sourceString +
                                 "': start=" + std::to_string(*options.startFrame) +
                                 " is beyond its last frame (" + std::to_string(n - 1) + ")");
        first = *options.startFrame;
    } else if (options.startS) {
        const int64_t t0 = reader->timestampNs(0);
        // Two int64 timestamps lie up to 2^64 - 1 ns apart, exact in __int128; a start further
        // than that is beyond every frame.
        const double targetNs = std::round(*options.startS * 1e9);
        if (targetNs >= 18446744073709551616.0) {
            first = n;
        } else {
            const auto target = static_cast<__int128>(targetNs);
            while (first < n && __int128{reader->timestampNs(first)} - t0 < target)
                ++first;
        }
        if (first >= n) {
            char text[96];
            std::snprintf(
                text, sizeof text, "start=%gs is beyond its last frame (%.3f s)", *options.startS,
                (static_cast<double>(reader->timestampNs(n - 1)) - static_cast<double>(t0)) / 1e9);
            return makeError(ErrorKind::Usage, "source '" + info.sourceString + "': " + text);
        }
    }
    return std::unique_ptr<FrameSource>(
        std::make_unique<PlaybackSource>(std::move(reader), options, first));
}

}  // namespace infocus::replay
