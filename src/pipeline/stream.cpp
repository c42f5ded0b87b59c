// SPDX-License-Identifier: MIT
// The stream loop: measurement (src/metrics) never opens a source; this is where the two meet.
#include "infocus/pipeline.h"
#include "infocus/source.h"

namespace infocus {

AnalysisOptions resolveForSource(const AnalysisOptions& options, const SourceInfo& info) {
    AnalysisOptions used = options;
    if (options.trackLiveCamera && info.liveCamera) {
        used.blurSearchesPerFrame = kLiveBlurSearchesPerFrame;
        used.blurSearchBudgetS = kLiveBlurSearchBudgetS;
    }
    if (options.transferFromSource && info.transfer.curve) used.transfer = *info.transfer.curve;
    return used;
}

Status analyzeSourceFrames(std::string_view source, const AnalysisOptions& options,
                           uint64_t maxFrames, const FrameAnalysisSink& sink,
                           const DamageSink& onDamaged, const StartSink& onStart) {
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
    if (auto st = s.start(); !st) return st.error();
    Status result;
    for (uint64_t i = 0; maxFrames == 0 || i < maxFrames; ++i) {
        auto frame = s.next();
        if (!frame && frame.error().kind == ErrorKind::Corrupt) {
            // One damaged frame (torn record, bad JPEG) must not cost the intact ones after it.
            if (onDamaged) onDamaged(frame.error());
            --i;
            continue;
        }
        if (!frame) {
            if (frame.error().kind != ErrorKind::EndOfStream) result = frame.error();
            break;
        }
        auto a = (*analyzer)->analyze(*frame, i);
        if (!a && a.error().kind == ErrorKind::Corrupt) {
            if (onDamaged) onDamaged(a.error());
            --i;
            continue;
        }
        if (!a) {
            result = a.error();
            break;
        }
        if (auto st = sink(*a, *frame); !st) {
            result = st;
            break;
        }
    }
    s.stop();
    return result;
}

Status analyzeSource(std::string_view source, const AnalysisOptions& options, uint64_t maxFrames,
                     const AnalysisSink& sink, const DamageSink& onDamaged,
                     const StartSink& onStart) {
    return analyzeSourceFrames(
        source, options, maxFrames, [&](const FrameAnalysis& a, const Frame&) { return sink(a); },
        onDamaged, onStart);
}

}  // namespace infocus
