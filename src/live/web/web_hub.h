// SPDX-License-Identifier: MIT
// The newest state and its encoded preview, shared by every client of the web view: one thread
// follows the pipeline, encodes each new preview once (only while a stream client is connected)
// and wakes the clients, which always take the newest and never queue.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "infocus/live.h"

namespace infocus::web {

/// A preview frame encoded once for all stream clients.
struct EncodedFrame {
    uint64_t frame = 0;  ///< the state's frame
    std::string jpeg;
};

/// One analysed frame as the clients see it.
struct HubSnapshot {
    std::shared_ptr<const LiveState> state;
    std::shared_ptr<const std::string> json;   ///< liveStateJson(*state), made while /events
                                               ///< clients are connected
    std::shared_ptr<const EncodedFrame> jpeg;  ///< the newest encoded preview (may be older)
};

/// The encoder thread and what it publishes.
class FrameHub {
public:
    /// Follows @p pipeline (which must outlive the hub), encoding at @p jpegQuality.
    FrameHub(LiveView& pipeline, int jpegQuality);
    ~FrameHub();
    /// Ends the thread and wakes every waiting client; safe to call twice.
    void stop();
    bool stopping() const { return stopping_.load(); }

    /// Waits up to @p timeout for a snapshot whose state is newer than @p afterState (or whose
    /// preview is newer than @p afterJpeg when set), returning nullopt on time-out or stop.
    std::optional<HubSnapshot> waitNewer(std::optional<uint64_t> afterState,
                                         std::optional<uint64_t> afterJpeg, bool wantJpeg,
                                         std::chrono::milliseconds timeout);
    /// Sleeps @p d or until stop(), whichever comes first.
    void sleepFor(std::chrono::milliseconds d);

    /// Counts clients: encoding and the JSON run only while some want them.
    std::atomic<int> streamClients{0};
    std::atomic<int> eventClients{0};

    /// Encoder cost: CPU seconds of the encoder thread spent encoding, and frames encoded.
    double encodeCpuS() const { return encodeCpuS_.load(); }
    uint64_t framesEncoded() const { return framesEncoded_.load(); }

private:
    void run();

    LiveView& pipeline_;
    const int quality_;
    std::atomic<bool> stopping_{false};
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    HubSnapshot newest_;
    std::atomic<double> encodeCpuS_{0.0};
    std::atomic<uint64_t> framesEncoded_{0};
    std::thread thread_;
};

}  // namespace infocus::web
