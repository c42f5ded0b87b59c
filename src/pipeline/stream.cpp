// SPDX-License-Identifier: MIT
// The stream loop: measurement (src/metrics) never opens a source; this is where the two meet.
// Frames of files and recordings may be measured several at once; they are handed on in order.
#include <algorithm>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "infocus/pipeline.h"
#include "infocus/source.h"

namespace infocus {

AnalysisOptions resolveForSource(const AnalysisOptions& options, const SourceInfo& info) {
    AnalysisOptions used = options;
    if (options.trackLiveCamera && info.liveCamera) {
        const LiveBlurSearch search = liveBlurSearch(info.fps);
        used.blurSearchesPerFrame = search.searchesPerFrame;
        used.blurSearchBudgetS = search.budgetS;
    }
    if (options.transferFromSource && info.transfer.curve) used.transfer = *info.transfer.curve;
    return used;
}

namespace {

// What both loops hand their frames to.
struct Sinks {
    const FrameAnalysisSink& sink;
    const DamageSink& onDamaged;
    const ProgressSink& progress;
    uint64_t total = 0;  // frames expected, 0 when unknown
};

// One frame at a time: live cameras, tracked blur, and --jobs 1.
Status runSequential(FrameSource& s, Analyzer& analyzer, uint64_t maxFrames, const Sinks& out) {
    for (uint64_t i = 0; maxFrames == 0 || i < maxFrames; ++i) {
        auto frame = s.next();
        if (!frame && frame.error().kind == ErrorKind::Corrupt) {
            // One damaged frame (torn record, bad JPEG) must not cost the intact ones after it.
            if (out.onDamaged) out.onDamaged(frame.error());
            --i;
            continue;
        }
        if (!frame) {
            if (frame.error().kind != ErrorKind::EndOfStream) return frame.error();
            return {};
        }
        auto a = analyzer.analyze(*frame, i);
        if (!a && a.error().kind == ErrorKind::Corrupt) {
            if (out.onDamaged) out.onDamaged(a.error());
            --i;
            continue;
        }
        if (!a) return a.error();
        if (auto st = out.sink(*a, *frame); !st) return st;
        if (out.progress) out.progress(i + 1, out.total);
    }
    return {};
}

// A frame read and waiting for (or holding) its analysis.
struct Slot {
    Frame frame;
    std::optional<Result<FrameAnalysis>> result;  // set by a worker
};

// Several frames at a time: the calling thread reads frames and hands results on in read order;
// each worker measures the oldest frame not yet taken with its own analyser. At most two
// frames a job are held, so memory stays bounded on long recordings.
Status runParallel(FrameSource& s, std::vector<std::unique_ptr<Analyzer>>& analyzers,
                   uint64_t maxFrames, const Sinks& out) {
    std::mutex mutex;
    std::condition_variable workReady, resultReady;
    std::deque<std::shared_ptr<Slot>> window, todo;
    bool stopping = false;
    const auto worker = [&](Analyzer& analyzer) {
        for (;;) {
            std::shared_ptr<Slot> slot;
            {
                std::unique_lock lock(mutex);
                workReady.wait(lock, [&] { return stopping || !todo.empty(); });
                if (todo.empty()) return;
                slot = std::move(todo.front());
                todo.pop_front();
            }
            auto a = analyzer.analyze(slot->frame, 0);  // numbered when handed on
            std::lock_guard lock(mutex);
            slot->result = std::move(a);
            resultReady.notify_all();
        }
    };
    std::vector<std::thread> pool;
    for (auto& a : analyzers)
        pool.emplace_back(worker, std::ref(*a));

    const size_t depth = 2 * analyzers.size();
    uint64_t delivered = 0;
    bool ended = false;
    std::optional<Error> sourceError;
    Status result;
    for (;;) {
        while (!ended && window.size() < depth &&
               (maxFrames == 0 || delivered + window.size() < maxFrames)) {
            auto frame = s.next();
            if (!frame && frame.error().kind == ErrorKind::Corrupt) {
                if (out.onDamaged) out.onDamaged(frame.error());
                continue;
            }
            if (!frame) {
                if (frame.error().kind != ErrorKind::EndOfStream) sourceError = frame.error();
                ended = true;
                break;
            }
            auto slot = std::make_shared<Slot>();
            slot->frame = std::move(*frame);
            std::lock_guard lock(mutex);
            window.push_back(slot);
            todo.push_back(std::move(slot));
            workReady.notify_one();
        }
        if (window.empty()) break;
        std::shared_ptr<Slot> oldest;
        {
            std::unique_lock lock(mutex);
            resultReady.wait(lock, [&] { return window.front()->result.has_value(); });
            oldest = std::move(window.front());
            window.pop_front();
        }
        Result<FrameAnalysis>& a = *oldest->result;
        if (!a && a.error().kind == ErrorKind::Corrupt) {
            if (out.onDamaged) out.onDamaged(a.error());
            continue;
        }
        if (!a) {
            result = a.error();
            break;
        }
        a->frame = delivered;  // the index one job gives: damaged frames take none
        if (auto st = out.sink(*a, oldest->frame); !st) {
            result = st;
            break;
        }
        ++delivered;
        if (out.progress) out.progress(delivered, out.total);
    }
    {
        std::lock_guard lock(mutex);
        stopping = true;
        todo.clear();
    }
    workReady.notify_all();
    for (std::thread& t : pool)
        t.join();
    // As with one job: the frames before a source's failure are handed on, then it is told.
    if (result && sourceError) return *sourceError;
    return result;
}

}  // namespace

unsigned defaultJobs() {
    return std::max(1u, std::thread::hardware_concurrency());
}

Status analyzeSourceFrames(std::string_view source, const AnalysisOptions& options,
                           uint64_t maxFrames, const FrameAnalysisSink& sink,
                           const DamageSink& onDamaged, const StartSink& onStart,
                           const StreamOptions& stream) {
    // Options are checked before the source opens: a mistyped grid must not wait on a camera.
    auto analyzer = Analyzer::create(options);
    if (!analyzer) return analyzer.error();
    auto src = openSource(source);
    if (!src) return src.error();
    FrameSource& s = **src;
    const SourceInfo info = s.info();
    const AnalysisOptions used = resolveForSource(options, info);
    if (used.blurSearchesPerFrame != options.blurSearchesPerFrame ||
        used.transfer != options.transfer) {
        analyzer = Analyzer::create(used);
        if (!analyzer) return analyzer.error();
    }
    if (onStart) onStart(info, used);
    Sinks out{sink, onDamaged, stream.progress};
    if (info.frameCount && *info.frameCount > 0)
        out.total = static_cast<uint64_t>(*info.frameCount);
    if (maxFrames && (out.total == 0 || maxFrames < out.total)) out.total = maxFrames;
    // A camera delivers at its own pace and a tracked blur carries each frame's edges to the
    // next: both are measured one frame at a time.
    const bool parallel = stream.jobs > 1 && !info.liveCamera && used.blurSearchesPerFrame == 0;
    std::vector<std::unique_ptr<Analyzer>> analyzers;
    if (parallel) {
        // The jobs share the cores: each analyser takes its part of them, not all.
        AnalysisOptions each = used;
        if (each.threads == 0)
            each.threads = std::max(1u, std::thread::hardware_concurrency() / stream.jobs);
        for (unsigned j = 0; j < stream.jobs; ++j) {
            auto more = Analyzer::create(each);
            if (!more) return more.error();
            analyzers.push_back(std::move(*more));
        }
    }
    if (auto st = s.start(); !st) return st.error();
    const Status result = parallel ? runParallel(s, analyzers, maxFrames, out)
                                   : runSequential(s, **analyzer, maxFrames, out);
    s.stop();
    return result;
}

Status analyzeSource(std::string_view source, const AnalysisOptions& options, uint64_t maxFrames,
                     const AnalysisSink& sink, const DamageSink& onDamaged,
                     const StartSink& onStart, const StreamOptions& stream) {
    return analyzeSourceFrames(
        source, options, maxFrames, [&](const FrameAnalysis& a, const Frame&) { return sink(a); },
        onDamaged, onStart, stream);
}

}  // namespace infocus
