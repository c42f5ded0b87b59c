// SPDX-License-Identifier: MIT
// File sources: recordings, Y4M, single images, image directories and globs, video files.
#include <fcntl.h>
#include <glob.h>
#include <sys/stat.h>
#include <turbojpeg.h>
#include <unistd.h>

#include <dirent.h>
#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>
#include <fstream>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <opencv2/videoio/registry.hpp>
#include <optional>
#include <sstream>
#include <vector>

#include "infocus/recording.h"
#include "replay/playback.h"
#include "replay/recording_format.h"
#include "replay/replay_sources.h"
#include "src/core/read_number.h"

namespace infocus::replay {

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

std::string extension(const std::string& path) {
    const size_t slash = path.rfind('/');
    const size_t dot = path.rfind('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
    return lower(path.substr(dot + 1));
}

// The whole of @p text as an integer in [@p lo, @p hi]; empty for anything else ("1e9", "",
// "4294967297"), which atoi would have read as some other number.
std::optional<int> wholeNumber(std::string_view text, int lo, int hi) {
    int v = 0;
    if (!readsWhole(text, v) || v < lo || v > hi) return std::nullopt;
    return v;
}

bool isImageExtension(const std::string& ext) {
    static const std::set<std::string> kExts = {"jpg", "jpeg", "png", "tif", "tiff", "bmp",
                                                "pgm", "ppm",  "pnm", "pbm", "webp"};
    return kExts.count(ext) > 0;
}

// The timestamp of frame @p i at @p fps frames a second, ns from the first; saturates at
// INT64_MAX rather than overflow (a long file at a time-lapse rate).
int64_t frameTimeNs(size_t i, double fps) {
    const auto period = static_cast<int64_t>(std::llround(1e9 / fps));
    int64_t t = 0;
    if (i > static_cast<size_t>(INT64_MAX) ||
        __builtin_mul_overflow(static_cast<int64_t>(i), period, &t))
        return INT64_MAX;
    return t;
}

// ---------------------------------------------------------------------------------------------
// Recordings

class RecordingFrameReader final : public FrameReader {
public:
    RecordingFrameReader(std::unique_ptr<RecordingReader> r, std::string text)
        : r_(std::move(r)), text_(std::move(text)) {}

    SourceInfo info() const override {
        const RecordingHeader& h = r_->header();
        SourceInfo i;
        i.sourceString = text_;
        i.device = h.device.empty() ? h.sourceString : h.device;
        i.driver = "replay";
        i.format = h.format;
        i.size = h.size;
        i.fps = h.fps;
        i.frameCount = static_cast<int64_t>(r_->frameCount());
        i.transfer.curve = h.transfer.curve;
        i.transfer.origin = h.transfer.origin.empty()
                                ? "the recording's header names no transfer function"
                                : "the recording's header: " + h.transfer.origin;
        return i;
    }
    size_t count() const override { return r_->frameCount(); }
    int64_t timestampNs(size_t i) const override { return r_->frameInfo(i).timestampNs; }
    Result<Frame> read(size_t i) override { return r_->read(i); }
    std::optional<Error> trailingError() const override {
        if (!r_->damage()) return std::nullopt;
        return makeError(ErrorKind::Corrupt, *r_->damage());
    }

private:
    std::unique_ptr<RecordingReader> r_;
    std::string text_;
};

// ---------------------------------------------------------------------------------------------
// Y4M (YUV4MPEG2): "YUV4MPEG2 W.. H.. F30:1 C420jpeg ...\n", then per frame "FRAME...\n" and
// the planes Y, Cb, Cr. Only the luma plane is delivered.

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
        if (!r->readLine(0, line) || line.rfind("YUV4MPEG2", 0) != 0)
            return bad("does not start with a YUV4MPEG2 header");
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
        char buf[4096];
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

// ---------------------------------------------------------------------------------------------
// Images: JPEG files are delivered as MJPEG frames holding the file's bytes (so the luma path
// decodes luma only); other formats through cv::imread as GREY or, for 16-bit files, Y16.

Result<std::vector<uint8_t>> readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in)
        return makeError(ErrorKind::NotFound,
                         "cannot open image " + path + ": " + std::strerror(errno));
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
    return bytes;
}

