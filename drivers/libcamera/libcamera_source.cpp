// SPDX-License-Identifier: MIT
#include "drivers/libcamera/libcamera_source.h"

#include <libcamera/camera.h>
#include <libcamera/camera_manager.h>
#include <libcamera/color_space.h>
#include <libcamera/control_ids.h>
#include <libcamera/formats.h>
#include <libcamera/framebuffer.h>
#include <libcamera/framebuffer_allocator.h>
#include <libcamera/property_ids.h>
#include <libcamera/request.h>
#include <sys/mman.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>

#include "drivers/common/mode_choice.h"
#include "drivers/libcamera/libcamera_compat.h"
#include "drivers/v4l2/media_lens.h"

namespace infocus::libcam {

namespace lc = libcamera;

namespace {

// Controls queued with a request take effect a few frames later (sensor pipeline delay).
constexpr int kDefaultSettleFrames = 3;
constexpr auto kFrameTimeout = std::chrono::seconds(5);
constexpr unsigned kMinBuffers = 4;

// libcamera allows one CameraManager per process: share it between listing and sources, and
// stop it when the last user is gone.
std::shared_ptr<lc::CameraManager> cameraManager(std::string& error) {
    static std::mutex mutex;
    static std::weak_ptr<lc::CameraManager> shared;
    std::lock_guard lock(mutex);
    if (auto m = shared.lock()) return m;
    // libcamera logs INFO lines to stderr by default; keep stderr for infocus's own messages
    // unless the user asked for libcamera's logs (LIBCAMERA_LOG_LEVELS set).
    // Its categories are created lazily and take their level from this variable when the logger
    // first reads it, so it is set (without overriding the user's) before anything logs.
    ::setenv("LIBCAMERA_LOG_LEVELS", "*:ERROR", 0);
    auto m = std::make_shared<lc::CameraManager>();
    if (int r = m->start(); r < 0) {
        error = "libcamera camera manager did not start: " + std::string(std::strerror(-r));
        return nullptr;
    }
    shared = m;
    return m;
}

// libcamera names formats by DRM fourcc, whose RGB names give the word order: DRM RGB888 is
// B,G,R in memory.
PixelFormat fromLibcamera(const lc::PixelFormat& f) {
    static const std::pair<lc::PixelFormat, PixelFormat> kMap[] = {
        {lc::formats::YUYV, PixelFormat::YUYV},     {lc::formats::UYVY, PixelFormat::UYVY},
        {lc::formats::NV12, PixelFormat::NV12},     {lc::formats::NV21, PixelFormat::NV21},
        {lc::formats::YUV420, PixelFormat::YU12},   {lc::formats::R8, PixelFormat::GREY},
        {lc::formats::RGB888, PixelFormat::BGR24},  {lc::formats::BGR888, PixelFormat::RGB24},
        {lc::formats::MJPEG, PixelFormat::MJPEG},   {lc::formats::SRGGB8, PixelFormat::SRGGB8},
        {lc::formats::SGRBG8, PixelFormat::SGRBG8}, {lc::formats::SGBRG8, PixelFormat::SGBRG8},
        {lc::formats::SBGGR8, PixelFormat::SBGGR8},
    };
    for (const auto& [l, p] : kMap)
        if (l == f) return p;
    return PixelFormat::Invalid;
}

// The transfer function of a stream's colour space (StreamConfiguration::colorSpace).
TransferReport transferOf(const std::optional<lc::ColorSpace>& cs) {
    if (!cs) return {std::nullopt, "libcamera reports no colour space for the stream"};
    const std::string how = "libcamera's colour space " + cs->toString();
    switch (cs->transferFunction) {
        case lc::ColorSpace::TransferFunction::Linear:
            return {TransferFunction::Linear, how};
        case lc::ColorSpace::TransferFunction::Srgb:
            return {TransferFunction::Srgb, how};
        case lc::ColorSpace::TransferFunction::Rec709:
            return {TransferFunction::Rec709, how};
    }
    return {std::nullopt, how + ", whose transfer function is unknown to infocus"};
}

std::optional<double> maxFps(const lc::Camera& camera) {
    auto it = camera.controls().find(&lc::controls::FrameDurationLimits);
    if (it == camera.controls().end()) return std::nullopt;
    const int64_t minUs = it->second.min().get<int64_t>();
    if (minUs <= 0) return std::nullopt;
    return 1e6 / double(minUs);
}

// The viewfinder formats and sizes as mode options (libcamera 0.0.3 has no per-size rates: the
// camera's shortest frame duration stands for all).
std::vector<capture::FormatOption> offeredModes(lc::Camera& camera,
                                                const lc::StreamConfiguration& sc) {
    std::vector<capture::FormatOption> out;
    const auto fps = maxFps(camera);
    const lc::StreamFormats& formats = sc.formats();
    for (const lc::PixelFormat& pf : formats.pixelformats()) {
        capture::FormatOption f;
        f.fourcc = pf.fourcc();
        f.format = fromLibcamera(pf);
        f.description = pf.toString();
        auto sizes = formats.sizes(pf);
        if (sizes.empty()) sizes.push_back(formats.range(pf).max);
        for (const lc::Size& s : sizes) {
            capture::SizeOption o{{int(s.width), int(s.height)}, {}};
            if (fps) o.fps.push_back(*fps);
            f.sizes.push_back(o);
        }
        out.push_back(std::move(f));
    }
    return out;
}

Result<std::shared_ptr<lc::Camera>> findCamera(lc::CameraManager& manager,
                                               const std::string& target) {
    auto cameras = manager.cameras();
    if (cameras.empty())
        return makeError(ErrorKind::NotFound,
                         "libcamera finds no camera; check 'infocus devices' and that the camera "
                         "is connected and not in use");
    if (target.empty()) return cameras.front();
    int index = -1;
    auto [p, e] = std::from_chars(target.data(), target.data() + target.size(), index);
    if (e == std::errc() && p == target.data() + target.size()) {
        if (index >= 0 && size_t(index) < cameras.size()) return cameras[size_t(index)];
        return makeError(ErrorKind::NotFound, "libcamera camera " + target +
                                                  " does not exist; there are " +
                                                  std::to_string(cameras.size()) +
                                                  " (indices from 0, see 'infocus devices')");
    }
    if (auto cam = manager.get(target)) return cam;
    return makeError(ErrorKind::NotFound, "libcamera has no camera with id '" + target +
                                              "'; 'infocus devices' lists the ids");
}

struct BufferPool {
    struct Map {
        void* addr = MAP_FAILED;
        size_t length = 0;
    };
    std::vector<Map> maps;
    std::map<const lc::FrameBuffer*, std::vector<const uint8_t*>> planes;  // per buffer, per plane
    std::mutex mutex;
    std::vector<lc::Request*> returned;
    ~BufferPool() {
        for (auto& m : maps)
            if (m.addr != MAP_FAILED) ::munmap(m.addr, m.length);
    }
};

class LibcameraFocus : public FocusControl {
public:
    LibcameraFocus(const lc::ControlInfo& info, bool hasAfMode, int settle)
        : min_(info.min().get<float>()),
          max_(info.max().get<float>()),
          def_(info.def().isNone() ? min_ : info.def().get<float>()),
          hasAfMode_(hasAfMode),
          settle_(settle) {}

