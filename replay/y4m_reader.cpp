// SPDX-License-Identifier: MIT
// Y4M (YUV4MPEG2) files: "YUV4MPEG2 W.. H.. F30:1 C420jpeg ...\n", then per frame "FRAME...\n"
// and the planes Y, Cb, Cr. Only the luma plane is delivered.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <sstream>
#include <string_view>
#include <vector>

#include "replay/file_readers.h"
#include "src/core/read_number.h"

namespace infocus::replay {

namespace {

// The whole of @p text as an integer in [@p lo, @p hi]; empty for anything else ("1e9", "",
// "4294967297"), which atoi would have read as some other number.
std::optional<int> wholeNumber(std::string_view text, int lo, int hi) {
    int v = 0;
    if (!readsWhole(text, v) || v < lo || v > hi) return std::nullopt;
    return v;
}

// The longest header or FRAME line read (with its '\n').
constexpr size_t kMaxLineBytes = 4096;

class Y4mReader final : public FrameReader {
public:
    static Result<std::unique_ptr<FrameReader>> open(const std::string& path,
                                                     const std::string& text) {
        const auto bad = [&](const std::string& why) -> Error {
            return makeError(ErrorKind::Corrupt,
                             "Y4M file " + path + ": " + why +
                                 "; write it again as YUV4MPEG2, e.g. ffmpeg -i IN -f "
                                 "yuv4mpegpipe OUT.y4m");
        };
        const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) {
            const int e = errno;
            return makeError(e == ENOENT ? ErrorKind::NotFound : ErrorKind::Io,
                             "cannot open " + path + ": " + std::strerror(e), e);
        }
        std::unique_ptr<Y4mReader> r(new Y4mReader);
        r->fd_ = fd;
        r->path_ = path;
        r->text_ = text;
        std::string line;
        if (!r->readLine(0, line)) {
            // The signature without the end of its line is a header too long (or cut short),
            // not a file of another kind.
            char head[9] = {};
            const ssize_t n = ::pread(fd, head, sizeof head, 0);
            if (n == 0) return bad("is empty (0 bytes)");
            if (n == sizeof head && std::memcmp(head, "YUV4MPEG2", sizeof head) == 0)
                return bad("its YUV4MPEG2 header line does not end within " +
                           std::to_string(kMaxLineBytes) + " bytes (too long, or cut short)");
            return bad("does not start with a YUV4MPEG2 header");
        }
        if (line.rfind("YUV4MPEG2", 0) != 0) return bad("does not start with a YUV4MPEG2 header");
        std::istringstream tokens(line.substr(9));
        std::string tok, colour = "420jpeg";
        int fpsNum = 0, fpsDen = 1;
        // A side of up to 65536 px: a frame of 4 G pixels, far past any camera, and its plane
        // sizes stay far from overflow.
        constexpr int kMaxSide = 65536;
        while (tokens >> tok) {
            const std::string_view value = std::string_view(tok).substr(1);
            switch (tok[0]) {
                case 'W':
                case 'H': {
                    const auto side = wholeNumber(value, 1, kMaxSide);
                    if (!side)
                        return bad("its header's " + tok + " is not a " +
                                   (tok[0] == 'W' ? "width" : "height") + " of 1 to " +
                                   std::to_string(kMaxSide) + " pixels");
                    (tok[0] == 'W' ? r->size_.width : r->size_.height) = *side;
                    break;
                }
                case 'F': {
                    // A rate the header gets wrong only costs the playback pace: it falls back.
                    const size_t colon = value.find(':');
                    const auto num = wholeNumber(value.substr(0, colon), 1, INT_MAX);
                    const auto den = colon == std::string_view::npos
                                         ? std::nullopt
                                         : wholeNumber(value.substr(colon + 1), 1, INT_MAX);
                    if (num && den) fpsNum = *num, fpsDen = *den;
                    break;
                }
                case 'C':
                    colour = tok.substr(1);
                    break;
                default:
                    break;  // interlacing, aspect ratio, X comments: irrelevant to luma
            }
        }
        if (r->size_.width <= 0 || r->size_.height <= 0)
            return bad("its header has no positive width (W) and height (H)");
        if (!withinFrameLimit(r->size_.width, r->size_.height))
            return bad("its header's " + std::to_string(r->size_.width) + "x" +
                       std::to_string(r->size_.height) + " is more than the " + maxFrameSizeText() +
                       " pixels a frame may hold");
        // A rate past those a source option may give would overflow the frames' timestamps.
        const double fps = static_cast<double>(fpsNum) / fpsDen;
        r->fps_ = fps >= kMinFps && fps <= kMaxFps ? fps : 0.0;

