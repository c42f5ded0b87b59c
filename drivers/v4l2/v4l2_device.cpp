// SPDX-License-Identifier: MIT
#include "drivers/v4l2/v4l2_device.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <utility>

#include "drivers/v4l2/media_lens.h"

namespace infocus::v4l2 {

namespace {

std::string fixedString(const uint8_t* s, size_t n) {
    return std::string(reinterpret_cast<const char*>(s),
                       strnlen(reinterpret_cast<const char*>(s), n));
}

std::string fourccText(uint32_t f) {
    std::string s;
    // Bit 31 marks the big-endian variant of a format (v4l2_fourcc_be), not a character.
    constexpr uint32_t kBigEndian = 1u << 31;
    const uint32_t code = f & ~kBigEndian;
    for (int i = 0; i < 4; ++i)
        s += static_cast<char>((code >> (8 * i)) & 0xff);
    while (!s.empty() && s.back() == ' ')
        s.pop_back();
    if (f & kBigEndian) s += "-BE";
    return s;
}

// Frame rates of one size, highest first (VIDIOC_ENUM_FRAMEINTERVALS; interval = num/den s).
std::vector<double> enumerateRates(int fd, uint32_t fourcc, Size size) {
    std::vector<double> fps;
    v4l2_frmivalenum iv{};
    iv.pixel_format = fourcc;
    iv.width = static_cast<uint32_t>(size.width);
    iv.height = static_cast<uint32_t>(size.height);
    for (iv.index = 0; xioctl(fd, VIDIOC_ENUM_FRAMEINTERVALS, &iv) == 0; ++iv.index) {
        if (iv.type == V4L2_FRMIVAL_TYPE_DISCRETE) {
            if (iv.discrete.numerator)
                fps.push_back(double(iv.discrete.denominator) / iv.discrete.numerator);
        } else {
            // Stepwise/continuous: the ends of the range are what a user chooses between.
            if (iv.stepwise.min.numerator)
                fps.push_back(double(iv.stepwise.min.denominator) / iv.stepwise.min.numerator);
            if (iv.stepwise.max.numerator)
                fps.push_back(double(iv.stepwise.max.denominator) / iv.stepwise.max.numerator);
            break;
        }
    }
    std::sort(fps.rbegin(), fps.rend());
    fps.erase(std::unique(fps.begin(), fps.end()), fps.end());
    return fps;
}

}  // namespace

int xioctl(int fd, unsigned long request, void* arg) {
    int r;
    do {
        r = ::ioctl(fd, request, arg);
    } while (r < 0 && errno == EINTR);
    return r < 0 ? -errno : 0;
}

std::string errnoText(int err) {
    return std::strerror(err < 0 ? -err : err);
}

bool Capability::capture() const {
    return (caps & (V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_VIDEO_CAPTURE_MPLANE)) &&
           (caps & V4L2_CAP_STREAMING);
}

PixelFormat pixelFormatFromV4l2(uint32_t fourcc) {
    switch (fourcc) {
        case V4L2_PIX_FMT_NV12M:
            return PixelFormat::NV12;
        case V4L2_PIX_FMT_NV21M:
            return PixelFormat::NV21;
        case V4L2_PIX_FMT_YUV420M:
            return PixelFormat::YU12;
        default:
            break;
    }
    const auto f = static_cast<PixelFormat>(fourcc);
    return isSupported(f) ? f : PixelFormat::Invalid;
}

TransferReport transferFromV4l2(uint32_t colorspace, uint32_t xferFunc) {
    const bool byDefault = xferFunc == V4L2_XFER_FUNC_DEFAULT;
    // A driver that leaves both at 0 says nothing; the kernel's map would read that as BT.709.
    if (byDefault && colorspace == V4L2_COLORSPACE_DEFAULT)
        return {std::nullopt, "the V4L2 driver reports no colour space for the format"};
    const uint32_t xfer =
        byDefault ? static_cast<uint32_t>(V4L2_MAP_XFER_FUNC_DEFAULT(colorspace)) : xferFunc;
    const std::string how =
        byDefault ? "the V4L2 format's colour space" : "the V4L2 format's transfer function";
    switch (xfer) {
        case V4L2_XFER_FUNC_SRGB:
            return {TransferFunction::Srgb, how};
        case V4L2_XFER_FUNC_709:
            return {TransferFunction::Rec709, how};
        case V4L2_XFER_FUNC_NONE:
            return {TransferFunction::Linear, how};
        case V4L2_XFER_FUNC_OPRGB:
            return {std::nullopt, how + " is opRGB, which infocus does not decode"};
        case V4L2_XFER_FUNC_SMPTE240M:
            return {std::nullopt, how + " is SMPTE 240M, which infocus does not decode"};
        case V4L2_XFER_FUNC_DCI_P3:
            return {std::nullopt, how + " is DCI-P3, which infocus does not decode"};
        case V4L2_XFER_FUNC_SMPTE2084:
            return {std::nullopt, how + " is SMPTE 2084 (HDR), which infocus does not decode"};
        default:
            break;
    }
    return {std::nullopt, how + " is " + std::to_string(xfer) + ", unknown to infocus"};
}

Device::~Device() {
    if (fd_ >= 0) ::close(fd_);
}

Device::Device(Device&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), path_(std::move(other.path_)), cap_(other.cap_) {}

Device& Device::operator=(Device&& other) noexcept {
    if (this != &other) {
        if (fd_ >= 0) ::close(fd_);
        fd_ = std::exchange(other.fd_, -1);
        path_ = std::move(other.path_);
        cap_ = other.cap_;
    }
    return *this;
}

Result<Device> Device::open(const std::string& path) {
    Device d;
    d.path_ = path;
    d.fd_ = ::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (d.fd_ < 0) {
        const int e = errno;
        if (e == ENOENT)
            return makeError(ErrorKind::NotFound,
                             path + ": no such device; run 'infocus devices' to list cameras", e);
        return makeError(e == EACCES ? ErrorKind::Io : ErrorKind::Device,
                         path + ": cannot open: " + errnoText(e) +
                             (e == EACCES ? "; add yourself to the 'video' group" : ""),
                         e);
    }
    v4l2_capability cap{};
    if (int r = d.ioctl(VIDIOC_QUERYCAP, &cap); r < 0)
        return makeError(ErrorKind::Device,
                         path + ": not a V4L2 device (VIDIOC_QUERYCAP: " + errnoText(r) + ")", -r);
    d.cap_.driver = fixedString(cap.driver, sizeof cap.driver);
    d.cap_.card = fixedString(cap.card, sizeof cap.card);
    d.cap_.bus = fixedString(cap.bus_info, sizeof cap.bus_info);
    d.cap_.caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
    return d;
}

std::vector<capture::FormatOption> Device::enumerateFormats() const {
    std::vector<capture::FormatOption> out;
    v4l2_fmtdesc fd{};
    fd.type = cap_.bufType();
    for (fd.index = 0; ioctl(VIDIOC_ENUM_FMT, &fd) == 0; ++fd.index) {
        capture::FormatOption f;
        f.fourcc = fd.pixelformat;
        f.format = pixelFormatFromV4l2(fd.pixelformat);
        f.description = fixedString(fd.description, sizeof fd.description);
        v4l2_frmsizeenum fs{};
        fs.pixel_format = fd.pixelformat;
        for (fs.index = 0; ioctl(VIDIOC_ENUM_FRAMESIZES, &fs) == 0; ++fs.index) {
            if (fs.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
                Size s{int(fs.discrete.width), int(fs.discrete.height)};
                f.sizes.push_back({s, enumerateRates(fd_, fd.pixelformat, s)});
                continue;
            }
            // Stepwise or continuous: offer the largest size and common sizes inside the range.
            const auto& sw = fs.stepwise;
            const Size candidates[] = {
                {int(sw.max_width), int(sw.max_height)}, {1920, 1080}, {1280, 720}, {640, 480}};
            for (const Size& s : candidates) {
                const bool inside =
                    s.width >= int(sw.min_width) && s.width <= int(sw.max_width) &&
                    s.height >= int(sw.min_height) && s.height <= int(sw.max_height) &&
                    (s.width - int(sw.min_width)) % int(std::max(1u, sw.step_width)) == 0 &&
                    (s.height - int(sw.min_height)) % int(std::max(1u, sw.step_height)) == 0;
                const bool seen =
                    std::any_of(f.sizes.begin(), f.sizes.end(),
                                [&](const capture::SizeOption& o) { return o.size == s; });
                if (inside && !seen) f.sizes.push_back({s, enumerateRates(fd_, fd.pixelformat, s)});
            }
            break;
        }
        out.push_back(std::move(f));
    }
    return out;
}

bool Device::trySize(uint32_t fourcc, Size size) const {
    v4l2_format fmt{};
    fmt.type = cap_.bufType();
    if (cap_.multiplanar()) {
        fmt.fmt.pix_mp.pixelformat = fourcc;
        fmt.fmt.pix_mp.width = uint32_t(size.width);
        fmt.fmt.pix_mp.height = uint32_t(size.height);
    } else {
        fmt.fmt.pix.pixelformat = fourcc;
        fmt.fmt.pix.width = uint32_t(size.width);
        fmt.fmt.pix.height = uint32_t(size.height);
    }
    if (ioctl(VIDIOC_TRY_FMT, &fmt) < 0) return false;
    return cap_.multiplanar() ? fmt.fmt.pix_mp.width == uint32_t(size.width) &&
                                    fmt.fmt.pix_mp.height == uint32_t(size.height)
                              : fmt.fmt.pix.width == uint32_t(size.width) &&
                                    fmt.fmt.pix.height == uint32_t(size.height);
}

std::optional<capture::Mode> Device::currentMode() const {
    v4l2_format fmt{};
    fmt.type = cap_.bufType();
    if (ioctl(VIDIOC_G_FMT, &fmt) < 0) return std::nullopt;
    capture::Mode m;
    if (cap_.multiplanar()) {
        m.fourcc = fmt.fmt.pix_mp.pixelformat;
        m.size = {int(fmt.fmt.pix_mp.width), int(fmt.fmt.pix_mp.height)};
    } else {
        m.fourcc = fmt.fmt.pix.pixelformat;
        m.size = {int(fmt.fmt.pix.width), int(fmt.fmt.pix.height)};
    }
    m.format = pixelFormatFromV4l2(m.fourcc);
    v4l2_streamparm parm{};
    parm.type = cap_.bufType();
    if (ioctl(VIDIOC_G_PARM, &parm) == 0 && parm.parm.capture.timeperframe.numerator)
        m.fps = double(parm.parm.capture.timeperframe.denominator) /
                parm.parm.capture.timeperframe.numerator;
    return m;
}

std::optional<TransferReport> Device::currentTransfer() const {
    v4l2_format fmt{};
    fmt.type = cap_.bufType();
    if (ioctl(VIDIOC_G_FMT, &fmt) < 0) return std::nullopt;
    return cap_.multiplanar()
               ? transferFromV4l2(fmt.fmt.pix_mp.colorspace, fmt.fmt.pix_mp.xfer_func)
               : transferFromV4l2(fmt.fmt.pix.colorspace, fmt.fmt.pix.xfer_func);
}

std::optional<v4l2_queryctrl> Device::queryControl(uint32_t cid) const {
    v4l2_queryctrl q{};
    q.id = cid;
    if (ioctl(VIDIOC_QUERYCTRL, &q) < 0 || (q.flags & V4L2_CTRL_FLAG_DISABLED)) return std::nullopt;
    return q;
}

Result<int32_t> Device::getControl(uint32_t cid) const {
    v4l2_control c{};
    c.id = cid;
    if (int r = ioctl(VIDIOC_G_CTRL, &c); r < 0)
        return makeError(
            ErrorKind::Device,
            path_ + ": cannot read control 0x" +
                [&] {
                    char b[16];
                    std::snprintf(b, sizeof b, "%08x", cid);
                    return std::string(b);
                }() +
                ": " + errnoText(r),
            -r);
    return c.value;
}

int Device::setControl(uint32_t cid, int32_t value) const {
    v4l2_control c{};
    c.id = cid;
    c.value = value;
    return ioctl(VIDIOC_S_CTRL, &c);
}

std::vector<std::string> findCaptureNodes() {
    std::vector<std::string> nodes;
    DIR* dir = ::opendir("/dev");
    if (!dir) return nodes;
    while (const dirent* e = ::readdir(dir)) {
        if (std::strncmp(e->d_name, "video", 5) != 0) continue;
        const std::string path = std::string("/dev/") + e->d_name;
        auto d = Device::open(path);
        if (d && d->capability().capture()) nodes.push_back(path);
    }
    ::closedir(dir);
    // /dev/video10 after /dev/video9: order by the number, not the text.
    std::sort(nodes.begin(), nodes.end(), [](const std::string& a, const std::string& b) {
        return a.size() != b.size() ? a.size() < b.size() : a < b;
    });
    return nodes;
}

Result<DeviceInfo> describeDevice(const std::string& path) {
    auto dev = Device::open(path);
    if (!dev) return dev.error();
    const Capability& cap = dev->capability();
    DeviceInfo info;
    info.backend = "v4l2";
    info.sourceString = "v4l2:" + path;
    info.device = path;
    info.driver = cap.driver;
    info.card = cap.card;
    info.bus = cap.bus;
    info.mediaController = cap.mediaController();
    if (auto m = dev->currentMode())
        info.currentFormat = fourccText(m->fourcc) + " " + std::to_string(m->size.width) + "x" +
                             std::to_string(m->size.height);
    info.currentTransfer = dev->currentTransfer();
    for (auto& f : dev->enumerateFormats()) {
        DeviceFormat df;
        df.fourcc = fourccText(f.fourcc);
        df.format = f.format;
        df.description = f.description;
        for (auto& s : f.sizes)
            df.sizes.push_back({s.size, s.fps});
        info.formats.push_back(std::move(df));
    }
    auto control = [&](uint32_t cid, const char* name,
                       const char* unit) -> std::optional<DeviceControl> {
        auto q = dev->queryControl(cid);
        if (!q) return std::nullopt;
        DeviceControl c;
        c.name = name;
        c.unit = unit;
        c.min = q->minimum;
        c.max = q->maximum;
        c.step = q->step;
        c.defaultValue = q->default_value;
        if (auto v = dev->getControl(cid)) c.current = *v;
        return c;
    };
    info.focus = control(V4L2_CID_FOCUS_ABSOLUTE, "focus_absolute", "v4l2");
    if (!info.focus)
        if (auto lens = findLensOfVideoNode(path)) info.focus = describeLens(*lens);
    info.focusRelative = dev->queryControl(V4L2_CID_FOCUS_RELATIVE).has_value();
    info.autofocusContinuous = dev->queryControl(V4L2_CID_FOCUS_AUTO).has_value();
    info.autofocusTrigger = dev->queryControl(V4L2_CID_AUTO_FOCUS_START).has_value();
    const std::tuple<uint32_t, const char*, const char*> others[] = {
        {V4L2_CID_EXPOSURE_ABSOLUTE, "exposure_time_absolute", "100us"},
        {V4L2_CID_EXPOSURE, "exposure", "v4l2"},
        {V4L2_CID_GAIN, "gain", "v4l2"},
        {V4L2_CID_ANALOGUE_GAIN, "analogue_gain", "v4l2"},
        // In-camera sharpening makes edges read narrower than their blur (docs/blur.md).
        {V4L2_CID_SHARPNESS, "sharpness", "v4l2"},
    };
    for (auto& [cid, name, unit] : others)
        if (auto c = control(cid, name, unit)) info.controls.push_back(*c);
    return info;
}

}  // namespace infocus::v4l2
