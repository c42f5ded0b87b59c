// SPDX-License-Identifier: MIT
#include "src/pipeline/live/command_queue.h"

#include <string>

namespace infocus::live_detail {

Status CommandQueue::run(std::function<Status()> fn, std::chrono::seconds timeout) {
    auto task = std::make_shared<Command>();
    task->fn = std::move(fn);
    auto result = task->done.get_future();
    {
        std::lock_guard lock(mutex_);
        if (closed_) return makeError(ErrorKind::Io, "the source has ended; its lens cannot move");
        commands_.push_back(task);
    }
    if (result.wait_for(timeout) != std::future_status::ready)
        return makeError(ErrorKind::Device, "the camera delivered no frame for " +
                                                std::to_string(timeout.count()) +
                                                " s; the lens was not moved");
    return result.get();
}

void CommandQueue::runQueued() {
    std::deque<std::shared_ptr<Command>> commands;
    {
        std::lock_guard lock(mutex_);
        commands.swap(commands_);
    }
    for (auto& c : commands)
        c->done.set_value(c->fn());
}

void CommandQueue::close() {
    std::deque<std::shared_ptr<Command>> commands;
    {
        std::lock_guard lock(mutex_);
        closed_ = true;
        commands.swap(commands_);
    }
    for (auto& c : commands)
        c->done.set_value(makeError(ErrorKind::Io, "the source has ended"));
}

}  // namespace infocus::live_detail
