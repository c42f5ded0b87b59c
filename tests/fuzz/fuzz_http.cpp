// SPDX-License-Identifier: MIT
// The web view's request handling: any bytes as one connection's requests (up to five kept
// alive) to the real server on a small simulated camera, answered from memory by the server's
// own request path (answerBytes): the library's parser, the gate (token, Host, method), every
// route and the streams. The first byte picks the target: the token-less loopback server, the
// server with a token, or POST /control's parser run directly on the pipeline.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <string_view>

#include "infocus/live.h"
#include "src/live/web/web.h"
#include "src/live/web/web_control.h"
#include "tests/fuzz/fuzz.h"

namespace {

using namespace infocus;

constexpr const char* kToken = "fuzz-token-0123456789abcdef";

struct Fixture {
    std::unique_ptr<LivePipeline> pipeline;
    std::unique_ptr<WebServer> open, guarded;
};

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "fuzz_http: %s\n", what.c_str());
    std::abort();
}

// One pipeline and two servers for the whole process, started once. Never destroyed: their
// threads run until the process ends.
Fixture& fixture() {
    static Fixture* const f = [] {
        auto* fx = new Fixture;
        LiveOptions options;
        options.previewLongSide = 160;
        auto p = LivePipeline::open("sim:size=160x120,fps=30", options);
        if (!p) fail(p.error().message);
        fx->pipeline = std::move(*p);
        if (Status st = fx->pipeline->start(); !st) fail(st.error().message);
        // Every route then has a state to answer from.
        if (!fx->pipeline->waitForState(std::nullopt, std::chrono::seconds(10)))
            fail("the simulated camera gave no state in 10 s");
        WebOptions o;
        o.listen = "127.0.0.1:0";
        o.previewLongSide = options.previewLongSide;
        auto open = WebServer::start(*fx->pipeline, o);
        if (!open) fail(open.error().message);
        fx->open = std::move(*open);
        o.token = kToken;
        auto guarded = WebServer::start(*fx->pipeline, o);
        if (!guarded) fail(guarded.error().message);
        fx->guarded = std::move(*guarded);
        return fx;
    }();
    return *f;
}

}  // namespace

namespace infocus::fuzz {

std::vector<std::vector<uint8_t>> seeds() {
    const std::string token = kToken;
    const std::string host = "Host: 127.0.0.1\r\n";
    const std::string control =
        "POST /control HTTP/1.1\r\n" + host + "Content-Type: application/json\r\nContent-Length: ";
    std::vector<std::string> requests = {
        std::string(1, '\x01') + "GET / HTTP/1.1\r\n" + host + "\r\n",
        std::string(1, '\x01') + "GET /state HTTP/1.1\r\n" + host + "\r\nGET /app.js HTTP/1.1\r\n" +
            host + "Connection: close\r\n\r\n",
        std::string(1, '\x01') + "HEAD /style.css HTTP/1.0\r\n" + host + "\r\n",
        std::string(1, '\x01') + control + "20\r\n\r\n{\"reset_peak\": true}",
        std::string(1, '\x01') + control + "16\r\n\r\n{\"grid\": [4, 3]}",
        std::string(1, '\x01') + "GET /events HTTP/1.1\r\n" + host + "\r\n",
        std::string(1, '\x01') + "GET /stream.mjpg HTTP/1.1\r\n" + host + "\r\n",
        std::string(1, '\x01') + "GET /peaking.png HTTP/1.1\r\nHost: [::1]:8080\r\n\r\n",
        std::string(1, '\x01') + "GET /magnifier.jpg HTTP/1.1\r\nHost: localhost\r\n\r\n",
        std::string(1, '\x01') + "DELETE /state HTTP/1.1\r\n" + host + "\r\n",
        std::string(1, '\x01') + "GET /state HTTP/1.1\r\nHost: evil.example\r\n\r\n",
        std::string(1, '\x01') + "POST /control HTTP/1.1\r\n" + host +
            "Content-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n"
            "8\r\n{\"grid\":\r\n8\r\n [8, 6]}\r\n0\r\n\r\n",
        std::string(1, '\x01') + "GET /state HTTP/1.1\r\n" + host + "Range: bytes=0-10,20-\r\n\r\n",
        std::string(1, '\x02') + "GET /state?token=" + token + " HTTP/1.1\r\n\r\n",
        std::string(1, '\x02') + "GET /state HTTP/1.1\r\nAuthorization: Bearer " + token +
            "\r\n\r\n",
        std::string(1, '\x02') + "GET /?token=wrong HTTP/1.1\r\n\r\n",
        std::string(1, '\x02') + "POST /control?token=" + token +
            " HTTP/1.1\r\nContent-Type: application/json\r\nContent-Length: 18\r\n\r\n"
            "{\"focus_step\": -3}",
        std::string(1, '\x00') + "{\"magnifier\": [80, 60, 2]}",
        std::string(1, '\x00') + "{\"roi\": [10, 10, 50, 40]}",
        std::string(1, '\x00') + "{\"peaking\": \"percentile\"}",
        std::string(1, '\x00') + "{\"focus\": 0.25}",
        std::string(1, '\x00') + "{\"roi\": null}",
    };
    std::vector<std::vector<uint8_t>> out;
    for (const std::string& r : requests)
        out.emplace_back(r.begin(), r.end());
    return out;
}

}  // namespace infocus::fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    Fixture& f = fixture();
    const std::string_view rest(reinterpret_cast<const char*>(data + 1), size - 1);
    switch (data[0] % 3) {
        case 0: {
            const web::ControlReply r = web::runControl(rest, *f.pipeline, true);
            if (r.body.empty())
                fail("/control answered " + std::to_string(r.httpStatus) + " with no body");
            break;
        }
        case 1:
            (void)answerBytes(*f.open, rest);
            break;
        default:
            (void)answerBytes(*f.guarded, rest);
            break;
    }
    return 0;
}
