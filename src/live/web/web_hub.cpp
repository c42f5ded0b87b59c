// SPDX-License-Identifier: MIT
#include "src/live/web/web_hub.h"

#include <time.h>

#include <cstdio>

#include "infocus/live.h"
#include "src/live/web/web_encode.h"

namespace infocus::web {

namespace {

double threadCpuS() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}

}  // namespace

FrameHub::FrameHub(LiveView& pipeline, int jpegQuality)
    : pipeline_(pipeline), quality_(jpegQuality), thread_([this] { run(); }) {}

FrameHub::~FrameHub() {
    stop();
}

void FrameHub::stop() {
    {
        std::lock_guard lock(mutex_);
        stopping_.store(true);
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
}

void FrameHub::sleepFor(std::chrono::milliseconds d) {
    std::unique_lock lock(mutex_);
    cv_.wait_for(lock, d, [&] { return stopping_.load(); });
}

std::optional<HubSnapshot> FrameHub::waitNewer(std::optional<uint64_t> afterState,
                                               std::optional<uint64_t> afterJpeg, bool wantJpeg,
                                               std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    const auto fresh = [&] {
        if (wantJpeg) return newest_.jpeg && (!afterJpeg || newest_.jpeg->frame > *afterJpeg);
        return newest_.state && (!afterState || newest_.state->frame > *afterState);
    };
    cv_.wait_for(lock, timeout, [&] { return stopping_.load() || fresh(); });
    if (stopping_.load() || !fresh()) return std::nullopt;
    return newest_;
}

void FrameHub::run() {
    std::optional<uint64_t> last;
    while (!stopping_.load()) {
        auto s = pipeline_.waitForState(last, std::chrono::milliseconds(100));
        if (!s) {
            // An ended pipeline answers at once; the hub waits for stop() without spinning.
            if (pipeline_.ended()) sleepFor(std::chrono::milliseconds(100));
            continue;
        }
        last = s->frame;
        std::shared_ptr<const EncodedFrame> jpeg;
        if (streamClients.load() > 0 && s->preview) {
            const double cpu0 = threadCpuS();
            auto encoded = encodeGreyJpeg(*s->preview, quality_);
            encodeCpuS_.store(encodeCpuS_.load() + threadCpuS() - cpu0);
            if (encoded) {
                jpeg = std::make_shared<const EncodedFrame>(EncodedFrame{s->frame, *encoded});
                framesEncoded_.fetch_add(1);
            } else {
                std::fprintf(stderr, "infocus live: web view: %s\n",
                             encoded.error().message.c_str());
            }
        }
        std::shared_ptr<const std::string> json;
        if (eventClients.load() > 0) json = std::make_shared<const std::string>(liveStateJson(*s));
        {
            std::lock_guard lock(mutex_);
            newest_.state = std::move(s);
            newest_.json = std::move(json);
            if (jpeg) newest_.jpeg = std::move(jpeg);
        }
        cv_.notify_all();
    }
}

}  // namespace infocus::web
