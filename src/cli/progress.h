// SPDX-License-Identifier: MIT
// One progress line on stderr for the long runs over files and recordings (analyze, stack,
// report, record): frames done of the total, frames a second, time left.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace infocus::cli {

/// Redraws one line on stderr as frames are done. Silent when stderr is not a terminal, with
/// --quiet, or once disable() was called (a live camera has no end to count towards).
class ProgressLine {
public:
    ProgressLine(std::string command, bool quiet);
    ~ProgressLine();
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;

    /// @p done frames of @p total (0: unknown); redrawn at most ten times a second.
    void update(uint64_t done, uint64_t total);
    /// Erases the line, for a message that must start at the left margin; the next update
    /// draws it again.
    void clear();
    /// Stops drawing and erases the line.
    void disable();
    bool enabled() const { return enabled_; }

private:
    std::string command_;
    bool enabled_ = false;
    bool drawn_ = false;
    std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace infocus::cli
