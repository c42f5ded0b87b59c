// SPDX-License-Identifier: MIT
// The terminal face in a build without ncursesw: the same entry points, saying why there is none.
#include "infocus/tui.h"

namespace infocus {

bool tuiAvailable() {
    return false;
}

Status runTui(LivePipeline&, const TuiOptions&) {
    return makeError(ErrorKind::Unsupported,
                     "this infocus was built without the terminal view (ncursesw was not found); "
                     "use --ui text or --ui json, or install libncurses-dev and rebuild");
}

}  // namespace infocus