    FocusRange range() const override { return {min_, max_, 0.0, def_, "dioptre"}; }

    Result<LensPosition> get() override {
        std::lock_guard lock(mutex_);
        if (!current_)
            return makeError(ErrorKind::Unsupported,
                             "the lens position is not known before the first frame or move");
        return LensPosition{*current_, "dioptre", *current_};
    }

    Status set(double value) override {
        std::lock_guard lock(mutex_);
        pending_ = std::clamp(value, min_, max_);
        return {};
    }

    int settleFrames() const override { return settle_; }

    // Puts a pending move into the controls of the next request.
    void apply(lc::ControlList& controls) {
        std::lock_guard lock(mutex_);
        if (!pending_) return;
        if (hasAfMode_) controls.set(lc::controls::AfMode, lc::controls::AfModeManual);
        controls.set(lc::controls::LensPosition, static_cast<float>(*pending_));
        current_ = pending_;
        pending_.reset();
    }

    void observed(double value) {
        std::lock_guard lock(mutex_);
        current_ = value;
    }

private:
    double min_, max_, def_;
    bool hasAfMode_;
    int settle_;
    std::mutex mutex_;
    std::optional<double> pending_, current_;
};

class LibcameraSource : public FrameSource {
public:
    LibcameraSource(std::shared_ptr<lc::CameraManager> manager, std::shared_ptr<lc::Camera> camera)
        : manager_(std::move(manager)),
          camera_(std::move(camera)),
          pool_(std::make_shared<BufferPool>()) {}

