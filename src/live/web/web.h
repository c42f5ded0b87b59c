// SPDX-License-Identifier: MIT
/// @file web.h
/// The web face of `infocus live`: an HTTP server on the live pipeline that serves a page, the
/// newest state (JSON and server-sent events), an MJPEG stream of the preview, the peaking mask
/// and the magnifier crop, and takes the page's controls. The HTTP contract is in docs/live.md.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "infocus/error.h"
#include "infocus/live.h"

namespace infocus {

/// Where the server listens and what it allows.
struct WebOptions {
    /// "ADDR:PORT": an IPv4 address, "localhost" or a bracketed IPv6 address; port 0 picks a
    /// free port. Loopback by default.
    std::string listen = "127.0.0.1:8080";
    /// The token every request must carry; generated (128 bits, hex) when empty and the address
    /// is beyond loopback. Given on loopback, it is required there too.
    std::optional<std::string> token;
    int maxStreams = 8;        ///< concurrent /stream.mjpg clients; more get 503
    int maxEventClients = 16;  ///< concurrent /events clients; more get 503
    /// Long side of the preview the pipeline should publish (LiveOptions::previewLongSide).
    int previewLongSide = 960;
    int jpegQuality = 80;         ///< of the MJPEG frames and the magnifier crop
    double maxEventsPerS = 30.0;  ///< per /events client; the newest state only
    size_t maxBodyBytes = 4096;   ///< POST bodies beyond this get 413
};

/// An address and port parsed from "ADDR:PORT".
struct ListenAddress {
    std::string host;  ///< without brackets ("::1")
    int port = 0;      ///< 0–65535; 0: any free port
    bool loopback = false;
};

/// Parses @p text as "ADDR:PORT" (IPv4, "localhost" or "[IPv6]"); ErrorKind::Usage naming what
/// is wrong otherwise.
Result<ListenAddress> parseListenAddress(std::string_view text);

/// The server: its own threads (the listener, its pool and one preview encoder) until stop().
class WebServer {
public:
    /// Binds @p options.listen and starts serving @p pipeline, which must outlive the server.
    /// ErrorKind::Io naming the address when it cannot be bound (in use, not on this machine).
    static Result<std::unique_ptr<WebServer>> start(LiveView& pipeline, const WebOptions& options);
    /// Stops the server (stop()).
    virtual ~WebServer() = default;
    /// Closes the listening socket and every streaming connection, and joins the threads;
    /// returns within about a second. Safe to call twice.
    virtual void stop() = 0;
    /// The URL to open, with the token as a query parameter when there is one.
    virtual std::string url() const = 0;
    /// The port bound (the one chosen when the options asked for port 0).
    virtual int port() const = 0;
    /// The token requests must carry, empty when none is needed.
    virtual std::string token() const = 0;

protected:
    WebServer() = default;
};

/// Answers the HTTP requests in @p bytes (one connection's, up to 5 kept-alive requests) as
/// @p server would on a socket, without one, and returns the bytes it would have sent; a
/// stream's answer is cut after about 50 ms. The request fuzzer's way into the server.
std::string answerBytes(WebServer& server, std::string_view bytes);

}  // namespace infocus
