// SPDX-License-Identifier: MIT
// `analyze_jobs`: frames a second of the stream loop over a 300-frame 1080p recording, measured
// N frames at once against one at a time.
#include <stdlib.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "bench/bench.h"
#include "infocus/pipeline.h"
#include "infocus/recording.h"
#include "infocus/source.h"
#include "infocus/synth.h"

namespace infocus::bench {

namespace {

constexpr int kFrames = 300;
constexpr int kWidth = 1920, kHeight = 1080;

// A dead-leaves texture with slanted squares, panned a pixel a frame, near focus (a 3 px disc),
// 1 grey level of noise: frames that differ as a camera's do, with edges in most regions.
Status writeRecording(const std::string& dir) {
    synth::SharpCanvas canvas = synth::makeCanvas(kWidth + kFrames, kHeight, 1);
    synth::paintDeadLeaves(canvas, 2024, 4.0, 120.0);
    for (int i = 0; i < 12; ++i)
        synth::paint(canvas,
                     synth::squareScene(kWidth * (0.1 + 0.07 * i), kHeight * (0.2 + 0.12 * (i % 5)),
                                        90.0, 5.0 + 7.0 * i, i % 2 ? 30.0f : 220.0f));
    const Image<uint8_t> scene =
        synth::toLuma8(synth::renderSharp(canvas, {synth::Psf::disc(3.0), 1, 1.0, 7}).pixels);
    SourceInfo info;
    info.sourceString = "infocus bench";
    info.driver = "bench";
    info.format = PixelFormat::GREY;
    info.size = {kWidth, kHeight};
    info.fps = 30.0;
    auto writer = RecordingWriter::create(dir, makeRecordingHeader(info, nullptr));
    if (!writer) return writer.error();
    for (int i = 0; i < kFrames; ++i) {
        auto frame = allocateFrame(PixelFormat::GREY, info.size);
        if (!frame) return frame.error();
        for (int y = 0; y < kHeight; ++y)
            std::copy_n(scene.row(y) + i, kWidth,
                        mutablePlane(*frame, 0) + y * frame->planes[0].stride);
        frame->timestampNs = int64_t{i} * 33'333'333;
        frame->sequence = static_cast<uint64_t>(i);
        if (auto st = (*writer)->append(*frame); !st) return st;
    }
    return (*writer)->close();
}

// Seconds to analyse every frame of @p dir as `infocus analyze --jobs @p jobs` does (16x9, blur
// searched in full), each frame's blur on @p threads (0: the job's share of the cores), or
// nothing on a failure.
std::optional<double> runSeconds(const std::string& dir, unsigned jobs, unsigned threads = 0) {
    StreamOptions stream;
    stream.jobs = jobs;
    AnalysisOptions options;
    options.threads = threads;
    uint64_t frames = 0;
    const auto t0 = std::chrono::steady_clock::now();
    const Status st = analyzeSource(
        dir, options, 0,
        [&](const FrameAnalysis&) -> Status {
            ++frames;
            return {};
        },
        {}, {}, stream);
    if (!st || frames != kFrames) return std::nullopt;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void benchJobs(const BenchOptions&, const RowSink& sink) {
    namespace fs = std::filesystem;
    BenchRow row{"analyze_jobs", kWidth, kHeight, 0.0, std::nullopt, "the same with --jobs 1", ""};
    std::string dir = (fs::temp_directory_path() / "infocus-bench-jobs-XXXXXX").string();
    if (!mkdtemp(dir.data())) {
        row.note = "could not make a temporary directory in " + fs::temp_directory_path().string();
        sink(row);
        return;
    }
    const std::string rec = dir + "/rec";
    if (auto st = writeRecording(rec); !st) {
        row.note = "could not write the recording: " + st.error().message;
    } else {
        const unsigned jobs = defaultJobs();
        // Read once first, so that both runs find the recording in the page cache.
        (void)runSeconds(rec, jobs);
        const auto one = runSeconds(rec, 1);
        const auto many = runSeconds(rec, jobs);
        // One frame after another on one core: --jobs 1 shares each frame's blur over the cores.
        const auto serial = runSeconds(rec, 1, 1);
        if (one && many && serial) {
            row.ms = *many * 1e3 / kFrames;
            row.baselineMs = *one * 1e3 / kFrames;
            char note[300];
            std::snprintf(note, sizeof note,
                          "%d-frame GREY recording, 16x9 regions with blur; %u jobs %.1f "
                          "frames/s, 1 job %.1f frames/s, 1 job on one core %.1f frames/s "
                          "(%.2fx); target 1.8x on 2 cores",
                          kFrames, jobs, kFrames / *many, kFrames / *one, kFrames / *serial,
                          *serial / *many);
            row.note = note;
        } else {
            row.note = "the recording could not be analysed";
        }
    }
    std::error_code ec;
    fs::remove_all(dir, ec);
    sink(row);
}

}  // namespace infocus::bench
