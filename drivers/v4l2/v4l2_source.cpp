// SPDX-License-Identifier: MIT
#include "drivers/v4l2/v4l2_source.h"

#include <poll.h>
#include <sys/mman.h>
#include <time.h>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <mutex>
#include <vector>

#include "drivers/common/mode_choice.h"
#include "drivers/v4l2/media_lens.h"
#include "drivers/v4l2/v4l2_device.h"

namespace infocus::v4l2 {

namespace {

// Enough buffers that the caller can hold one or two frames while the driver fills the rest.
constexpr unsigned kBufferCount = 4;
// A camera that sends nothing for this long is stalled (the slowest modes are ~1 fps).
constexpr int kFrameTimeoutMs = 5000;
// Frames a typical voice-coil lens needs to stop moving at 30 fps.
constexpr int kDefaultSettleFrames = 2;
// How often the input's signal status is read while streaming.
constexpr int64_t kSignalCheckNs = 250'000'000;

int64_t monotonicNowNs() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return int64_t(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

// The mapped buffers. Shared by the source and every frame it lent out: a frame returns its
// buffer here when dropped, and the memory stays mapped until the last of them is gone.
struct BufferPool {
    struct Mapping {
        void* addr = MAP_FAILED;
        size_t length = 0;
    };
    std::vector<std::vector<Mapping>> buffers;  // [buffer][plane]
    std::mutex mutex;
    std::vector<unsigned> returned;  // buffers frames gave back, to queue again

    ~BufferPool() {
        for (auto& planes : buffers)
            for (auto& m : planes)
                if (m.addr != MAP_FAILED) ::munmap(m.addr, m.length);
    }
};

class V4l2Focus : public FocusControl {
public:
    V4l2Focus(const Device& dev, v4l2_queryctrl q, int settle)
        : dev_(dev), q_(q), settle_(settle) {}

    FocusRange range() const override {
        return {double(q_.minimum), double(q_.maximum), double(q_.step), double(q_.default_value),
                "v4l2"};
    }

    Result<LensPosition> get() override {
        auto v = dev_.getControl(V4L2_CID_FOCUS_ABSOLUTE);
        if (!v) return v.error();
        return LensPosition{double(*v), "v4l2", std::nullopt};
    }

    Status set(double value) override {
        // Continuous autofocus would fight a manual position: switch it off first.
        if (dev_.queryControl(V4L2_CID_FOCUS_AUTO)) {
            auto af = dev_.getControl(V4L2_CID_FOCUS_AUTO);
            if (af && *af != 0)
                if (int r = dev_.setControl(V4L2_CID_FOCUS_AUTO, 0); r < 0)
                    return makeError(
                        ErrorKind::Device,
                        dev_.path() + ": cannot turn continuous autofocus off: " + errnoText(r),
                        -r);
        }
        // A one-shot autofocus run in progress would move the lens after us.
        if (dev_.queryControl(V4L2_CID_AUTO_FOCUS_STATUS) &&
            dev_.queryControl(V4L2_CID_AUTO_FOCUS_STOP)) {
            auto st = dev_.getControl(V4L2_CID_AUTO_FOCUS_STATUS);
            if (st && (*st & V4L2_AUTO_FOCUS_STATUS_BUSY))
                (void)dev_.setControl(V4L2_CID_AUTO_FOCUS_STOP, 1);
        }
        const double v = capture::snapToStep(value, q_.minimum, q_.maximum, q_.step);
        if (int r = dev_.setControl(V4L2_CID_FOCUS_ABSOLUTE, static_cast<int32_t>(v)); r < 0)
            return makeError(ErrorKind::Device,
                             dev_.path() + ": cannot set focus_absolute to " +
                                 std::to_string(int(v)) + ": " + errnoText(r),
                             -r);
        return {};
    }

    int settleFrames() const override { return settle_; }

private:
    const Device& dev_;
    v4l2_queryctrl q_;
    int settle_;
};

class V4l2Source : public FrameSource {
public:
    V4l2Source(Device dev, capture::Mode mode, int settle)
        : dev_(std::move(dev)), mode_(mode), pool_(std::make_shared<BufferPool>()) {
        if (auto q = dev_.queryControl(V4L2_CID_FOCUS_ABSOLUTE)) {
            focus_ = std::make_unique<V4l2Focus>(dev_, *q, settle);
        } else if (auto lens = findLensOfVideoNode(dev_.path())) {
            // A media-controller camera: the lens is a sub-device of the sensor feeding this node.
            // One that cannot be opened leaves the camera without focus, as a node without one.
            if (auto f = openLensFocus(*lens, settle)) focus_ = std::move(*f);
        }
    }
    ~V4l2Source() override { stop(); }

    Status init() {
        const uint32_t type = dev_.capability().bufType();
        v4l2_format fmt{};
        fmt.type = type;
        if (int r = dev_.ioctl(VIDIOC_G_FMT, &fmt); r < 0) return devError("VIDIOC_G_FMT", r);
        mplane_ = dev_.capability().multiplanar();
        if (mplane_) {
            stride_ = fmt.fmt.pix_mp.plane_fmt[0].bytesperline;
            transfer_ = transferFromV4l2(fmt.fmt.pix_mp.colorspace, fmt.fmt.pix_mp.xfer_func);
        } else {
            stride_ = fmt.fmt.pix.bytesperline;
            transfer_ = transferFromV4l2(fmt.fmt.pix.colorspace, fmt.fmt.pix.xfer_func);
        }
        v4l2_requestbuffers req{};
        req.count = kBufferCount;
        req.type = type;
        req.memory = V4L2_MEMORY_MMAP;
        if (int r = dev_.ioctl(VIDIOC_REQBUFS, &req); r < 0) return devError("VIDIOC_REQBUFS", r);
        if (req.count < 2)
            return makeError(ErrorKind::Device, dev_.path() + ": the driver gave " +
                                                    std::to_string(req.count) +
                                                    " buffer(s); streaming needs at least 2");
        pool_->buffers.resize(req.count);
        for (unsigned i = 0; i < req.count; ++i) {
            v4l2_buffer buf{};
            v4l2_plane planes[VIDEO_MAX_PLANES]{};
            buf.type = type;
            buf.memory = V4L2_MEMORY_MMAP;
            buf.index = i;
            if (mplane_) {
                buf.m.planes = planes;
                buf.length = VIDEO_MAX_PLANES;
            }
            if (int r = dev_.ioctl(VIDIOC_QUERYBUF, &buf); r < 0)
                return devError("VIDIOC_QUERYBUF", r);
            const unsigned n = mplane_ ? buf.length : 1;
            for (unsigned p = 0; p < n; ++p) {
                const size_t length = mplane_ ? planes[p].length : buf.length;
                const off_t offset = mplane_ ? planes[p].m.mem_offset : buf.m.offset;
                void* addr =
                    ::mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_SHARED, dev_.fd(), offset);
                if (addr == MAP_FAILED)
                    return makeError(ErrorKind::Device,
                                     dev_.path() + ": cannot map buffer " + std::to_string(i) +
                                         ": " + errnoText(errno),
                                     errno);
                pool_->buffers[i].push_back({addr, length});
            }
        }
        return {};
    }

    SourceInfo info() const override {
        SourceInfo i;
        i.sourceString = "v4l2:" + dev_.path();
        i.device = dev_.path();
        i.driver = dev_.capability().driver;
        i.format = mode_.format;
        i.size = mode_.size;
        i.fps = mode_.fps;
        i.liveCamera = true;
        i.transfer = transfer_;
        return i;
    }

    Status start() override {
        if (streaming_) return {};
        for (unsigned i = 0; i < pool_->buffers.size(); ++i)
            if (Status s = requeue(i); !s) return s;
        if (Status s = retryRefused(); !s) return s;
        uint32_t type = dev_.capability().bufType();
        if (int r = dev_.ioctl(VIDIOC_STREAMON, &type); r < 0) {
            if (r == -EPIPE && dev_.capability().mediaController())
                return makeError(ErrorKind::Unsupported,
                                 dev_.path() +
                                     " is one node of a media-controller pipeline that is "
                                     "not configured; open the camera through libcamera "
                                     "('infocus devices' lists it) or set the pipeline up "
                                     "with media-ctl",
                                 EPIPE);
            if (r == -ENODEV) return devError("VIDIOC_STREAMON", r);
            return makeError(ErrorKind::Device,
                             dev_.path() +
                                 ": the driver refused to start streaming "
                                 "(VIDIOC_STREAMON: " +
                                 errnoText(r) + ")",
                             -r);
        }
        streaming_ = true;
        signalLostNs_.reset();
        nextSignalCheckNs_ = 0;
        if (focus_) {
            if (auto p = focus_->get()) lens_ = *p;
        }
        // Exposure is reported only when it is fixed (auto exposure would change it per frame).
        auto mode = dev_.getControl(V4L2_CID_EXPOSURE_AUTO);
        auto exposure = dev_.getControl(V4L2_CID_EXPOSURE_ABSOLUTE);
        if (mode && *mode == V4L2_EXPOSURE_MANUAL && exposure) exposureS_ = *exposure * 100e-6;
        return {};
    }

    Result<Frame> next() override {
        if (!streaming_)
            return makeError(ErrorKind::Usage, dev_.path() + ": next() before start()");
        if (gone_)
            return makeError(ErrorKind::Device, dev_.path() + ": the device was disconnected");
        requeueReturned();
        while (true) {
            if (Status s = retryRefused(); !s) return s.error();
            pollfd p{dev_.fd(), POLLIN, 0};
            const int n = ::poll(&p, 1, kFrameTimeoutMs);
            if (n < 0 && errno == EINTR) continue;
            if (n == 0)
                return makeError(ErrorKind::Device,
                                 dev_.path() + ": no frame for " +
                                     std::to_string(kFrameTimeoutMs / 1000) +
                                     " s; is the camera stalled or its input without signal?");
            v4l2_buffer buf{};
            v4l2_plane planes[VIDEO_MAX_PLANES]{};
            buf.type = dev_.capability().bufType();
            buf.memory = V4L2_MEMORY_MMAP;
            if (mplane_) {
                buf.m.planes = planes;
                buf.length = VIDEO_MAX_PLANES;
            }
            const int r = dev_.ioctl(VIDIOC_DQBUF, &buf);
            if (r == -EAGAIN) continue;
            if (r == -ENODEV) {
                gone_ = true;
                return makeError(
                    ErrorKind::Device,
                    dev_.path() + ": the device was disconnected while streaming (after " +
                        std::to_string(stats_.delivered) + " frames); reconnect it and start again",
                    ENODEV);
            }
            if (r < 0) return devError("VIDIOC_DQBUF", r);
            --queued_;
            const uint64_t gap = seq_.update(buf.sequence);
            stats_.dropped += gap;
            if (buf.flags & V4L2_BUF_FLAG_ERROR) {
                ++stats_.errors;
                if (Status s = requeue(buf.index); !s) return s.error();
                continue;
            }
            // Without a signal an input delivers noise, not a picture: skipped and counted as
            // damaged, and the run ends when it does not come back.
            if (Status s = checkSignal(); !s) return s.error();
            if (signalLostNs_) {
                ++stats_.errors;
                if (Status s = requeue(buf.index); !s) return s.error();
                continue;
            }
            auto frame = makeFrame(buf, planes);
            if (!frame) {
                ++stats_.errors;
                if (Status s = requeue(buf.index); !s) return s.error();
                continue;
            }
            ++stats_.delivered;
            return frame;
        }
    }

    void stop() override {
        if (!streaming_) return;
        uint32_t type = dev_.capability().bufType();
        (void)dev_.ioctl(VIDIOC_STREAMOFF, &type);  // fails only on a vanished device
        streaming_ = false;
    }

    SourceStats stats() const override { return stats_; }
    FocusControl* focusControl() override { return focus_.get(); }

private:
    Error devError(const char* what, int r) const {
        if (r == -ENODEV)
            return makeError(ErrorKind::Device,
                             dev_.path() + ": the device was disconnected (" + what + ")", ENODEV);
        return makeError(ErrorKind::Device, dev_.path() + ": " + what + " failed: " + errnoText(r),
                         -r);
    }

    Status queue(unsigned index) {
        v4l2_buffer buf{};
        v4l2_plane planes[VIDEO_MAX_PLANES]{};
        buf.type = dev_.capability().bufType();
        buf.memory = V4L2_MEMORY_MMAP;
        buf.index = index;
        if (mplane_) {
            buf.m.planes = planes;
            buf.length = static_cast<uint32_t>(pool_->buffers[index].size());
        }
        if (int r = dev_.ioctl(VIDIOC_QBUF, &buf); r < 0) return devError("VIDIOC_QBUF", r);
        ++queued_;
        return {};
    }

    void requeueReturned() {
        std::vector<unsigned> back;
        {
            std::lock_guard lock(pool_->mutex);
            back.swap(pool_->returned);
        }
        for (unsigned i : back)
            (void)requeue(i);  // fails only on a disconnect, which the next DQBUF reports
    }

    // Gives a buffer back to the driver. A refusal is counted as damage and the buffer tried again
    // before the next wait (a driver may refuse one buffer once); only a disconnect fails here.
    Status requeue(unsigned index) {
        Status s = queue(index);
        if (s || s.error().sysErrno == ENODEV) return s;
        ++stats_.errors;
        refused_.push_back(index);
        refusedError_ = s.error().message;
        return {};
    }

    // Queues the buffers the driver refused; a second refusal of the same buffer ends the run.
    Status retryRefused() {
        std::vector<unsigned> again;
        again.swap(refused_);
        for (unsigned index : again)
            if (Status s = queue(index); !s) {
                if (s.error().sysErrno == ENODEV) return s;
                return makeError(ErrorKind::Device,
                                 dev_.path() + ": the driver refused buffer " +
                                     std::to_string(index) + " twice (" + s.error().message +
                                     "; first: " + refusedError_ + ")",
                                 s.error().sysErrno);
            }
        return {};
    }

    // Reads the input's status (VIDIOC_ENUMINPUT) at most every kSignalCheckNs: keeps when the
    // signal was lost, and fails once it has been gone for kFrameTimeoutMs.
    Status checkSignal() {
        const int64_t now = monotonicNowNs();
        if (now < nextSignalCheckNs_) return {};
        nextSignalCheckNs_ = now + kSignalCheckNs;
        v4l2_input in{};
        int index = 0;
        if (dev_.ioctl(VIDIOC_G_INPUT, &index) < 0) return {};
        in.index = static_cast<uint32_t>(index);
        if (dev_.ioctl(VIDIOC_ENUMINPUT, &in) < 0) return {};
        const uint32_t lost =
            V4L2_IN_ST_NO_POWER | V4L2_IN_ST_NO_SIGNAL | V4L2_IN_ST_NO_H_LOCK | V4L2_IN_ST_NO_SYNC;
        if (!(in.status & lost)) {
            signalLostNs_.reset();
            return {};
        }
        if (!signalLostNs_) signalLostNs_ = now;
        if (now - *signalLostNs_ < int64_t(kFrameTimeoutMs) * 1000000) return {};
        const std::string what = (in.status & V4L2_IN_ST_NO_POWER)    ? "no power"
                                 : (in.status & V4L2_IN_ST_NO_SIGNAL) ? "no signal"
                                                                      : "no sync (horizontal lock)";
        return makeError(
            ErrorKind::Device,
            dev_.path() + ": input " + std::to_string(index) + " (" +
                std::string(reinterpret_cast<const char*>(in.name),
                            strnlen(reinterpret_cast<const char*>(in.name), sizeof in.name)) +
                ") has had " + what + " for " + std::to_string(kFrameTimeoutMs / 1000) +
                " s (after " + std::to_string(stats_.delivered) +
                " frames); connect a source to it or choose another input (input=N)");
    }

    // Wraps a dequeued buffer as a Frame: zero copy while the driver keeps a buffer to fill,
    // a copy when the caller already holds all the others.
    Result<Frame> makeFrame(const v4l2_buffer& buf, const v4l2_plane* planes) {
        const auto& maps = pool_->buffers[buf.index];
        Frame f;
        f.format = mode_.format;
        f.size = mode_.size;
        f.sequence = buf.sequence;
        f.lens = lens_;
        f.exposureS = exposureS_;
        const bool monotonic =
            (buf.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
        f.timestampNs = monotonic ? int64_t(buf.timestamp.tv_sec) * 1000000000 +
                                        int64_t(buf.timestamp.tv_usec) * 1000
                                  : monotonicNowNs();
        if (focus_) {
            // The position a move asked for, once the caller let it settle.
            if (auto p = focus_->get()) f.lens = lens_ = *p;
        }
        if (mode_.format == PixelFormat::MJPEG) {
            const size_t used = mplane_ ? planes[0].bytesused : buf.bytesused;
            if (used == 0) return makeError(ErrorKind::Corrupt, "empty buffer");
            f.planes[0] = {static_cast<const uint8_t*>(maps[0].addr), 0, used};
            f.numPlanes = 1;
        } else {
            auto layout = frameLayout(mode_.format, mode_.size, stride_);
            if (!layout) return layout.error();
            if (maps.size() == 1) {
                const size_t used = mplane_ ? planes[0].bytesused : buf.bytesused;
                // A short buffer is a damaged frame; some drivers leave bytesused 0 for "all".
                if (used != 0 && used < layout->totalSize)
                    return makeError(ErrorKind::Corrupt, "short buffer");
                const auto* base = static_cast<const uint8_t*>(maps[0].addr);
                size_t offset = 0;
                for (unsigned p = 0; p < layout->numPlanes; ++p) {
                    f.planes[p] = {base + offset, layout->stride[p], layout->size[p]};
                    offset += layout->size[p];
                }
            } else {
                if (maps.size() != layout->numPlanes)
                    return makeError(ErrorKind::Unsupported, "plane count mismatch");
                for (unsigned p = 0; p < layout->numPlanes; ++p) {
                    if (planes[p].bytesused != 0 && planes[p].bytesused < layout->size[p])
                        return makeError(ErrorKind::Corrupt, "short plane");
                    f.planes[p] = {
                        static_cast<const uint8_t*>(maps[p].addr) + planes[p].data_offset,
                        layout->stride[p], layout->size[p]};
                }
            }
            f.numPlanes = layout->numPlanes;
        }
        if (queued_ == 0) {
            // The driver would starve: hand out a copy and give the buffer straight back.
            auto copy = copyFrame(f);
            // The buffer goes back to the driver whether or not the copy worked.
            if (Status s = requeue(buf.index); !s) return s.error();
            if (!copy) return copy.error();
            return *copy;
        }
        auto pool = pool_;
        const unsigned index = buf.index;
        f.storage = std::shared_ptr<const void>(maps[0].addr, [pool, index](const void*) {
            std::lock_guard lock(pool->mutex);
            pool->returned.push_back(index);
        });
        return f;
    }

    Device dev_;
    capture::Mode mode_;
    std::shared_ptr<BufferPool> pool_;
    std::unique_ptr<FocusControl> focus_;  // the node's FOCUS_ABSOLUTE or its lens sub-device's
    bool mplane_ = false;
    size_t stride_ = 0;
    TransferReport transfer_;  // what the format says of its grey levels
    unsigned queued_ = 0;
    std::vector<unsigned> refused_;        // buffers the driver refused, to queue again
    std::string refusedError_;             // why, for the message if it refuses again
    std::optional<int64_t> signalLostNs_;  // when the input was first seen without a signal
    int64_t nextSignalCheckNs_ = 0;
    bool streaming_ = false;
    bool gone_ = false;
    capture::SequenceTracker seq_;
    SourceStats stats_;
    std::optional<LensPosition> lens_;
    std::optional<double> exposureS_;
};

Result<int> parseInt(const SourceSpec& spec, const std::string& key, int fallback) {
    auto it = spec.options.find(key);
    if (it == spec.options.end()) return fallback;
    int v = 0;
    const auto& t = it->second;
    auto [p, e] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (e != std::errc() || p != t.data() + t.size() || v < 0)
        return makeError(ErrorKind::Usage, "source '" + spec.text + "': " + key + "=" + t +
                                               ": give a whole number ≥ 0");
    return v;
}

// Sets format, size and rate; the driver may adjust a request, which counts as a failure.
Status applyMode(const Device& dev, const capture::Mode& mode) {
    v4l2_format fmt{};
    fmt.type = dev.capability().bufType();
    if (int r = dev.ioctl(VIDIOC_G_FMT, &fmt); r < 0)
        return makeError(ErrorKind::Device, dev.path() + ": VIDIOC_G_FMT failed: " + errnoText(r),
                         -r);
    if (dev.capability().multiplanar()) {
        fmt.fmt.pix_mp.pixelformat = mode.fourcc;
        fmt.fmt.pix_mp.width = mode.size.width;
        fmt.fmt.pix_mp.height = mode.size.height;
    } else {
        fmt.fmt.pix.pixelformat = mode.fourcc;
        fmt.fmt.pix.width = mode.size.width;
        fmt.fmt.pix.height = mode.size.height;
        fmt.fmt.pix.bytesperline = 0;
    }
    if (int r = dev.ioctl(VIDIOC_S_FMT, &fmt); r < 0)
        return makeError(ErrorKind::Device,
                         dev.path() + ": cannot set format " + pixelFormatName(mode.format) + " " +
                             std::to_string(mode.size.width) + "x" +
                             std::to_string(mode.size.height) + ": " + errnoText(r) +
                             (r == -EBUSY ? " (another program is streaming from it)" : ""),
                         -r);
    const bool mp = dev.capability().multiplanar();
    const uint32_t gotFourcc = mp ? fmt.fmt.pix_mp.pixelformat : fmt.fmt.pix.pixelformat;
    const Size got{int(mp ? fmt.fmt.pix_mp.width : fmt.fmt.pix.width),
                   int(mp ? fmt.fmt.pix_mp.height : fmt.fmt.pix.height)};
    if (gotFourcc != mode.fourcc || !(got == mode.size))
        return makeError(ErrorKind::Unsupported,
                         dev.path() + ": asked for " + pixelFormatName(mode.format) + " " +
                             std::to_string(mode.size.width) + "x" +
                             std::to_string(mode.size.height) + ", the driver chose " +
                             pixelFormatName(static_cast<PixelFormat>(gotFourcc)) + " " +
                             std::to_string(got.width) + "x" + std::to_string(got.height) +
                             "; pick a mode 'infocus devices' lists");
    if (mode.fps > 0) {
        v4l2_streamparm parm{};
        parm.type = dev.capability().bufType();
        // timeperframe = 1/fps, in thousandths so 29.97 survives.
        parm.parm.capture.timeperframe.numerator = 1000;
        parm.parm.capture.timeperframe.denominator = static_cast<uint32_t>(mode.fps * 1000 + 0.5);
        (void)dev.ioctl(VIDIOC_S_PARM,
                        &parm);  // not every driver sets a rate; the mode still works
    }
    return {};
}

}  // namespace

Result<std::unique_ptr<FrameSource>> openV4l2Source(const SourceSpec& spec) {
    const std::string path = spec.target.empty() ? "/dev/video0" : spec.target;
    for (const auto& [key, value] : spec.options)
        if (key != "input" && key != "format" && key != "size" && key != "fps" && key != "settle")
            return makeError(ErrorKind::Usage,
                             "source '" + spec.text + "': unknown option '" + key +
                                 "'; V4L2 sources take input, format, size, fps, settle");
    auto request = capture::parseModeRequest(spec.options, spec.text);
    if (!request) return request.error();
    auto settle = parseInt(spec, "settle", kDefaultSettleFrames);
    if (!settle) return settle.error();
    auto input = parseInt(spec, "input", -1);
    if (!input) return input.error();

    auto dev = Device::open(path);
    if (!dev) return dev.error();
    if (!dev->capability().capture())
        return makeError(
            ErrorKind::Unsupported,
            path + " (" + dev->capability().card +
                ") is not a streaming capture node; 'infocus devices' lists those that are");
    if (spec.options.count("input")) {
        int index = *input;
        if (int r = dev->ioctl(VIDIOC_S_INPUT, &index); r < 0)
            return makeError(
                r == -EINVAL ? ErrorKind::Usage : ErrorKind::Device,
                path + ": cannot select input " + std::to_string(*input) + ": " + errnoText(r), -r);
    }
    auto offered = dev->enumerateFormats();
    const auto current = dev->currentMode();
    // Drivers that enumerate no sizes (e.g. analogue inputs) still stream their current size,
    // and may accept a requested one.
    for (auto& f : offered) {
        if (!f.sizes.empty()) continue;
        if (current)
            f.sizes.push_back({current->size, current->fps > 0 ? std::vector{current->fps}
                                                               : std::vector<double>{}});
        if (request->size && !(current && current->size == *request->size))
            f.sizes.push_back({*request->size, {}});
    }
    // Stepwise ranges are sampled; a requested size inside one is confirmed with VIDIOC_TRY_FMT.
    if (request->size)
        for (auto& f : offered) {
            if (request->format && f.format != *request->format) continue;
            const bool listed = std::any_of(f.sizes.begin(), f.sizes.end(), [&](const auto& o) {
                return o.size == *request->size;
            });
            if (!listed && dev->trySize(f.fourcc, *request->size))
                f.sizes.push_back({*request->size, {}});
        }
    auto mode = capture::chooseMode(offered, *request, current);
    if (!mode)
        return makeError(mode.error().kind,
                         path + " (" + dev->capability().card + "): " + mode.error().message);
    if (!(current && *current == *mode && request->empty()))
        if (Status s = applyMode(*dev, *mode); !s) return s.error();

    auto source = std::make_unique<V4l2Source>(std::move(*dev), *mode, *settle);
    if (Status s = source->init(); !s) return s.error();
    return std::unique_ptr<FrameSource>(std::move(source));
}

std::vector<DeviceInfo> listV4l2Devices() {
    std::vector<DeviceInfo> out;
    for (const auto& node : findCaptureNodes())
        if (auto info = describeDevice(node)) out.push_back(std::move(*info));
    return out;
}

}  // namespace infocus::v4l2
