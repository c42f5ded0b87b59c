// SPDX-License-Identifier: MIT
// The web page as a face, and the module entry point that gives it to `infocus live`.
#include <algorithm>
#include <iostream>

#include "src/live/face_module.h"
#include "src/live/web/web.h"

namespace infocus {

namespace {

// Serves the page in the background from start() to stop(); alone, it waits for the run's end.
class WebFace final : public Face {
public:
    explicit WebFace(const FaceSettings& settings) {
        options_.listen = settings.listen;
        if (!settings.token.empty()) options_.token = settings.token;
    }

    Status prepare(LiveOptions& options) override {
        if (auto a = parseListenAddress(options_.listen); !a) return a.error();
        options.previewLongSide = std::max(options.previewLongSide, options_.previewLongSide);
        return {};
    }

    Status start(LiveView& view) override {
        auto started = WebServer::start(view, options_);
        if (!started) return started.error();
        server_ = std::move(*started);
        std::cerr << "infocus live: open " << server_->url() << std::endl;
        return {};
    }

    Status run(LiveView& view, const RunLimits& limits) override {
        return waitForEnd(view, limits);
    }

    void stop() override {
        if (server_) server_->stop();
    }

private:
    WebOptions options_;
    std::unique_ptr<WebServer> server_;
};

}  // namespace

}  // namespace infocus

extern "C" __attribute__((visibility("default"))) const infocus::FaceModule* infocus_web_face() {
    static const infocus::FaceModule table{
        infocus::kFaceModuleAbi, [](const infocus::FaceSettings& settings) -> infocus::Face* {
            return new infocus::WebFace(settings);
        }};
    return &table;
}
