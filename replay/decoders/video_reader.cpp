// SPDX-License-Identifier: MIT
// Video files through OpenCV's VideoCapture (FFmpeg or GStreamer backend), converted to luma.
// Part of the decoder module.
#include <cstdint>
#include <cstring>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <opencv2/videoio/registry.hpp>
#include <optional>

#include "replay/decoders/decoders.h"
#include "replay/file_readers.h"

namespace infocus::replay {

namespace {

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
        if (!cap_.read(bgr) || bgr.empty()) {
            // Short of the container's count: the rest is missing, said once at the end.
            if (count_ < SIZE_MAX / 2 && (!decodedTo_ || i < *decodedTo_)) decodedTo_ = i;
            return makeError(ErrorKind::EndOfStream, "end of video " + path_);
        }
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

    std::optional<Error> trailingError() const override {
        if (!decodedTo_) return std::nullopt;
        const size_t missing = count_ - *decodedTo_;
        return makeError(ErrorKind::Corrupt,
                         "video " + path_ + ": its container lists " + std::to_string(count_) +
                             " frames, " + std::to_string(missing) + " of them (frames " +
                             std::to_string(*decodedTo_) + " to " + std::to_string(count_ - 1) +
                             ") could not be decoded; the file is truncated or damaged");
    }

private:
    VideoReader() = default;
    cv::VideoCapture cap_;
    std::string path_, text_;
    double fps_ = 30.0;
    size_t count_ = 0;
    size_t next_ = 0;
    Size size_;
    std::optional<size_t> decodedTo_;  ///< the first frame that did not decode, if any
};

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

Result<std::unique_ptr<FrameReader>> openVideoReader(const std::string& path,
                                                     const std::string& text) {
    return VideoReader::open(path, text);
}

}  // namespace infocus::replay
