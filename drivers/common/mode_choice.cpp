// SPDX-License-Identifier: MIT
#include "drivers/common/mode_choice.h"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace infocus::capture {

namespace {

// Below this a live focus meter lags the hand on the focus ring.
constexpr double kMinLiveFps = 15.0;

double bestFps(const SizeOption& s) {
    return s.fps.empty() ? 0.0 : *std::max_element(s.fps.begin(), s.fps.end());
}

std::string describe(const std::vector<FormatOption>& offered) {
    std::string out;
    for (const auto& f : offered) {
        if (!out.empty()) out += "; ";
        out += pixelFormatName(static_cast<PixelFormat>(f.fourcc));
        if (f.format == PixelFormat::Invalid) out += " (unreadable)";
        std::string sizes;
        for (const auto& s : f.sizes) {
            sizes.append(sizes.empty() ? " " : ",");
            sizes.append(std::to_string(s.size.width))
                .append("x")
                .append(std::to_string(s.size.height));
        }
        out += sizes;
    }
    return out.empty() ? "nothing" : out;
}

}  // namespace

Result<Size> parseSize(const std::string& text) {
    const size_t x = text.find_first_of("xX");
    Size s;
    if (x == std::string::npos) return makeError(ErrorKind::Usage, "bad size '" + text + "'");
    const char* b = text.data();
    auto [p1, e1] = std::from_chars(b, b + x, s.width);
    auto [p2, e2] = std::from_chars(b + x + 1, b + text.size(), s.height);
    if (e1 != std::errc() || e2 != std::errc() || p1 != b + x || p2 != b + text.size() ||
        s.width <= 0 || s.height <= 0)
        return makeError(ErrorKind::Usage,
                         "bad size '" + text + "'; write WIDTHxHEIGHT, e.g. 1280x720");
    return s;
}

Result<ModeRequest> parseModeRequest(const std::map<std::string, std::string>& options,
                                     const std::string& source) {
    ModeRequest r;
    if (auto it = options.find("format"); it != options.end()) {
        auto f = parsePixelFormat(it->second);
        if (!f)
            return makeError(ErrorKind::Usage, "source '" + source + "': format=" + it->second +
                                                   ": " + f.error().message);
        r.format = *f;
    }
    if (auto it = options.find("size"); it != options.end()) {
        auto s = parseSize(it->second);
        if (!s)
            return makeError(ErrorKind::Usage, "source '" + source + "': size=" + it->second +
                                                   ": write WIDTHxHEIGHT, e.g. size=1280x720");
        r.size = *s;
    }
    if (auto it = options.find("fps"); it != options.end()) {
        double v = 0;
        const auto& t = it->second;
        auto [p, e] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (e != std::errc() || p != t.data() + t.size() || !(v > 0))
            return makeError(ErrorKind::Usage, "source '" + source + "': fps=" + t +
                                                   ": give a positive frame rate, e.g. fps=30");
        r.fps = v;
    }
    return r;
}

int lumaCost(PixelFormat format) {
    switch (format) {
        case PixelFormat::GREY:
        case PixelFormat::NV12:
        case PixelFormat::NV21:
        case PixelFormat::YU12:
            return 0;
        case PixelFormat::YUYV:
        case PixelFormat::UYVY:
            return 1;
        case PixelFormat::Y10:
        case PixelFormat::Y16:
            return 2;
        case PixelFormat::RGB24:
        case PixelFormat::BGR24:
        case PixelFormat::RGBX:
        case PixelFormat::BGRX:
            return 3;
        case PixelFormat::SRGGB8:
        case PixelFormat::SGRBG8:
        case PixelFormat::SGBRG8:
        case PixelFormat::SBGGR8:
            return 4;
        case PixelFormat::MJPEG:
            return 5;
        case PixelFormat::Invalid:
            break;
    }
    return 100;
}

Result<Mode> chooseMode(const std::vector<FormatOption>& offered, const ModeRequest& request,
                        const std::optional<Mode>& current) {
    if (request.empty() && current && isSupported(current->format) &&
        current->format != PixelFormat::Invalid)
        return *current;

    struct Candidate {
        const FormatOption* format;
        const SizeOption* size;
        double fps;
    };
    std::vector<Candidate> candidates;
    for (const auto& f : offered) {
        if (f.format == PixelFormat::Invalid || !isSupported(f.format)) continue;
        if (request.format && f.format != *request.format) continue;
        for (const auto& s : f.sizes) {
            if (request.size && !(s.size == *request.size)) continue;
            double fps = bestFps(s);
            if (request.fps && !s.fps.empty()) {
                fps = s.fps.front();
                for (double r : s.fps)
                    if (std::abs(r - *request.fps) < std::abs(fps - *request.fps)) fps = r;
                // A rate far from the request is not what was asked for.
                if (std::abs(fps - *request.fps) > 0.05 * *request.fps) continue;
            }
            candidates.push_back({&f, &s, fps});
        }
    }
    if (candidates.empty()) {
        std::string asked;
        if (request.format) asked += " format " + pixelFormatName(*request.format);
        if (request.size)
            asked += " size " + std::to_string(request.size->width) + "x" +
                     std::to_string(request.size->height);
        if (request.fps) asked += " at " + std::to_string(*request.fps) + " fps";
        return makeError(ErrorKind::Unsupported,
                         "no readable capture mode" +
                             (asked.empty() ? std::string() : " with" + asked) +
                             "; the device offers: " + describe(offered));
    }
    const bool anyLive = std::any_of(candidates.begin(), candidates.end(),
                                     [](const Candidate& c) { return c.fps >= kMinLiveFps; });
    auto key = [&](const Candidate& c) {
        const bool live = !anyLive || c.fps >= kMinLiveFps;
        const int64_t area = int64_t(c.size->size.width) * c.size->size.height;
        return std::tuple(live, area, -lumaCost(c.format->format), c.fps);
    };
    const auto best =
        std::max_element(candidates.begin(), candidates.end(),
                         [&](const Candidate& a, const Candidate& b) { return key(a) < key(b); });
    return Mode{best->format->fourcc, best->format->format, best->size->size, best->fps};
}

uint64_t SequenceTracker::update(uint32_t sequence) {
    uint64_t gap = 0;
    // Unsigned difference wraps correctly across 2^32.
    if (last_) gap = static_cast<uint32_t>(sequence - *last_ - 1u);
    // A sequence that goes backwards (restart) is not a loss of 4 billion frames.
    if (gap > (1u << 30)) gap = 0;
    last_ = sequence;
    dropped_ += gap;
    return gap;
}

double snapToStep(double value, double min, double max, double step) {
    double v = std::clamp(value, min, max);
    if (step > 0) {
        v = min + std::round((v - min) / step) * step;
        // Rounding up may step past max when the range is not a whole number of steps.
        if (v > max + 1e-9) v -= step;
    }
    return v;
}

}  // namespace infocus::capture
