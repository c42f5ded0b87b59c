// SPDX-License-Identifier: MIT
#include "src/live/printed_face.h"

#include <chrono>
#include <iostream>

namespace infocus {

namespace {

class PrintedFace final : public Face {
public:
    explicit PrintedFace(StateLine line) : line_(std::move(line)) {}

    Status prepare(LiveOptions&) override { return {}; }

    Status run(LiveView& view, const RunLimits& limits) override {
        using Clock = std::chrono::steady_clock;
        const RunClock clock(limits);
        auto nextPrint = Clock::now() + std::chrono::seconds(1);
        std::optional<uint64_t> last;
        for (;;) {
            auto s = view.waitForState(last, std::chrono::milliseconds(100));
            if (s) last = s->frame;
            const auto newest = view.state();
            const bool over = clock.done(newest.get());
            if (Clock::now() >= nextPrint ||
                (over && newest && limits.frames && newest->frame + 1 >= *limits.frames)) {
                if (newest) {
                    std::cout << line_(*newest) << std::endl;
                    if (!std::cout)
                        return makeError(ErrorKind::Io,
                                         "cannot write to stdout; write to a file or a pipe "
                                         "that is read");
                }
                nextPrint += std::chrono::seconds(1);
            }
            if (over) return {};
            if (!s && view.ended()) return view.endStatus();
        }
    }

private:
    StateLine line_;
};

}  // namespace

std::unique_ptr<Face> makePrintedFace(StateLine line) {
    return std::make_unique<PrintedFace>(std::move(line));
}

}  // namespace infocus
