// SPDX-License-Identifier: MIT
// A camera stream allocates one frame after another of one size. Handed back to the heap, each
// leaves a hole of a frame's size that the heap's trim returns to the system and the next frame
// faults in again: the process's memory swings by a frame and the page faults cost time. Kept
// here instead, a released buffer is the next one taken. The pool holds at most kMaxBuffers
// buffers and kMaxBytes bytes; past either the oldest goes back to the heap.
#include "buffer_pool.h"

#include <algorithm>
#include <deque>
#include <mutex>

namespace infocus::detail {

namespace {

constexpr size_t kMaxBuffers = 8;
constexpr size_t kMaxBytes = size_t{96} << 20;

class BufferPool {
public:
    std::shared_ptr<std::vector<uint8_t>> take(size_t bytes) {
        std::unique_ptr<std::vector<uint8_t>> v;
        {
            std::lock_guard lock(mutex_);
            const auto it = std::find_if(free_.rbegin(), free_.rend(),
                                         [&](const auto& b) { return b->size() == bytes; });
            if (it != free_.rend()) {
                v = std::move(*it);
                free_.erase(std::next(it).base());
                held_ -= bytes;
            }
        }
        if (v)
            std::fill(v->begin(), v->end(), uint8_t{0});
        else
            v = std::make_unique<std::vector<uint8_t>>(bytes, uint8_t{0});
        return {v.release(), [this](std::vector<uint8_t>* p) { give(p); }};
    }

private:
    void give(std::vector<uint8_t>* p) {
        std::unique_ptr<std::vector<uint8_t>> v(p);
        if (v->size() > kMaxBytes) return;
        std::deque<std::unique_ptr<std::vector<uint8_t>>> evicted;  // freed after the lock
        std::lock_guard lock(mutex_);
        held_ += v->size();
        free_.push_back(std::move(v));
        while (free_.size() > kMaxBuffers || held_ > kMaxBytes) {
            held_ -= free_.front()->size();
            evicted.push_back(std::move(free_.front()));
            free_.pop_front();
        }
    }

    std::mutex mutex_;
    std::deque<std::unique_ptr<std::vector<uint8_t>>> free_;
    size_t held_ = 0;
};

// Never destroyed: a frame may be released after static destruction has begun.
BufferPool& pool() {
    static BufferPool* const p = new BufferPool;
    return *p;
}

}  // namespace

std::shared_ptr<std::vector<uint8_t>> pooledBuffer(size_t bytes) {
    return pool().take(bytes);
}

}  // namespace infocus::detail