    ~LibcameraSource() override {
        stop();
        requests_.clear();
        allocator_.reset();
        if (acquired_) camera_->release();
    }

    Status init(const SourceSpec& spec, int settle) {
        if (int r = camera_->acquire(); r < 0)
            return makeError(ErrorKind::Device,
                             "libcamera camera '" + camera_->id() +
                                 "' is in use by another program (" + std::strerror(-r) + ")",
                             -r);
        acquired_ = true;
        config_ = viewfinderConfiguration(*camera_);
        if (!config_ || config_->empty())
            return makeError(ErrorKind::Unsupported, "libcamera camera '" + camera_->id() +
                                                         "' offers no viewfinder stream");
        lc::StreamConfiguration& sc = config_->at(0);
        auto request = capture::parseModeRequest(spec.options, spec.text);
        if (!request) return request.error();
        capture::Mode current{sc.pixelFormat.fourcc(),
                              fromLibcamera(sc.pixelFormat),
                              {int(sc.size.width), int(sc.size.height)},
                              maxFps(*camera_).value_or(0)};
        auto mode = capture::chooseMode(offeredModes(*camera_, sc), *request, current);
        if (!mode)
            return makeError(mode.error().kind,
                             "libcamera camera '" + camera_->id() + "': " + mode.error().message);
        mode_ = *mode;
        requestedFps_ = request->fps;
        sc.pixelFormat = lc::PixelFormat(mode_.fourcc);
        sc.size = lc::Size(unsigned(mode_.size.width), unsigned(mode_.size.height));
        sc.bufferCount = std::max(sc.bufferCount, kMinBuffers);
        const auto status = config_->validate();
        if (status == lc::CameraConfiguration::Invalid ||
            sc.pixelFormat != lc::PixelFormat(mode_.fourcc) ||
            sc.size != lc::Size(unsigned(mode_.size.width), unsigned(mode_.size.height)))
            return makeError(ErrorKind::Unsupported,
                             "libcamera camera '" + camera_->id() + "' does not accept " +
                                 pixelFormatName(mode_.format) + " " +
                                 std::to_string(mode_.size.width) + "x" +
                                 std::to_string(mode_.size.height) + " (it proposes " +
                                 sc.toString() + "); pick a mode 'infocus devices' lists");
        if (int r = camera_->configure(config_.get()); r < 0)
            return makeError(
                ErrorKind::Device,
                "libcamera camera '" + camera_->id() + "': configure failed: " + std::strerror(-r),
                -r);
        stream_ = sc.stream();
        stride_ = sc.stride;
        transfer_ = transferOf(sc.colorSpace);
        allocator_ = std::make_unique<lc::FrameBufferAllocator>(camera_);
        if (int r = allocator_->allocate(stream_); r < 0)
            return makeError(ErrorKind::Device,
                             "libcamera camera '" + camera_->id() +
                                 "': cannot allocate buffers: " + std::strerror(-r),
                             -r);
        for (const auto& buffer : allocator_->buffers(stream_)) {
            if (Status s = mapBuffer(*buffer); !s) return s;
            auto req = camera_->createRequest();
            if (!req || req->addBuffer(stream_, buffer.get()) < 0)
                return makeError(ErrorKind::Device, "libcamera camera '" + camera_->id() +
                                                        "': cannot create a request");
            requests_.push_back(std::move(req));
        }
        const auto& ctrls = camera_->controls();
        if (auto it = ctrls.find(&lc::controls::LensPosition); it != ctrls.end())
            focus_ = std::make_unique<LibcameraFocus>(
                it->second, ctrls.find(&lc::controls::AfMode) != ctrls.end(), settle);
        else if (auto lens = v4l2::findLensOfCamera(camera_->id()))
            // The pipeline does not drive the sensor's lens (vimc): its sub-device directly.
            if (auto f = v4l2::openLensFocus(*lens, settle)) lensFocus_ = std::move(*f);
        camera_->requestCompleted.connect(this, &LibcameraSource::onComplete);
        return {};
    }

