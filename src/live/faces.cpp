// SPDX-License-Identifier: MIT
// The faces this build has: the one file that tests HAVE_TUI, HAVE_WEB and HAVE_WINDOW.
#include "src/live/faces.h"

#include <sstream>

#include "infocus_config.h"
#include "src/core/module_loader.h"
#include "src/live/face_module.h"
#include "src/live/printed_face.h"
#if HAVE_TUI
#include "src/live/tui/tui.h"
#endif

namespace infocus {

namespace {

std::string joined(const std::vector<std::string>& names) {
    std::string out;
    for (size_t i = 0; i < names.size(); ++i)
        out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    return out;
}

bool built(std::string_view name) {
    for (const std::string& b : builtFaces())
        if (b == name) return true;
    return false;
}

Error notBuilt(std::string_view name, std::string_view needs) {
    return makeError(ErrorKind::Usage, "this infocus was built without the " + std::string(name) +
                                           " face (" + std::string(needs) + "); use --ui " +
                                           joined(builtFaces()) + ", or rebuild with " +
                                           std::string(needs));
}

// A face from its module: the module missing (a partial install) is a usage error that names
// the faces there are.
Result<std::unique_ptr<Face>> loadFace(const std::string& name, const std::string& file,
                                       const std::string& entry, const std::string& subdir,
                                       const FaceSettings& settings) {
    auto table = loadModuleTable<FaceModule>(file, entry, kFaceModuleAbi,
                                             "the " + name + " face of infocus live", subdir);
    if (!table) {
        std::vector<std::string> others;
        for (const std::string& b : builtFaces())
            if (b != name) others.push_back(b);
        return makeError(ErrorKind::Usage,
                         table.error().message + "; meanwhile use --ui " + joined(others));
    }
    return std::unique_ptr<Face>((*table)->create(settings));
}

Result<std::unique_ptr<Face>> makeFace(const std::string& name, const FaceSettings& settings) {
    if (name == "text") return makeTextFace();
    if (name == "json") return makeJsonFace();
#if HAVE_TUI
    if (name == "tui") return makeTuiFace(settings);
#endif
#if HAVE_WEB
    if (name == "web")
        return loadFace(name, "infocus-web.so", "infocus_web_face", "src/live/web", settings);
#endif
#if HAVE_WINDOW
    if (name == "window")
        return loadFace(name, "infocus-window.so", "infocus_window_face", "src/live/window",
                        settings);
#endif
    return makeError(ErrorKind::Usage, "\"" + name + "\" is not a face of this infocus");
}

}  // namespace

std::vector<std::string> builtFaces() {
    std::vector<std::string> out;
    if (HAVE_TUI) out.emplace_back("tui");
    if (HAVE_WINDOW) out.emplace_back("window");
    out.emplace_back("text");
    out.emplace_back("json");
    if (HAVE_WEB) out.emplace_back("web");
    return out;
}

std::string defaultFace(bool onTerminal) {
    return onTerminal && HAVE_TUI ? "tui" : "text";
}

Result<FaceChoice> parseFaces(std::string_view ui) {
    FaceChoice f;
    std::stringstream list{std::string(ui)};
    std::string face;
    const auto usage = [&](const std::string& why) {
        return makeError(ErrorKind::Usage, "--ui " + std::string(ui) + ": " + why +
                                               "; use one of tui, window, text or json, and/or "
                                               "web, e.g. --ui web or --ui tui,web");
    };
    while (std::getline(list, face, ',')) {
        if (face == "web") {
            f.web = true;
        } else if (face == "tui" || face == "window" || face == "text" || face == "json") {
            if (!f.blocking.empty()) return usage("at most one of tui, window, text and json");
            f.blocking = face;
        } else {
            return usage("\"" + face + "\" is not a face");
        }
    }
    if (f.blocking.empty() && !f.web) return usage("no face named");
    if (f.blocking == "tui" && !built("tui")) return notBuilt("terminal", "libncurses-dev");
    if (f.blocking == "window" && !built("window"))
        return notBuilt("window", "libsdl2-dev and libimgui-dev");
    if (f.web && !built("web")) return notBuilt("web", "libcpp-httplib-dev");
    return f;
}

Result<FaceSet> FaceSet::make(const FaceChoice& choice, const FaceSettings& settings,
                              LiveOptions& options) {
    FaceSet set;
    if (!choice.blocking.empty()) {
        auto face = makeFace(choice.blocking, settings);
        if (!face) return face.error();
        set.blocking_ = std::move(*face);
        if (Status st = set.blocking_->prepare(options); !st) return st.error();
    }
    if (choice.web) {
        auto face = makeFace("web", settings);
        if (!face) return face.error();
        set.web_ = std::move(*face);
        if (Status st = set.web_->prepare(options); !st) return st.error();
    }
    return set;
}

FaceSet::FaceSet(FaceSet&&) noexcept = default;
FaceSet& FaceSet::operator=(FaceSet&&) noexcept = default;
FaceSet::~FaceSet() {
    if (web_) web_->stop();
    if (blocking_) blocking_->stop();
}

Status FaceSet::run(LiveView& view, const RunLimits& limits) {
    if (web_)
        if (Status st = web_->start(view); !st) return st;
    Status result = blocking_ ? blocking_->run(view, limits) : waitForEnd(view, limits);
    if (web_) web_->stop();
    if (blocking_) blocking_->stop();
    return result;
}

}  // namespace infocus
