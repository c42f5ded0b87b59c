// SPDX-License-Identifier: MIT
// Threads that stay for the life of their owner and run the shares of one task at a time: a
// frame's work spread over the cores without starting threads for every frame.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace infocus {

/// Runs share 0 of a task on the caller and shares 1..n-1 on threads kept between tasks.
class ShareWorkers {
public:
    ShareWorkers() = default;
    ShareWorkers(const ShareWorkers&) = delete;
    ShareWorkers& operator=(const ShareWorkers&) = delete;
    ~ShareWorkers() {
        {
            std::lock_guard lock(mutex_);
            closing_ = true;
        }
        wake_.notify_all();
        for (std::thread& t : threads_)
            t.join();
    }

    /// Calls @p work(share) for every share in 0..@p shares-1, at most one at a time on each
    /// thread, and returns when all have returned. Not reentrant.
    void run(size_t shares, const std::function<void(size_t)>& work) {
        if (shares == 0) return;
        {
            std::lock_guard lock(mutex_);
            while (threads_.size() + 1 < shares) {
                const size_t share = threads_.size() + 1;
                threads_.emplace_back([this, share] { loop(share); });
            }
            work_ = &work;
            active_ = shares;
            pending_ = shares - 1;
            ++generation_;
        }
        wake_.notify_all();
        work(0);
        std::unique_lock lock(mutex_);
        done_.wait(lock, [&] { return pending_ == 0; });
        work_ = nullptr;
    }

private:
    void loop(size_t share) {
        size_t seen = 0;
        std::unique_lock lock(mutex_);
        for (;;) {
            wake_.wait(lock, [&] { return closing_ || generation_ != seen; });
            if (closing_) return;
            seen = generation_;
            if (share >= active_) continue;
            const std::function<void(size_t)>* work = work_;
            lock.unlock();
            (*work)(share);
            lock.lock();
            if (--pending_ == 0) done_.notify_all();
        }
    }

    std::mutex mutex_;
    std::condition_variable wake_, done_;
    std::vector<std::thread> threads_;
    const std::function<void(size_t)>* work_ = nullptr;
    size_t active_ = 0, pending_ = 0, generation_ = 0;
    bool closing_ = false;
};

}  // namespace infocus
