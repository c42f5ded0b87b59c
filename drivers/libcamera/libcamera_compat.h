// SPDX-License-Identifier: MIT
/// @file libcamera_compat.h
/// The one place that knows libcamera versions. Written against Debian bookworm's 0.0.3; the API
/// changes of later releases that this backend touches are bridged here and nowhere else.
#pragma once

#include <libcamera/camera.h>
#include <libcamera/stream.h>
#include <libcamera/version.h>

#include <memory>

namespace infocus::libcam {

/// libcamera's version as MAJOR*10000 + MINOR*100 + PATCH (0.0.3 → 3).
inline constexpr int kLibcameraVersion =
    LIBCAMERA_VERSION_MAJOR * 10000 + LIBCAMERA_VERSION_MINOR * 100 + LIBCAMERA_VERSION_PATCH;

/// A configuration for one viewfinder stream. 0.0.x takes a StreamRoles vector; from 0.1 on
/// generateConfiguration() takes a Span of roles and the StreamRoles alias is gone.
inline std::unique_ptr<libcamera::CameraConfiguration> viewfinderConfiguration(
    libcamera::Camera& camera) {
#if LIBCAMERA_VERSION_MAJOR == 0 && LIBCAMERA_VERSION_MINOR == 0
    return camera.generateConfiguration(libcamera::StreamRoles{libcamera::StreamRole::Viewfinder});
#else
    const libcamera::StreamRole roles[] = {libcamera::StreamRole::Viewfinder};
    return camera.generateConfiguration(roles);
#endif
}

}  // namespace infocus::libcam
