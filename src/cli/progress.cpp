// SPDX-License-Identifier: MIT
#include "progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace infocus::cli {

namespace {

// "1:05" or "12 s"
std::string duration(double s) {
    char text[32];
    const auto whole = static_cast<long>(s + 0.5);
    if (whole >= 60)
        std::snprintf(text, sizeof text, "%ld:%02ld", whole / 60, whole % 60);
    else
        std::snprintf(text, sizeof text, "%ld s", whole);
    return text;
}

}  // namespace

ProgressLine::ProgressLine(std::string command, bool quiet)
    : command_(std::move(command)),
      // Progress is for a person watching: a file or a pipe gets only the results and errors.
      enabled_(!quiet && isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()) {}

ProgressLine::~ProgressLine() {
    clear();
}

void ProgressLine::update(uint64_t done, uint64_t total) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    const bool last = total && done >= total;
    if (drawn_ && !last && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double fps = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
    char line[160];
    if (total) {
        const double left = fps > 0 ? static_cast<double>(total - std::min(done, total)) / fps : 0;
        std::snprintf(line, sizeof line, "infocus %s: %llu/%llu frames (%.0f%%)  %.1f fps  %s left",
                      command_.c_str(), static_cast<unsigned long long>(done),
                      static_cast<unsigned long long>(total), 100.0 * done / total, fps,
                      duration(left).c_str());
    } else {
        std::snprintf(line, sizeof line, "infocus %s: %llu frames  %.1f fps", command_.c_str(),
                      static_cast<unsigned long long>(done), fps);
    }
    // Carriage return and erase-to-end redraw the line in place.
    std::fprintf(stderr, "\r\033[K%s", line);
    std::fflush(stderr);
    drawn_ = true;
}

void ProgressLine::clear() {
    if (!drawn_) return;
    std::fputs("\r\033[K", stderr);
    std::fflush(stderr);
    drawn_ = false;
}

void ProgressLine::disable() {
    clear();
    enabled_ = false;
}

}  // namespace infocus::cli
