// SPDX-License-Identifier: MIT
/// @file devices.h
/// The cameras on this machine, as `infocus devices` lists them: V4L2 capture nodes and libcamera
/// cameras, their modes and what they offer for focusing. Backend-neutral types only.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "infocus/error.h"
#include "infocus/frame.h"
#include "infocus/source.h"

namespace infocus {

/// A frame size a camera offers for a format and the frame rates there (fps, highest first;
/// empty when the device does not say).
struct DeviceSize {
    Size size;
    std::vector<double> fps;
};

/// A pixel format a camera offers. @ref fourcc is the device's own code (e.g. "NM12"), @ref format
/// what infocus reads it as (Invalid when infocus cannot read it).
struct DeviceFormat {
    std::string fourcc;
    PixelFormat format = PixelFormat::Invalid;
    std::string description;
    std::vector<DeviceSize> sizes;
};

/// A numeric control that matters for focusing (focus, exposure, gain, sharpening), by its native
/// unit.
struct DeviceControl {
    std::string name;  ///< "focus_absolute", "lens_position", "exposure_time", ...
    std::string unit;  ///< "v4l2" (driver steps), "dioptre", "100us", "us", ...
    double min = 0.0;
    double max = 0.0;
    double step = 0.0;  ///< 0 when continuous
    double defaultValue = 0.0;
    std::optional<double> current;  ///< the value now, when readable
    /// The node the control is on when it is not the camera's own (a lens sub-device,
    /// `/dev/v4l-subdev2`); empty otherwise.
    std::string device;
    /// What that node is, for people: "Lens A of Sensor A" (media-controller entity names).
    std::string lens;
};

/// One camera: a V4L2 capture node or a libcamera camera.
struct DeviceInfo {
    std::string backend;  ///< "v4l2" or "libcamera"
    std::string
        sourceString;    ///< the source string that opens it (`v4l2:/dev/video0`, `libcamera:0`)
    std::string device;  ///< device node or libcamera camera id
    std::string driver;  ///< kernel driver or libcamera pipeline/model
    std::string card;    ///< card or model name
    std::string bus;     ///< bus info (V4L2) or location
    bool mediaController = false;  ///< V4L2 node of a media-controller pipeline (use libcamera)
    std::optional<std::string> currentFormat;       ///< "YUYV 640x480" when readable
    std::optional<TransferReport> currentTransfer;  ///< the current format's, when readable
    std::vector<DeviceFormat> formats;
    std::optional<DeviceControl> focus;  ///< absolute focus, when the camera can move its lens
    bool focusRelative = false;          ///< has V4L2_CID_FOCUS_RELATIVE (moves without position)
    bool autofocusContinuous = false;  ///< has continuous autofocus (FOCUS_AUTO, AfModeContinuous)
    bool autofocusTrigger = false;     ///< has one-shot autofocus start/stop/status
    std::vector<DeviceControl> controls;  ///< exposure, gain and sharpness controls, where present
};

/// A camera backend that could not be asked for its cameras, and why.
struct UnlistedBackend {
    std::string backend;  ///< "libcamera"
    std::string why;      ///< the backend's error: its module missing, libcamera not starting
};

/// Lists every camera of every backend this infocus was built with. A backend that cannot be
/// asked is named in @p unlisted and the others are still listed. An empty list is not an error.
std::vector<DeviceInfo> listDevices(std::vector<UnlistedBackend>& unlisted);

/// listDevices, with the first backend that could not be asked as the error.
Result<std::vector<DeviceInfo>> listDevices();

/// The kinds of camera this infocus can list, for help texts: "cameras (V4L2 nodes, libcamera
/// cameras)", naming only the backends it was built with.
std::string cameraKindsText();

/// What `devices` says when it finds no camera: where it looked and what to do.
std::string noCameraMessage();

/// Why a media-controller node (DeviceInfo::mediaController) is not streamed directly.
std::string mediaControllerNote();

/// Examples of source strings for help texts: "v4l2:/dev/video0, libcamera:0, sim:..., or a path".
std::string sourceStringExamples();

}  // namespace infocus
