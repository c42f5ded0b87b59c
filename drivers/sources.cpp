// SPDX-License-Identifier: MIT
// The one place that knows which backends were built: every HAVE_* test for a backend is here.
#include "infocus/devices.h"
#include "infocus/source.h"
#include "infocus_config.h"
#if HAVE_V4L2
#include "drivers/v4l2/v4l2_source.h"
#endif
#if HAVE_LIBCAMERA
#include "drivers/libcamera/libcamera_source.h"
#endif
#include "replay/replay_sources.h"

namespace infocus {

Result<std::unique_ptr<FrameSource>> openSource(std::string_view text) {
    auto spec = parseSourceSpec(text);
    if (!spec) return spec.error();
    return openSource(*spec);
}

Result<std::unique_ptr<FrameSource>> openSource(const SourceSpec& spec) {
    if (spec.kind == "v4l2") {
#if HAVE_V4L2
        return v4l2::openV4l2Source(spec);
#else
        return makeError(ErrorKind::Unsupported,
                         "source '" + spec.text +
                             "': this infocus was built without V4L2; rebuild with -Dv4l2=enabled");
#endif
    }
    if (spec.kind == "libcamera") {
#if HAVE_LIBCAMERA
        return libcam::openLibcameraSource(spec);
#else
        return makeError(ErrorKind::Unsupported, "source '" + spec.text +
                                                     "': this infocus was built without libcamera; "
                                                     "rebuild with -Dlibcamera=enabled");
#endif
    }
    if (spec.kind == "path") return replay::openPathSource(spec);
    if (spec.kind == "sim") return replay::openSimSource(spec);
    return makeError(ErrorKind::Usage,
                     "source '" + spec.text + "': unknown source kind '" + spec.kind + "'");
}

std::vector<DeviceInfo> listDevices(std::vector<UnlistedBackend>& unlisted) {
    std::vector<DeviceInfo> all;
#if HAVE_V4L2
    for (auto& d : v4l2::listV4l2Devices())
        all.push_back(std::move(d));
#endif
#if HAVE_LIBCAMERA
    auto cams = libcam::listLibcameraDevices();
    if (cams) {
        for (auto& d : *cams)
            all.push_back(std::move(d));
    } else {
        unlisted.push_back({"libcamera", cams.error().message});
    }
#endif
    (void)unlisted;
    return all;
}

Result<std::vector<DeviceInfo>> listDevices() {
    std::vector<UnlistedBackend> unlisted;
    auto all = listDevices(unlisted);
    if (!unlisted.empty())
        return makeError(ErrorKind::Device,
                         unlisted.front().backend + " cameras: " + unlisted.front().why);
    return all;
}

std::string cameraKindsText() {
    return "cameras (V4L2 nodes, libcamera cameras)";
}

std::string noCameraMessage() {
    std::string where;
#if HAVE_V4L2
    where = "no V4L2 capture node under /dev";
#endif
#if HAVE_LIBCAMERA
    where += std::string(where.empty() ? "no" : " and no") + " libcamera camera";
#endif
    if (where.empty()) where = "this infocus was built without camera backends";
    return "No camera found: " + where +
           ".\nConnect a camera (and check you are in the 'video' group), or use a recording or "
           "sim: as the source.";
}

std::string mediaControllerNote() {
    return "media-controller node: streams through libcamera, not directly";
}

std::string sourceStringExamples() {
    return "v4l2:/dev/video0, libcamera:0, sim:..., or a path";
}

}  // namespace infocus