    SourceInfo info() const override {
        SourceInfo i;
        i.sourceString = "libcamera:" + camera_->id();
        i.device = camera_->id();
        i.driver = "libcamera";
        i.format = mode_.format;
        i.size = mode_.size;
        i.fps = requestedFps_.value_or(mode_.fps);
        i.liveCamera = true;
        i.transfer = transfer_;
        return i;
    }

    Status start() override {
        if (started_) return {};
        lc::ControlList controls(camera_->controls());
        if (requestedFps_) {
            const int64_t us = static_cast<int64_t>(1e6 / *requestedFps_ + 0.5);
            const int64_t limits[2] = {us, us};
            controls.set(lc::controls::FrameDurationLimits, lc::Span<const int64_t, 2>(limits));
        }
        if (int r = camera_->start(&controls); r < 0)
            return makeError(
                ErrorKind::Device,
                "libcamera camera '" + camera_->id() + "': start failed: " + std::strerror(-r), -r);
        started_ = true;
        for (auto& req : requests_)
            if (Status s = queue(req.get()); !s) return s;
        return {};
    }

    Result<Frame> next() override {
        if (!started_)
            return makeError(ErrorKind::Usage, "libcamera source: next() before start()");
        requeueReturned();
        while (true) {
            lc::Request* req = nullptr;
            {
                std::unique_lock lock(mutex_);
                if (!cv_.wait_for(lock, kFrameTimeout, [&] { return !completed_.empty(); }))
                    return makeError(
                        ErrorKind::Device,
                        "libcamera camera '" + camera_->id() +
                            "': no frame for 5 s; the camera stalled or was unplugged");
                req = completed_.front();
                completed_.pop_front();
            }
            --inFlight_;
            if (req->status() == lc::Request::RequestCancelled)
                return makeError(ErrorKind::Device,
                                 "libcamera camera '" + camera_->id() +
                                     "': the request was cancelled (camera stopped "
                                     "or disconnected)");
            lc::FrameBuffer* buffer = req->buffers().begin()->second;
            const lc::FrameMetadata& md = buffer->metadata();
            stats_.dropped += seq_.update(md.sequence);
            if (md.status != lc::FrameMetadata::FrameSuccess) {
                ++stats_.errors;
                if (Status s = queue(req); !s) return s.error();
                continue;
            }
            auto frame = makeFrame(req, buffer);
            if (!frame) {
                ++stats_.errors;
                if (Status s = queue(req); !s) return s.error();
                continue;
            }
            ++stats_.delivered;
            return frame;
        }
    }

    void stop() override {
        if (!started_) return;
        camera_->stop();  // completes every pending request as cancelled
        started_ = false;
        std::lock_guard lock(mutex_);
        completed_.clear();
    }

    SourceStats stats() const override { return stats_; }
    FocusControl* focusControl() override {
        return focus_ ? static_cast<FocusControl*>(focus_.get()) : lensFocus_.get();
    }

private:
    Status mapBuffer(const lc::FrameBuffer& buffer) {
        // Planes often share one dmabuf at different offsets: map each fd once, whole.
        std::map<int, size_t> extent;
        for (const auto& p : buffer.planes())
            extent[p.fd.get()] = std::max(extent[p.fd.get()], size_t(p.offset) + p.length);
        std::map<int, const uint8_t*> base;
        for (auto [fd, length] : extent) {
            void* addr = ::mmap(nullptr, length, PROT_READ, MAP_SHARED, fd, 0);
            if (addr == MAP_FAILED)
                return makeError(ErrorKind::Device,
                                 "libcamera camera '" + camera_->id() +
                                     "': cannot map a buffer: " + std::strerror(errno),
                                 errno);
            pool_->maps.push_back({addr, length});
            base[fd] = static_cast<const uint8_t*>(addr);
        }
        auto& planes = pool_->planes[&buffer];
        for (const auto& p : buffer.planes())
            planes.push_back(base[p.fd.get()] + p.offset);
        return {};
    }

    void onComplete(lc::Request* request) {
        // Runs on libcamera's thread: hand over and return at once.
        {
            std::lock_guard lock(mutex_);
            completed_.push_back(request);
        }
        cv_.notify_one();
    }

