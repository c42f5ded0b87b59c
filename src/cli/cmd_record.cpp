// SPDX-License-Identifier: MIT
// `infocus record`: writes any source to a recording directory (see include/infocus/recording.h).
#include <signal.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "commands.h"
#include "infocus/devices.h"
#include "infocus/recording.h"
#include "infocus/source.h"
#include "progress.h"

namespace infocus::cli {

namespace {

struct RecordArgs {
    std::string source;
    std::string output;
    std::optional<int64_t> frames;
    std::optional<double> seconds;
    bool quiet = false;
};

// Set by SIGINT/SIGTERM: finish the current frame, then close the recording cleanly.
std::atomic<bool> gStop{false};

extern "C" void onStopSignal(int) {
    gStop.store(true);
}

// Installs the stop handlers for its lifetime and puts the previous ones back.
class StopSignals {
public:
    StopSignals() {
        struct sigaction sa {};
        sa.sa_handler = onStopSignal;
        sigemptyset(&sa.sa_mask);
        sigaction(SIGINT, &sa, &oldInt_);
        sigaction(SIGTERM, &sa, &oldTerm_);
    }
    ~StopSignals() {
        sigaction(SIGINT, &oldInt_, nullptr);
        sigaction(SIGTERM, &oldTerm_, nullptr);
    }
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;

private:
    struct sigaction oldInt_ {};
    struct sigaction oldTerm_ {};
};

int runRecord(const RecordArgs& args) {
    const std::string cmd = "record";
    // From the very start: opening a source can take a while (a camera, a large sim: scene),
    // and a signal then must stop the command cleanly, not kill it.
    const StopSignals signals;
    const auto stoppedEarly = [&] {
        std::printf("recorded nothing to %s: stopped by signal while the source was opening\n",
                    args.output.c_str());
        std::fflush(stdout);
        return 0;
    };
    auto source = openSource(args.source);
    // A failure caused by the signal (an interrupted open) is the stop, not an error.
    if (gStop.load()) return stoppedEarly();
    if (!source) return reportError(cmd, source.error());
    FrameSource& src = **source;
    const SourceInfo info = src.info();
    auto writer =
        RecordingWriter::create(args.output, makeRecordingHeader(info, src.focusControl()));
    if (!writer) return reportError(cmd, writer.error());

    if (auto s = src.start(); !s) return reportError(cmd, s.error());
    const auto t0 = std::chrono::steady_clock::now();
    // Files and sim: have a count to show; a camera's frames arrive at its own pace.
    ProgressLine progress(cmd, args.quiet || info.liveCamera);
    uint64_t total = info.frameCount ? static_cast<uint64_t>(*info.frameCount) : 0;
    if (args.frames && (total == 0 || static_cast<uint64_t>(*args.frames) < total))
        total = static_cast<uint64_t>(*args.frames);
    std::optional<Error> failure;
    bool interrupted = false;
    while (true) {
        if (gStop.load()) {
            interrupted = true;
            break;
        }
        if (args.frames && static_cast<int64_t>((*writer)->frames()) >= *args.frames) break;
        if (args.seconds &&
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >=
                *args.seconds)
            break;
        auto frame = src.next();
        if (!frame) {
            if (frame.error().kind == ErrorKind::EndOfStream) break;
            // A damaged frame of a file source is reported and skipped; anything else ends.
            progress.clear();
            std::fprintf(stderr, "infocus record: %s\n", frame.error().message.c_str());
            if (frame.error().kind == ErrorKind::Corrupt) {
                failure = frame.error();
                continue;
            }
            failure = frame.error();
            break;
        }
        if (auto s = (*writer)->append(*frame); !s) {
            failure = s.error();
            progress.clear();
            std::fprintf(stderr, "infocus record: %s\n", s.error().message.c_str());
            break;
        }
        progress.update((*writer)->frames(), total);
    }
    progress.clear();
    src.stop();
    const Status closed = (*writer)->close();
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const SourceStats stats = src.stats();
    std::printf(
        "recorded %llu frames (%s %dx%d) to %s: %.1f MB in %.2f s (%.1f frames/s), %llu dropped, "
        "%llu damaged%s\n",
        static_cast<unsigned long long>((*writer)->frames()), pixelFormatName(info.format).c_str(),
        info.size.width, info.size.height, args.output.c_str(), (*writer)->bytes() / 1e6, elapsed,
        elapsed > 0 ? (*writer)->frames() / elapsed : 0.0,
        static_cast<unsigned long long>(stats.dropped + (*writer)->droppedFlags()),
        static_cast<unsigned long long>(stats.errors), interrupted ? ", stopped by signal" : "");
    std::fflush(stdout);
    if (!closed.ok()) return reportError(cmd, closed.error());
    if (failure) return kExitFailure;
    return 0;
}

}  // namespace

Command addRecordCommand(CLI::App& app) {
    auto args = std::make_shared<RecordArgs>();
    CLI::App* sub = app.add_subcommand(
        "record", "Record a source (camera, sim:, file) to a directory that replays bit-exact");
    sub->add_option("source", args->source, "Source string: " + sourceStringExamples())->required();
    sub->add_option("-o,--output", args->output, "New or empty directory for the recording")
        ->required();
    auto* frames =
        sub->add_option("--frames", args->frames, "Stop after N frames")->check(frameCount(1));
    auto* seconds = sub->add_option("--seconds", args->seconds, "Stop after S seconds")
                        ->check(secondsIn(0.0, HUGE_VAL, "10"));
    frames->excludes(seconds);
    sub->add_flag("--quiet", args->quiet,
                  "No progress line on stderr (shown for files and sim: when stderr is a "
                  "terminal)");
    sub->footer(
        "Without --frames or --seconds, records until the source ends or Ctrl-C. Ctrl-C and "
        "SIGTERM stop after the current frame and close the recording cleanly.");
    return {sub, [args] { return runRecord(*args); }};
}

}  // namespace infocus::cli
