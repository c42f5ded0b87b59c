// SPDX-License-Identifier: MIT
// The JSON face: the state as one JSON object a second (the web page's /state, docs/live.md).
#include "infocus/live.h"
#include "src/live/printed_face.h"

namespace infocus {

std::unique_ptr<Face> makeJsonFace() {
    return makePrintedFace([](const LiveState& s) { return liveStateJson(s); });
}

}  // namespace infocus
