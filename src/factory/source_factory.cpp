// SPDX-License-Identifier: MIT
// The one place that knows which backends were built: every HAVE_* test for a backend is here.
#include "infocus/source.h"
#include "infocus_config.h"
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
        return makeError(ErrorKind::Unsupported,
                         "source '" + spec.text + "': V4L2 capture is not available yet");
#else
        return makeError(ErrorKind::Unsupported,
                         "source '" + spec.text +
                             "': this infocus was built without V4L2; rebuild with -Dv4l2=enabled");
#endif
    }
    if (spec.kind == "libcamera") {
#if HAVE_LIBCAMERA
        return makeError(ErrorKind::Unsupported,
                         "source '" + spec.text + "': libcamera capture is not available yet");
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

}  // namespace infocus