    Status queue(lc::Request* req) {
        req->reuse(lc::Request::ReuseBuffers);
        if (focus_) focus_->apply(req->controls());
        if (int r = camera_->queueRequest(req); r < 0)
            return makeError(ErrorKind::Device,
                             "libcamera camera '" + camera_->id() +
                                 "': cannot queue a request: " + std::strerror(-r),
                             -r);
        ++inFlight_;
        return {};
    }

    void requeueReturned() {
        std::vector<lc::Request*> back;
        {
            std::lock_guard lock(pool_->mutex);
            back.swap(pool_->returned);
        }
        for (auto* r : back)
            (void)queue(r);  // a failure shows as a timeout in next()
    }

    Result<Frame> makeFrame(lc::Request* req, lc::FrameBuffer* buffer) {
        const lc::FrameMetadata& md = buffer->metadata();
        const auto& planes = pool_->planes[buffer];
        Frame f;
        f.format = mode_.format;
        f.size = mode_.size;
        f.sequence = md.sequence;
        f.timestampNs = static_cast<int64_t>(md.timestamp);
        const lc::ControlList& meta = req->metadata();
        if (auto ts = meta.get(lc::controls::SensorTimestamp)) f.timestampNs = *ts;
        if (auto lens = meta.get(lc::controls::LensPosition)) {
            f.lens = LensPosition{double(*lens), "dioptre", double(*lens)};
            if (focus_) focus_->observed(*lens);
        } else if (FocusControl* focus = focusControl()) {
            if (auto p = focus->get()) f.lens = *p;
        }
        if (auto exposure = meta.get(lc::controls::ExposureTime)) f.exposureS = *exposure * 1e-6;
        if (mode_.format == PixelFormat::MJPEG) {
            f.planes[0] = {planes[0], 0, md.planes()[0].bytesused};
            f.numPlanes = 1;
        } else {
            auto layout = frameLayout(mode_.format, mode_.size, stride_);
            if (!layout) return layout.error();
            if (planes.size() == layout->numPlanes) {
                for (unsigned p = 0; p < layout->numPlanes; ++p)
                    f.planes[p] = {planes[p], layout->stride[p], layout->size[p]};
            } else {
                size_t offset = 0;
                for (unsigned p = 0; p < layout->numPlanes; ++p) {
                    f.planes[p] = {planes[0] + offset, layout->stride[p], layout->size[p]};
                    offset += layout->size[p];
                }
            }
            f.numPlanes = layout->numPlanes;
        }
        if (inFlight_ == 0) {
            // The camera would starve: hand out a copy and requeue at once.
            auto copy = copyFrame(f);
            // The request goes back to the camera whether or not the copy worked.
            if (Status s = queue(req); !s) return s.error();
            if (!copy) return copy.error();
            return *copy;
        }
        auto pool = pool_;
        f.storage = std::shared_ptr<const void>(planes[0], [pool, req](const void*) {
            std::lock_guard lock(pool->mutex);
            pool->returned.push_back(req);
        });
        return f;
    }

