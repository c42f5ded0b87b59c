// SPDX-License-Identifier: MIT
/// @file pipeline.h
/// The stream loop: open a source, take its frames, analyse each, hand the results on. The one
/// place where measurement meets a source; `analyze`, `depth`, `report` and `sweep` share it.
#pragma once

#include <cstdint>
#include <functional>
#include <string_view>

#include "infocus/analysis.h"
#include "infocus/error.h"
#include "infocus/frame.h"

namespace infocus {

/// Receives each analysed frame; a failed Status stops the analysis and is returned.
using AnalysisSink = std::function<Status(const FrameAnalysis&)>;

/// Receives each frame the source reported as damaged (ErrorKind::Corrupt) and skipped.
using DamageSink = std::function<void(const Error&)>;

struct SourceInfo;
/// Told once the source is open, before its first frame: what the source delivers, and the options
/// its frames are analysed with (AnalysisOptions::transferFromSource resolved).
using StartSink = std::function<void(const SourceInfo&, const AnalysisOptions&)>;

/// @p options as the frames of the source @p info describes are analysed with: the transfer
/// function the source reports where AnalysisOptions::transferFromSource asks for it, and blur
/// tracked within kLiveBlurSearchBudgetS a frame on a live camera where trackLiveCamera asks.
AnalysisOptions resolveForSource(const AnalysisOptions& options, const SourceInfo& info);
/// Told after each frame handed on: frames done, and the total (0 when unknown).
using ProgressSink = std::function<void(uint64_t done, uint64_t total)>;

/// How a stream is run, beyond what each frame is measured with.
struct StreamOptions {
    /// Frames measured at once, each job with its own Analyzer; results still reach the sink in
    /// order and equal those of one job. Live cameras, and a tracked blur
    /// (AnalysisOptions::blurSearchesPerFrame > 0, which carries state from frame to frame),
    /// always run one frame at a time.
    unsigned jobs = 1;
    /// Told from the calling thread after each frame the sink took; may be empty.
    ProgressSink progress;
};

/// The machine's cores (at least 1): the default of --jobs.
unsigned defaultJobs();

/// Opens @p source (a source string, see source.h) and analyses up to @p maxFrames frames
/// (0: until the source ends), handing each result to @p sink in order. A damaged frame is
/// skipped and reported to @p onDamaged (when given); the frames after it are still analysed.
Status analyzeSource(std::string_view source, const AnalysisOptions& options, uint64_t maxFrames,
                     const AnalysisSink& sink, const DamageSink& onDamaged = {},
                     const StartSink& onStart = {}, const StreamOptions& stream = {});

/// Receives each analysed frame with the frame it measured (valid only during the call).
using FrameAnalysisSink = std::function<Status(const FrameAnalysis&, const Frame&)>;
/// analyzeSource for callers that need the pixels too (the report embeds each frame).
Status analyzeSourceFrames(std::string_view source, const AnalysisOptions& options,
                           uint64_t maxFrames, const FrameAnalysisSink& sink,
                           const DamageSink& onDamaged = {}, const StartSink& onStart = {},
                           const StreamOptions& stream = {});
}  // namespace infocus