Result<Frame> loadImage(const std::string& path) {
    // A file that cannot be decoded: @p what is wrong with it, and what to do.
    const auto damaged = [&](const std::string& what) {
        return makeError(ErrorKind::Corrupt,
                         "image " + path + " " + what + "; copy or export it again");
    };
    auto bytes = readFile(path);
    if (!bytes) return bytes.error();
    if (bytes->empty()) return damaged("is empty (0 bytes)");
    const bool jpeg = bytes->size() > 3 && (*bytes)[0] == 0xFF && (*bytes)[1] == 0xD8;
    if (jpeg) {
        tjhandle tj = tjInitDecompress();
        int w = 0, h = 0, subsamp = 0, colorspace = 0;
        const int rc =
            tjDecompressHeader3(tj, bytes->data(), bytes->size(), &w, &h, &subsamp, &colorspace);
        const std::string why = rc != 0 ? tjGetErrorStr2(tj) : "";
        tjDestroy(tj);
        if (rc != 0) return damaged("is not a readable JPEG (" + why + ")");
        // A file cut inside its header may still parse without a frame size.
        if (w <= 0 || h <= 0) return damaged("is a JPEG cut short before its frame size");
        if (!withinFrameLimit(w, h))
            return damaged("claims " + std::to_string(w) + "x" + std::to_string(h) +
                           " pixels, more than the " + maxFrameSizeText() + " a frame may hold");
        Frame f = makeCompressedFrame(PixelFormat::MJPEG, {w, h}, bytes->data(), bytes->size());
        f.origin = path;
        return f;
    }
    cv::Mat m;
    try {
        m = cv::imdecode(*bytes, cv::IMREAD_GRAYSCALE | cv::IMREAD_ANYDEPTH);
    } catch (const cv::Exception&) {
        // OpenCV's message is a source location and an assertion: name the file instead.
        return damaged("cannot be decoded: OpenCV rejects it as damaged");
    }
    if (m.empty())
        return makeError(
            ErrorKind::Corrupt,
            "image " + path +
                " cannot be decoded: not an image format OpenCV reads, or damaged; give a JPEG, "
                "PNG, TIFF or another format OpenCV reads");
    PixelFormat format;
    if (m.depth() == CV_8U) {
        format = PixelFormat::GREY;
    } else if (m.depth() == CV_16U) {
        format = PixelFormat::Y16;
    } else {
        return makeError(ErrorKind::Unsupported,
                         "image " + path +
                             " has samples that are neither 8- nor 16-bit integers; "
                             "convert it to 8- or 16-bit PNG or TIFF");
    }
    auto frame = allocateFrame(format, {m.cols, m.rows});
    if (!frame) return frame.error();
    const size_t rowBytes = m.cols * m.elemSize();
    for (int y = 0; y < m.rows; ++y)
        std::memcpy(mutablePlane(*frame, 0) + y * frame->planes[0].stride, m.ptr(y), rowBytes);
    frame->origin = path;
    return frame;
}

class ImageListReader final : public FrameReader {
public:
    ImageListReader(std::vector<std::string> files, std::string text, std::string device,
                    double fps, Frame first)
        : files_(std::move(files)),
          text_(std::move(text)),
          device_(std::move(device)),
          fps_(fps),
          first_(std::move(first)) {}

    SourceInfo info() const override {
        SourceInfo i;
        i.sourceString = text_;
        i.device = device_;
        i.driver = "images";
        i.format = first_.format;
        i.size = first_.size;
        i.fps = fps_;
        i.frameCount = static_cast<int64_t>(files_.size());
        // Viewers take an image without a colour profile as sRGB, and cameras write them so;
        // 16-bit files come from raw converters as often linear as encoded.
        if (first_.format == PixelFormat::Y16) {
            i.transfer.origin =
                "a 16-bit image file may hold linear or encoded levels, and "
                "infocus reads no colour profile";
        } else {
            i.transfer.curve = TransferFunction::Srgb;
            i.transfer.origin =
                "image files are sRGB unless a colour profile says otherwise, "
                "and infocus reads none";
        }
        return i;
    }
    size_t count() const override { return files_.size(); }
    int64_t timestampNs(size_t i) const override { return frameTimeNs(i, fps_); }
    Result<Frame> read(size_t i) override {
        auto f = i == 0 && first_.numPlanes ? Result<Frame>(first_) : loadImage(files_[i]);
        if (!f) return f.error();
        f->sequence = i;
        f->timestampNs = timestampNs(i);
        return f;
    }

private:
    std::vector<std::string> files_;
    std::string text_, device_;
    double fps_;
    Frame first_;
};

