// SPDX-License-Identifier: MIT
// Controls that must run on the live pipeline's capture thread (a lens is moved by the thread
// that reads the camera, so no backend needs to be thread-safe): queued by any thread, run
// between two frames, their result handed back. Private to the live pipeline.
#pragma once

#include <chrono>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>

#include "infocus/error.h"

namespace infocus::live_detail {

/// A queue of controls for the capture thread.
class CommandQueue {
public:
    /// Queues @p fn and waits up to @p timeout for the capture thread to run it. ErrorKind::Io
    /// once the queue is closed; ErrorKind::Device when no frame came in time to run it.
    Status run(std::function<Status()> fn, std::chrono::seconds timeout);
    /// Runs every queued control (the capture thread, between frames).
    void runQueued();
    /// Refuses every queued and later control with "the source has ended".
    void close();

private:
    struct Command {
        std::function<Status()> fn;
        std::promise<Status> done;
    };
    std::mutex mutex_;
    bool closed_ = false;
    std::deque<std::shared_ptr<Command>> commands_;
};

}  // namespace infocus::live_detail
