// SPDX-License-Identifier: MIT
/// @file v4l2_device.h
/// A V4L2 device node: the one ioctl wrapper, capabilities, format/size/interval enumeration and
/// controls by CID. Internal to the V4L2 backend (includes the kernel header).
#pragma once

#include <linux/videodev2.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "drivers/common/mode_choice.h"
#include "infocus/devices.h"
#include "infocus/error.h"

namespace infocus::v4l2 {

/// ioctl(2) retried on EINTR. Returns 0 or -errno; the caller, which has the context, reports.
int xioctl(int fd, unsigned long request, void* arg);

/// What VIDIOC_QUERYCAP says about a node (device_caps when the driver sets them).
struct Capability {
    std::string driver, card, bus;
    uint32_t caps = 0;  ///< device_caps of this node
    bool capture() const;
    /// True for a media-controller node (V4L2_CAP_IO_MC): it streams only once its pipeline is
    /// configured, which libcamera does.
    bool mediaController() const { return caps & V4L2_CAP_IO_MC; }
    bool multiplanar() const {
        return (caps & V4L2_CAP_VIDEO_CAPTURE_MPLANE) && !(caps & V4L2_CAP_VIDEO_CAPTURE);
    }
    uint32_t bufType() const {
        return multiplanar() ? V4L2_BUF_TYPE_VIDEO_CAPTURE_MPLANE : V4L2_BUF_TYPE_VIDEO_CAPTURE;
    }
};

/// Maps a V4L2 fourcc to the format infocus reads; multi-planar variants (NM12, NM21, YM12) map
/// to their contiguous twins. Invalid when infocus cannot read it.
PixelFormat pixelFormatFromV4l2(uint32_t fourcc);

/// The transfer function of a format of @p colorspace and @p xferFunc (v4l2_pix_format's fields).
/// V4L2_XFER_FUNC_DEFAULT stands for the colour space's own curve, as V4L2_MAP_XFER_FUNC_DEFAULT
/// maps it; opRGB, SMPTE 240M, DCI-P3 and SMPTE 2084 are named but not decoded.
TransferReport transferFromV4l2(uint32_t colorspace, uint32_t xferFunc);

/// An open device node; closes it on destruction.
class Device {
public:
    Device() = default;
    ~Device();
    Device(Device&& other) noexcept;
    Device& operator=(Device&& other) noexcept;
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    /// Opens @p path read-write and non-blocking and queries its capabilities.
    static Result<Device> open(const std::string& path);

    int fd() const { return fd_; }
    const std::string& path() const { return path_; }
    const Capability& capability() const { return cap_; }
    /// xioctl on this node.
    int ioctl(unsigned long request, void* arg) const { return xioctl(fd_, request, arg); }

    /// Every format, size and frame rate of the capture queue (stepwise sizes are sampled at
    /// their maximum and at common sizes inside the range).
    std::vector<capture::FormatOption> enumerateFormats() const;
    /// True when the driver accepts @p fourcc at exactly @p size (VIDIOC_TRY_FMT, no change made).
    bool trySize(uint32_t fourcc, Size size) const;
    /// The current capture mode (format, size, rate), when the driver reports it.
    std::optional<capture::Mode> currentMode() const;
    /// The current format's transfer function (transferFromV4l2), when the driver reports it.
    std::optional<TransferReport> currentTransfer() const;

    /// The description of control @p cid, or nullopt when the node lacks it or it is disabled.
    std::optional<v4l2_queryctrl> queryControl(uint32_t cid) const;
    /// Reads control @p cid; -errno on failure.
    Result<int32_t> getControl(uint32_t cid) const;
    /// Writes control @p cid; returns 0 or -errno.
    int setControl(uint32_t cid, int32_t value) const;

private:
    int fd_ = -1;
    std::string path_;
    Capability cap_;
};

/// The capture nodes under /dev, found by capability (not by index), sorted by path.
std::vector<std::string> findCaptureNodes();

/// Describes the capture node @p path for `infocus devices`.
Result<DeviceInfo> describeDevice(const std::string& path);

/// Text of errno @p err (positive or negative).
std::string errnoText(int err);

}  // namespace infocus::v4l2