// ---------------------------------------------------------------------------------------------
// Video files through OpenCV's VideoCapture (FFmpeg or GStreamer backend), converted to luma.

class VideoReader final : public FrameReader {
public:
    static Result<std::unique_ptr<FrameReader>> open(const std::string& path,
                                                     const std::string& text) {
        std::unique_ptr<VideoReader> r(new VideoReader);
        r->path_ = path;
        r->text_ = text;
        // Quietly: a backend logs every file it refuses.
        const auto level = cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
        for (const int api : videoFileBackends()) {
            try {
                if (r->cap_.open(path, api)) break;
            } catch (const cv::Exception&) {
            }
        }
        cv::utils::logging::setLogLevel(level);
        if (!r->cap_.isOpened())
            return makeError(ErrorKind::Unsupported,
                             "cannot open " + path +
                                 ": not a recording, Y4M, image or video file OpenCV can read");
        const double fps = r->cap_.get(cv::CAP_PROP_FPS);
        r->fps_ = fps > 0 && fps < 1000 ? fps : 30.0;
        const double n = r->cap_.get(cv::CAP_PROP_FRAME_COUNT);
        r->count_ = n > 0 ? static_cast<size_t>(n) : SIZE_MAX / 2;
        r->size_ = {static_cast<int>(r->cap_.get(cv::CAP_PROP_FRAME_WIDTH)),
                    static_cast<int>(r->cap_.get(cv::CAP_PROP_FRAME_HEIGHT))};
        return std::unique_ptr<FrameReader>(std::move(r));
    }

    SourceInfo info() const override {
        SourceInfo i;
        i.sourceString = text_;
        i.device = path_;
        i.driver = "video";
        i.format = PixelFormat::GREY;
        i.size = size_;
        i.fps = fps_;
        if (count_ < SIZE_MAX / 2) i.frameCount = static_cast<int64_t>(count_);
        i.transfer.origin = "OpenCV does not report a video file's transfer function";
        return i;
    }
    size_t count() const override { return count_; }
    int64_t timestampNs(size_t i) const override { return frameTimeNs(i, fps_); }
    Result<Frame> read(size_t i) override {
        if (i != next_) {
            cap_.set(cv::CAP_PROP_POS_FRAMES, static_cast<double>(i));
            next_ = i;
        }
        cv::Mat bgr;
        if (!cap_.read(bgr) || bgr.empty())
            return makeError(ErrorKind::EndOfStream, "end of video " + path_);
        ++next_;
        cv::Mat grey;
        if (bgr.channels() == 3)
            cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
        else if (bgr.channels() == 4)
            cv::cvtColor(bgr, grey, cv::COLOR_BGRA2GRAY);
        else
            grey = bgr;
        if (grey.depth() != CV_8U) grey.convertTo(grey, CV_8U);
        auto frame = allocateFrame(PixelFormat::GREY, {grey.cols, grey.rows});
        if (!frame) return frame.error();
        for (int y = 0; y < grey.rows; ++y)
            std::memcpy(mutablePlane(*frame, 0) + y * frame->planes[0].stride, grey.ptr(y),
                        static_cast<size_t>(grey.cols));
        frame->sequence = i;
        frame->timestampNs = timestampNs(i);
        return frame;
    }

private:
    VideoReader() = default;
    cv::VideoCapture cap_;
    std::string path_, text_;
    double fps_ = 30.0;
    size_t count_ = 0;
    size_t next_ = 0;
    Size size_;
};

// ---------------------------------------------------------------------------------------------