        // Bytes per sample and chroma subsampling from the colour space tag.
        size_t bytes = 1;
        std::string sub = colour;
        // A bit depth is given as "<subsampling>p<bits>", e.g. 420p10 (not the p of 420jpeg).
        const size_t p = colour.find('p');
        const bool digitsAfter = p != std::string::npos && p + 1 < colour.size() &&
                                 colour.find_first_not_of("0123456789", p + 1) == std::string::npos;
        if (p > 0 && digitsAfter && colour.find_first_not_of("0123456789") == p) {
            const int depth = std::atoi(colour.c_str() + p + 1);
            sub = colour.substr(0, p);
            if (depth == 10) {
                r->format_ = PixelFormat::Y10;
            } else if (depth == 16) {
                r->format_ = PixelFormat::Y16;
            } else {
                return makeError(ErrorKind::Unsupported,
                                 "Y4M file " + path + ": colour space C" + colour +
                                     " is not supported; use 8, 10 or 16 bits per sample");
            }
            bytes = 2;
        } else if (colour == "mono16") {
            sub = "mono";
            r->format_ = PixelFormat::Y16;
            bytes = 2;
        }
        const size_t w = static_cast<size_t>(r->size_.width);
        const size_t h = static_cast<size_t>(r->size_.height);
        const size_t cw = (w + 1) / 2, ch = (h + 1) / 2;
        size_t chroma = 0;
        if (sub.rfind("420", 0) == 0)
            chroma = 2 * cw * ch;
        else if (sub == "422")
            chroma = 2 * cw * h;
        else if (sub == "444")
            chroma = 2 * w * h;
        else if (sub == "mono")
            chroma = 0;
        else
            return makeError(ErrorKind::Unsupported,
                             "Y4M file " + path + ": colour space C" + colour +
                                 " is not supported; use 420, 422, 444 or mono");
        r->lumaBytes_ = w * h * bytes;
        const size_t frameBytes = r->lumaBytes_ + chroma * bytes;

        struct stat st;
        ::fstat(fd, &st);
        const auto fileSize = static_cast<uint64_t>(st.st_size);
        uint64_t offset = line.size() + 1;
        while (offset < fileSize) {
            std::string frameLine;
            if (!r->readLine(offset, frameLine) || frameLine.rfind("FRAME", 0) != 0) {
                r->damage_ = "Y4M file " + path + ": no FRAME marker at byte " +
                             std::to_string(offset) + " (frame " +
                             std::to_string(r->offsets_.size()) +
                             "); the file is damaged there, the frames before it are intact";
                break;
            }
            const uint64_t data = offset + frameLine.size() + 1;
            if (data + frameBytes > fileSize) {
                r->damage_ = "Y4M file " + path + ": frame " + std::to_string(r->offsets_.size()) +
                             " is incomplete (" + std::to_string(fileSize - data) + " of " +
                             std::to_string(frameBytes) +
                             " bytes); the file is truncated, the frames before it are intact";
                break;
            }
            r->offsets_.push_back(data);
            offset = data + frameBytes;
        }
        return std::unique_ptr<FrameReader>(std::move(r));
    }

    ~Y4mReader() override {
        if (fd_ >= 0) ::close(fd_);
    }

    SourceInfo info() const override {
        SourceInfo i;
        i.sourceString = text_;
        i.device = path_;
        i.driver = "y4m";
        i.format = format_;
        i.size = size_;
        i.fps = fps_;
        i.frameCount = static_cast<int64_t>(offsets_.size());
        i.transfer.origin = "a Y4M header names no transfer function";
        return i;
    }
    size_t count() const override { return offsets_.size(); }
    int64_t timestampNs(size_t i) const override { return frameTimeNs(i, fps_ > 0 ? fps_ : 30.0); }
    Result<Frame> read(size_t i) override {
        auto frame = allocateFrame(format_, size_);
        if (!frame) return frame.error();
        const ssize_t n =
            ::pread(fd_, mutablePlane(*frame, 0), lumaBytes_, static_cast<off_t>(offsets_[i]));
        if (n != static_cast<ssize_t>(lumaBytes_)) {
            const int e = errno;
            return makeError(ErrorKind::Io,
                             "cannot read frame " + std::to_string(i) + " of " + path_ + ": " +
                                 (n < 0 ? std::strerror(e) : "short read"),
                             e);
        }
        frame->sequence = i;
        frame->timestampNs = timestampNs(i);
        return frame;
    }
    std::optional<Error> trailingError() const override {
        if (!damage_) return std::nullopt;
        return makeError(ErrorKind::Corrupt, *damage_);
    }

private:
    Y4mReader() = default;

    // Reads the text line at @p offset (without its '\n'); false when no '\n' within 4 KiB.
    bool readLine(uint64_t offset, std::string& line) const {
        char buf[kMaxLineBytes];
        const ssize_t n = ::pread(fd_, buf, sizeof buf, static_cast<off_t>(offset));
        if (n <= 0) return false;
        const void* nl = std::memchr(buf, '\n', static_cast<size_t>(n));
        if (!nl) return false;
        line.assign(buf, static_cast<size_t>(static_cast<const char*>(nl) - buf));
        return true;
    }

    int fd_ = -1;
    std::string path_, text_;
    Size size_;
    double fps_ = 0.0;
    PixelFormat format_ = PixelFormat::GREY;
    size_t lumaBytes_ = 0;
    std::vector<uint64_t> offsets_;
    std::optional<std::string> damage_;
};

}  // namespace

Result<std::unique_ptr<FrameReader>> openY4mReader(const std::string& path,
                                                   const std::string& text) {
    return Y4mReader::open(path, text);
}

}  // namespace infocus::replay