    std::shared_ptr<lc::CameraManager> manager_;
    std::shared_ptr<lc::Camera> camera_;
    std::unique_ptr<lc::CameraConfiguration> config_;
    std::unique_ptr<lc::FrameBufferAllocator> allocator_;
    std::vector<std::unique_ptr<lc::Request>> requests_;
    std::shared_ptr<BufferPool> pool_;
    std::unique_ptr<LibcameraFocus> focus_;
    std::unique_ptr<FocusControl> lensFocus_;  // the sensor's lens sub-device, without focus_
    lc::Stream* stream_ = nullptr;
    size_t stride_ = 0;
    TransferReport transfer_;  // the stream's, from its colour space
    capture::Mode mode_;
    std::optional<double> requestedFps_;
    bool acquired_ = false;
    bool started_ = false;
    int inFlight_ = 0;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<lc::Request*> completed_;
    capture::SequenceTracker seq_;
    SourceStats stats_;
};

Result<int> parseSettle(const SourceSpec& spec) {
    auto it = spec.options.find("settle");
    if (it == spec.options.end()) return kDefaultSettleFrames;
    int v = 0;
    const auto& t = it->second;
    auto [p, e] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (e != std::errc() || p != t.data() + t.size() || v < 0)
        return makeError(ErrorKind::Usage, "source '" + spec.text + "': settle=" + t +
                                               ": give a whole number of frames ≥ 0");
    return v;
}

}  // namespace

Result<std::unique_ptr<FrameSource>> openLibcameraSource(const SourceSpec& spec) {
    for (const auto& [key, value] : spec.options)
        if (key != "format" && key != "size" && key != "fps" && key != "settle")
            return makeError(ErrorKind::Usage,
                             "source '" + spec.text + "': unknown option '" + key +
                                 "'; libcamera sources take format, size, fps, settle");
    auto settle = parseSettle(spec);
    if (!settle) return settle.error();
    std::string error;
    auto manager = cameraManager(error);
    if (!manager) return makeError(ErrorKind::Device, error);
    auto camera = findCamera(*manager, spec.target);
    if (!camera) return camera.error();
    auto source = std::make_unique<LibcameraSource>(manager, *camera);
    if (Status s = source->init(spec, *settle); !s) return s.error();
    return std::unique_ptr<FrameSource>(std::move(source));
}

Result<std::vector<DeviceInfo>> listLibcameraDevices() {
    std::string error;
    auto manager = cameraManager(error);
    if (!manager) return makeError(ErrorKind::Device, error);
    std::vector<DeviceInfo> out;
    int index = 0;
    for (const auto& camera : manager->cameras()) {
        DeviceInfo info;
        info.backend = "libcamera";
        info.sourceString = "libcamera:" + std::to_string(index++);
        info.device = camera->id();
        info.driver = "libcamera";
        const auto& props = camera->properties();
        info.card = props.get(lc::properties::Model).value_or(camera->id());
        if (auto loc = props.get(lc::properties::Location))
            info.bus = *loc == lc::properties::CameraLocationFront  ? "front"
                       : *loc == lc::properties::CameraLocationBack ? "back"
                                                                    : "external";
        if (auto config = viewfinderConfiguration(*camera); config && !config->empty()) {
            const auto& sc = config->at(0);
            info.currentFormat = sc.pixelFormat.toString() + " " + sc.size.toString();
            info.currentTransfer = transferOf(sc.colorSpace);
            for (const auto& f : offeredModes(*camera, sc)) {
                DeviceFormat df;
                df.fourcc = f.description;
                df.format = f.format;
                df.description = f.description;
                for (const auto& s : f.sizes)
                    df.sizes.push_back({s.size, s.fps});
                info.formats.push_back(std::move(df));
            }
        }
        const auto& ctrls = camera->controls();
        auto control = [&](const lc::ControlId* id, const char* name,
                           const char* unit) -> std::optional<DeviceControl> {
            auto it = ctrls.find(id);
            if (it == ctrls.end()) return std::nullopt;
            auto num = [](const lc::ControlValue& v) -> double {
                switch (v.type()) {
                    case lc::ControlTypeFloat:
                        return v.get<float>();
                    case lc::ControlTypeInteger32:
                        return v.get<int32_t>();
                    case lc::ControlTypeInteger64:
                        return double(v.get<int64_t>());
                    default:
                        return 0.0;
                }
            };
            const auto& ci = it->second;
            DeviceControl c;
            c.name = name;
            c.unit = unit;
            c.min = num(ci.min());
            c.max = num(ci.max());
            c.defaultValue = ci.def().isNone() ? num(ci.min()) : num(ci.def());
            return c;
        };
        info.focus = control(&lc::controls::LensPosition, "lens_position", "dioptre");
        if (!info.focus)
            if (auto lens = v4l2::findLensOfCamera(camera->id()))
                info.focus = v4l2::describeLens(*lens);
        info.autofocusContinuous = ctrls.find(&lc::controls::AfMode) != ctrls.end();
        info.autofocusTrigger = ctrls.find(&lc::controls::AfTrigger) != ctrls.end();
        if (auto c = control(&lc::controls::ExposureTime, "exposure_time", "us"))
            info.controls.push_back(*c);
        if (auto c = control(&lc::controls::AnalogueGain, "analogue_gain", "x"))
            info.controls.push_back(*c);
        // The ISP's sharpening (0: none) makes edges read narrower than their blur.
        if (auto c = control(&lc::controls::Sharpness, "sharpness", "x"))
            info.controls.push_back(*c);
        out.push_back(std::move(info));
    }
    return out;
}

}  // namespace infocus::libcam