bool isDirectory(const std::string& path) {
    struct stat st;
    return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool exists(const std::string& path) {
    struct stat st;
    return ::stat(path.c_str(), &st) == 0;
}

std::vector<std::string> imagesInDirectory(const std::string& dir) {
    std::vector<std::string> out;
    DIR* d = ::opendir(dir.c_str());
    if (!d) return out;
    while (dirent* e = ::readdir(d)) {
        const std::string name = e->d_name;
        if (name[0] != '.' && isImageExtension(extension(name))) out.push_back(dir + "/" + name);
    }
    ::closedir(d);
    std::sort(out.begin(), out.end());
    return out;
}

Result<std::unique_ptr<FrameSource>> openImages(const SourceSpec& spec,
                                                std::vector<std::string> files) {
    auto options = parsePlaybackOptions(spec);
    if (!options) return options.error();
    auto first = loadImage(files[0]);
    if (!first) return first.error();
    const double fps = options->fps > 0 ? options->fps : 30.0;
    return makePlayback(std::make_unique<ImageListReader>(std::move(files), spec.text, spec.target,
                                                          fps, std::move(*first)),
                        *options);
}

}  // namespace

std::vector<int> videoFileBackends() {
    // Not CAP_ANY, which also offers the path to every camera backend: V4L2 opened the file
    // read-write as a device and gphoto2 scanned the USB bus for cameras (loading some 120
    // driver files) before a file that is no video was refused.
    std::vector<int> apis;
    for (const cv::VideoCaptureAPIs api : {cv::CAP_FFMPEG, cv::CAP_GSTREAMER, cv::CAP_OPENCV_MJPEG})
        if (cv::videoio_registry::hasBackend(api)) apis.push_back(api);
    return apis;
}

Result<std::unique_ptr<FrameSource>> openPathSource(const SourceSpec& spec) {
    std::string path = spec.target;
    while (path.size() > 1 && path.back() == '/')
        path.pop_back();

    if (isDirectory(path)) {
        if (exists(path + "/" + kHeaderFileName)) {
            auto options = parsePlaybackOptions(spec);
            if (!options) return options.error();
            auto reader = RecordingReader::open(path);
            if (!reader) return reader.error();
            return makePlayback(
                std::make_unique<RecordingFrameReader>(std::move(*reader), spec.text), *options);
        }
        auto files = imagesInDirectory(path);
        if (files.empty()) {
            if (exists(path + "/" + kFramesFileName))
                return makeError(ErrorKind::Corrupt,
                                 "recording " + path + " has " + kFramesFileName + " but no " +
                                     kHeaderFileName + "; the recording is damaged");
            return makeError(ErrorKind::NotFound,
                             "directory " + path +
                                 " holds neither a recording (header.json) nor images (.jpg, "
                                 ".png, .tif, .bmp, .pgm, ...)");
        }
        return openImages(spec, std::move(files));
    }
    if (!exists(path)) {
        if (path.find_first_of("*?[") != std::string::npos) {
            glob_t g{};
            std::vector<std::string> files;
            if (::glob(path.c_str(), 0, nullptr, &g) == 0)
                for (size_t i = 0; i < g.gl_pathc; ++i)
                    if (!isDirectory(g.gl_pathv[i])) files.emplace_back(g.gl_pathv[i]);
            ::globfree(&g);
            if (files.empty())
                return makeError(ErrorKind::NotFound,
                                 "no file matches the pattern '" + path + "'; check the path");
            std::sort(files.begin(), files.end());
            return openImages(spec, std::move(files));
        }
        return makeError(ErrorKind::NotFound,
                         "source '" + spec.text + "': " + path +
                             " does not exist; give an existing recording, video, image, "
                             "directory or glob, or a camera (v4l2:, libcamera:, sim:)");
    }
    const std::string ext = extension(path);
    if (ext == "y4m") {
        auto options = parsePlaybackOptions(spec);
        if (!options) return options.error();
        auto reader = Y4mReader::open(path, spec.text);
        if (!reader) return reader.error();
        return makePlayback(std::move(*reader), *options);
    }
    if (isImageExtension(ext)) return openImages(spec, {path});
    auto options = parsePlaybackOptions(spec);
    if (!options) return options.error();
    auto reader = VideoReader::open(path, spec.text);
    if (!reader) return reader.error();
    return makePlayback(std::move(*reader), *options);
}

}  // namespace infocus::replay
