// SPDX-License-Identifier: MIT
// The web view's HTTP server (cpp-httplib): routes, the token, bounds on clients and bodies, and
// the streams. What each path answers is in docs/live.md ("Web view").
#include "src/live/web/web.h"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/random.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <httplib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <deque>
#include <functional>
#include <map>
#include <random>
#include <thread>

#include "infocus/live.h"
#include "src/live/web/page_assets.h"
#include "src/live/web/web_control.h"
#include "src/live/web/web_encode.h"
#include "src/live/web/web_hub.h"

namespace infocus {

namespace {

using namespace std::chrono_literals;
using web::errorJson;

constexpr const char* kJson = "application/json";
constexpr const char* kBoundary = "infocusframe";
// How often a waiting stream looks at its socket and at stop(): the bound on a clean stop.
constexpr auto kPoll = 100ms;
constexpr auto kPingInterval = 10s;
constexpr int kBacklog = 1024;         // connections the kernel holds before accept()
constexpr int kKeepAliveRequests = 5;  // the library's limit of requests on one connection

// 128 random bits as hex, from the kernel (getrandom), else std::random_device.
std::string makeToken() {
    unsigned char bytes[16];
    if (getrandom(bytes, sizeof bytes, 0) != static_cast<ssize_t>(sizeof bytes)) {
        std::random_device rd;
        for (unsigned char& b : bytes)
            b = static_cast<unsigned char>(rd());
    }
    std::string hex;
    char two[3];
    for (unsigned char b : bytes) {
        std::snprintf(two, sizeof two, "%02x", b);
        hex += two;
    }
    return hex;
}

// Headers on every answer, errors included: nothing is cached (the state and the token's URL
// change), a browser never guesses a type, no other site may frame or read the answers (no
// Access-Control-Allow-Origin is ever sent) and no Referer carries the token's URL elsewhere.
constexpr const char* kCsp = "Content-Security-Policy";
constexpr const char* kBlankCsp =
    "default-src 'none'; base-uri 'none'; form-action 'none'; frame-ancestors 'none'";

httplib::Headers defaultHeaders() {
    return {{"Cache-Control", "no-store"},
            {"X-Content-Type-Options", "nosniff"},
            {"Referrer-Policy", "no-referrer"},
            {"X-Frame-Options", "DENY"},
            {kCsp, kBlankCsp}};
}

// The page's policy: its own script and style only, the inline loader by its hash (no
// 'unsafe-inline'), pictures from the server and the blobs the page makes of them, requests to
// this server only.
std::string pagePolicy() {
    std::string scripts = "'self'";
    for (const web::PageAsset& a : web::pageAssets()) {
        if (std::string_view(a.path) != "/") continue;
        const std::string_view html(reinterpret_cast<const char*>(a.data), a.size);
        for (size_t at = html.find("<script>"); at != std::string_view::npos;
             at = html.find("<script>", at)) {
            at += 8;
            const size_t end = html.find("</script>", at);
            if (end == std::string_view::npos) break;
            const auto digest = web::sha256(html.substr(at, end - at));
            scripts += " 'sha256-" +
                       web::base64({reinterpret_cast<const char*>(digest.data()), digest.size()}) +
                       "'";
        }
    }
    return "default-src 'none'; script-src " + scripts +
           "; style-src 'self'; img-src 'self' blob: data:; connect-src 'self'; "
           "base-uri 'none'; form-action 'none'; frame-ancestors 'none'";
}

// How long a connection may wait between accept() and its request: for a first byte (or the next
// request of a kept-alive connection), and for the rest of a request once it has begun.
constexpr auto kIdleTimeout = 1s;
constexpr auto kRequestTimeout = 2s;
// A worker gets a request only once it has arrived whole, so a read that has to wait is past
// it (a body longer than the limit, which the library would read to its end): it waits this
// long at most. And a write waits for a reader this long at most.
constexpr auto kReadWait = 100ms;
constexpr auto kWriteWait = 2s;
// The waiting room's size bound, within the process's descriptor limit.
constexpr size_t kMaxWaiting = 4096;
// How much of a waiting request is looked at (the library refuses longer heads).
constexpr size_t kPeekBytes = 16384;

// A connection between requests: its socket, the bytes read from it but not yet parsed, and
// when it began to wait.
struct Connection {
    int fd = -1;
    std::string buffered;
    size_t requests = 0;
    uint64_t ticket = 0;  // its place in the order of waiting
    std::chrono::steady_clock::time_point waitingSince, firstByte;
    bool begun = false;  // a byte of the next request has arrived
    ~Connection() {
        if (fd >= 0) {
            ::shutdown(fd, SHUT_RDWR);
            ::close(fd);
        }
    }
};

// A socket as the library's Stream: reads through the connection's buffer, and every wait in
// slices of kPoll so that stop() ends it promptly.
class SocketStream final : public httplib::Stream {
public:
    SocketStream(Connection& c, const std::atomic<bool>& stopping) : c_(c), stopping_(stopping) {}

    bool is_readable() const override { return !c_.buffered.empty() || wait(POLLIN, kReadWait); }
    bool is_writable() const override {
        if (!wait(POLLOUT, kWriteWait)) return false;
        // A peer that has closed reads as readable with nothing to read.
        pollfd p{c_.fd, POLLIN, 0};
        if (::poll(&p, 1, 0) == 1) {
            char b;
            if (::recv(c_.fd, &b, 1, MSG_PEEK | MSG_DONTWAIT) == 0) return false;
        }
        return true;
    }
    ssize_t read(char* ptr, size_t size) override {
        if (c_.buffered.empty()) {
            if (!wait(POLLIN, kReadWait)) return -1;
            char chunk[4096];
            const ssize_t n = ::recv(c_.fd, chunk, sizeof chunk, MSG_DONTWAIT);
            if (n <= 0) return n;
            c_.buffered.assign(chunk, static_cast<size_t>(n));
        }
        size = std::min(size, c_.buffered.size());
        std::memcpy(ptr, c_.buffered.data(), size);
        c_.buffered.erase(0, size);
        return static_cast<ssize_t>(size);
    }
    ssize_t write(const char* ptr, size_t size) override {
        size_t done = 0;
        while (done < size) {
            if (!wait(POLLOUT, kWriteWait)) return -1;
            const ssize_t n = ::send(c_.fd, ptr + done, size - done, MSG_NOSIGNAL | MSG_DONTWAIT);
            if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) continue;
            if (n <= 0) return -1;
            done += static_cast<size_t>(n);
        }
        return static_cast<ssize_t>(size);
    }
    void get_remote_ip_and_port(std::string& ip, int& port) const override {
        address(false, ip, port);
    }
    void get_local_ip_and_port(std::string& ip, int& port) const override {
        address(true, ip, port);
    }
    socket_t socket() const override { return c_.fd; }

private:
    // Waits up to @p limit for @p events, in slices, until stop().
    bool wait(short events, std::chrono::milliseconds limit) const {
        const auto end = std::chrono::steady_clock::now() + limit;
        while (!stopping_.load()) {
            pollfd p{c_.fd, events, 0};
            const int r = ::poll(&p, 1, static_cast<int>(kPoll.count()));
            if (r > 0) return (p.revents & (events | POLLHUP | POLLERR)) != 0;
            if (r < 0 && errno != EINTR) return false;
            if (std::chrono::steady_clock::now() >= end) return false;
        }
        return false;
    }
    void address(bool local, std::string& ip, int& port) const {
        sockaddr_storage a{};
        socklen_t len = sizeof a;
        auto* sa = reinterpret_cast<sockaddr*>(&a);
        if ((local ? ::getsockname(c_.fd, sa, &len) : ::getpeername(c_.fd, sa, &len)) != 0) return;
        char host[INET6_ADDRSTRLEN] = "";
        if (a.ss_family == AF_INET) {
            const auto* in = reinterpret_cast<const sockaddr_in*>(&a);
            inet_ntop(AF_INET, &in->sin_addr, host, sizeof host);
            port = ntohs(in->sin_port);
        } else if (a.ss_family == AF_INET6) {
            const auto* in = reinterpret_cast<const sockaddr_in6*>(&a);
            inet_ntop(AF_INET6, &in->sin6_addr, host, sizeof host);
            port = ntohs(in->sin6_port);
        }
        ip = host;
    }

    Connection& c_;
    const std::atomic<bool>& stopping_;
};

// Whether @p bytes hold a whole request head, and its body when it announces a length of at most
// @p maxBody (a longer one is refused by the library at once, from the head alone).
bool wholeRequest(std::string_view bytes, size_t maxBody) {
    const size_t head = bytes.find("\r\n\r\n");
    if (head == std::string_view::npos) return bytes.size() >= kPeekBytes;
    std::string lower(bytes.substr(0, head));
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
    const size_t at = lower.find("\ncontent-length:");
    if (at == std::string::npos) return true;
    const size_t length = std::strtoull(lower.c_str() + at + 16, nullptr, 10);
    return length > maxBody || bytes.size() >= head + 4 + length || bytes.size() >= kPeekBytes;
}

// Connections from accept() to their answers. A connection waits in an epoll set, holding no
// thread, until its whole request has arrived (or it is closed for its time-out); only then does
// a worker answer it, and a kept-alive connection returns to wait for its next request. So
// connections that send nothing, half a request or a slow body cost a descriptor for at most
// two seconds and never a worker, and the waiting room's bound closes the oldest waiting when a
// flood fills it.
class Connections {
public:
    // @p answer: one request of a stream, as the library answers it.
    using Answer = std::function<bool(httplib::Stream&, bool lastRequest, bool& closed)>;

    Connections(size_t workers, size_t maxBody, Answer answer)
        : maxBody_(maxBody), answer_(std::move(answer)) {
        rlimit files{};
        maxWaiting_ = kMaxWaiting;
        // Half the descriptors at most: the camera, the pipeline and the streams need theirs.
        if (getrlimit(RLIMIT_NOFILE, &files) == 0 && files.rlim_cur != RLIM_INFINITY)
            maxWaiting_ = std::min<size_t>(maxWaiting_, files.rlim_cur / 2);
        epoll_ = ::epoll_create1(EPOLL_CLOEXEC);
        waker_ = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
        epoll_event ev{};
        ev.events = EPOLLIN;
        ev.data.fd = waker_;
        ::epoll_ctl(epoll_, EPOLL_CTL_ADD, waker_, &ev);
        waiter_ = std::thread([this] { waitLoop(); });
        for (size_t i = 0; i < workers; ++i)
            workers_.emplace_back([this] { workLoop(); });
    }

    ~Connections() {
        stop();
        ::close(epoll_);
        ::close(waker_);
    }

    // Takes a socket accept() returned.
    void adopt(int fd) {
        auto c = std::make_unique<Connection>();
        c->fd = fd;
        wait(std::move(c));
    }

    // Ends the threads and closes every connection; safe to call twice.
    void stop() {
        if (stopping_.exchange(true)) return;
        const uint64_t one = 1;
        (void)!::write(waker_, &one, sizeof one);
        cv_.notify_all();
        if (waiter_.joinable()) waiter_.join();
        for (std::thread& t : workers_)
            t.join();
        std::lock_guard lock(mutex_);
        waiting_.clear();
        ready_.clear();
    }

private:
    void wait(std::unique_ptr<Connection> c) {
        c->waitingSince = std::chrono::steady_clock::now();
        c->begun = !c->buffered.empty();
        c->firstByte = c->waitingSince;
        // A pipelined request already read needs no wait.
        if (!c->buffered.empty() && wholeRequest(c->buffered, maxBody_))
            return dispatch(std::move(c));
        std::lock_guard lock(mutex_);
        if (stopping_.load()) return;
        // The one that has waited longest is the likeliest to send nothing.
        while (waiting_.size() >= maxWaiting_ && !order_.empty()) {
            const auto [ticket, fd] = order_.front();
            order_.pop_front();
            auto it = waiting_.find(fd);
            if (it == waiting_.end() || it->second->ticket != ticket) continue;
            ::epoll_ctl(epoll_, EPOLL_CTL_DEL, fd, nullptr);
            waiting_.erase(it);
        }
        c->ticket = ++tickets_;
        order_.emplace_back(c->ticket, c->fd);
        epoll_event ev{};
        ev.events = EPOLLIN | EPOLLRDHUP | EPOLLET;
        ev.data.fd = c->fd;
        if (::epoll_ctl(epoll_, EPOLL_CTL_ADD, c->fd, &ev) != 0) return;  // closes it
        const int fd = c->fd;
        waiting_[fd] = std::move(c);
    }

    void dispatch(std::unique_ptr<Connection> c) {
        {
            std::lock_guard lock(mutex_);
            if (stopping_.load()) return;
            ready_.push_back(std::move(c));
        }
        cv_.notify_one();
    }

    // Whether the connection's request is whole (or it has ended: the library then answers what
    // came, or nothing); false leaves it waiting.
    bool ready(Connection& c) {
        char peek[kPeekBytes];
        const ssize_t n = ::recv(c.fd, peek, sizeof peek, MSG_PEEK | MSG_DONTWAIT);
        if (n == 0) return true;
        if (n < 0) return errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR;
        if (!c.begun) {
            c.begun = true;
            c.firstByte = std::chrono::steady_clock::now();
        }
        if (c.buffered.empty())
            return wholeRequest(std::string_view(peek, static_cast<size_t>(n)), maxBody_);
        return wholeRequest(c.buffered + std::string(peek, static_cast<size_t>(n)), maxBody_);
    }

    void waitLoop() {
        epoll_event events[64];
        auto lastSweep = std::chrono::steady_clock::now();
        while (!stopping_.load()) {
            const int n = ::epoll_wait(epoll_, events, 64, static_cast<int>(kPoll.count()));
            for (int i = 0; i < n; ++i) {
                const int fd = events[i].data.fd;
                if (fd == waker_) continue;
                std::unique_ptr<Connection> c;
                {
                    std::lock_guard lock(mutex_);
                    auto it = waiting_.find(fd);
                    if (it == waiting_.end() || !ready(*it->second)) continue;
                    ::epoll_ctl(epoll_, EPOLL_CTL_DEL, fd, nullptr);
                    c = std::move(it->second);
                    waiting_.erase(it);
                }
                dispatch(std::move(c));
            }
            const auto now = std::chrono::steady_clock::now();
            if (now - lastSweep < kPoll) continue;
            lastSweep = now;
            std::lock_guard lock(mutex_);
            // The order keeps only what may still wait: the front has left, or is the oldest.
            while (!order_.empty()) {
                auto it = waiting_.find(order_.front().second);
                if (it != waiting_.end() && it->second->ticket == order_.front().first) break;
                order_.pop_front();
            }
            for (auto it = waiting_.begin(); it != waiting_.end();) {
                const Connection& c = *it->second;
                const bool late = c.begun ? now - c.firstByte > kRequestTimeout
                                          : now - c.waitingSince > kIdleTimeout;
                if (!late) {
                    ++it;
                    continue;
                }
                ::epoll_ctl(epoll_, EPOLL_CTL_DEL, it->first, nullptr);
                it = waiting_.erase(it);
            }
        }
    }

    void workLoop() {
        for (;;) {
            std::unique_ptr<Connection> c;
            {
                std::unique_lock lock(mutex_);
                cv_.wait(lock, [this] { return stopping_.load() || !ready_.empty(); });
                if (stopping_.load()) return;
                c = std::move(ready_.front());
                ready_.pop_front();
            }
            SocketStream stream(*c, stopping_);
            bool closed = false;
            const bool last = ++c->requests >= static_cast<size_t>(kKeepAliveRequests);
            const bool ok = answer_(stream, last, closed);
            if (ok && !closed && !last && !stopping_.load()) wait(std::move(c));
        }
    }

    const size_t maxBody_;
    const Answer answer_;
    size_t maxWaiting_;
    int epoll_ = -1, waker_ = -1;
    std::atomic<bool> stopping_{false};
    std::mutex mutex_;
    std::condition_variable cv_;
    std::map<int, std::unique_ptr<Connection>> waiting_;
    std::deque<std::unique_ptr<Connection>> ready_;
    std::deque<std::pair<uint64_t, int>> order_;  // (ticket, fd) in the order they began to wait
    uint64_t tickets_ = 0;
    std::thread waiter_;
    std::vector<std::thread> workers_;
};

// Runs each accepted socket's job at once on the accepting thread: the job only hands the
// socket to Connections, which owns every thread that answers.
class HandOver final : public httplib::TaskQueue {
public:
    void enqueue(std::function<void()> job) override { job(); }
    void shutdown() override {}
};

// cpp-httplib's server with what its public interface lacks: the listen backlog, which the
// library leaves at 5 (a burst of connections would wait for SYN retries, a second and more),
// accepted sockets handed to Connections instead of a thread each, and one request answered
// from any Stream (Connections' and the request fuzzer's way in).
class HttpServer final : public httplib::Server {
public:
    bool widenBacklog(int backlog) { return ::listen(svr_sock_, backlog) == 0; }
    bool answer(httplib::Stream& stream, bool lastRequest, bool& closed) {
        return process_request(stream, lastRequest, closed, nullptr);
    }
    void handTo(Connections* connections) { connections_ = connections; }

private:
    bool process_and_close_socket(socket_t sock) override {
        connections_->adopt(sock);
        return true;
    }
    Connections* connections_ = nullptr;
};

// One connection held in memory: reads come from the bytes given, writes are kept. Writing ends
// after kMaxBytes or kMaxTime so that a stream's answer (MJPEG, events) ends too.
class MemoryStream final : public httplib::Stream {
public:
    explicit MemoryStream(std::string_view in) : in_(in) {}
    bool is_readable() const override { return pos_ < in_.size(); }
    bool is_writable() const override {
        return out_.size() < kMaxBytes && std::chrono::steady_clock::now() - start_ < kMaxTime;
    }
    ssize_t read(char* ptr, size_t size) override {
        size = std::min(size, in_.size() - pos_);
        std::memcpy(ptr, in_.data() + pos_, size);
        pos_ += size;
        return static_cast<ssize_t>(size);
    }
    ssize_t write(const char* ptr, size_t size) override {
        if (!is_writable()) return -1;
        out_.append(ptr, size);
        return static_cast<ssize_t>(size);
    }
    void get_remote_ip_and_port(std::string& ip, int& port) const override {
        ip = "127.0.0.1";
        port = 40000;
    }
    void get_local_ip_and_port(std::string& ip, int& port) const override {
        ip = "127.0.0.1";
        port = 8080;
    }
    socket_t socket() const override { return INVALID_SOCKET; }
    const std::string& written() const { return out_; }

private:
    static constexpr size_t kMaxBytes = 1 << 20;
    static constexpr auto kMaxTime = 50ms;
    std::string_view in_;
    size_t pos_ = 0;
    std::string out_;
    const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// The first non-loopback IPv4 address of this machine, for the URL of a wildcard listener.
std::string firstOutsideAddress() {
    ifaddrs* list = nullptr;
    std::string found = "127.0.0.1";
    if (getifaddrs(&list) != 0) return found;
    for (ifaddrs* a = list; a; a = a->ifa_next) {
        if (!a->ifa_addr || a->ifa_addr->sa_family != AF_INET) continue;
        const auto* in = reinterpret_cast<const sockaddr_in*>(a->ifa_addr);
        if ((ntohl(in->sin_addr.s_addr) >> 24) == 127) continue;
        char buf[INET_ADDRSTRLEN];
        if (inet_ntop(AF_INET, &in->sin_addr, buf, sizeof buf)) {
            found = buf;
            break;
        }
    }
    freeifaddrs(list);
    return found;
}

// The host part of a Host header, without port and brackets.
std::string hostOf(const std::string& header) {
    if (!header.empty() && header[0] == '[') return header.substr(1, header.find(']') - 1);
    return header.substr(0, header.find(':'));
}

class WebServerImpl final : public WebServer {
public:
    WebServerImpl(LiveView& pipeline, const WebOptions& options, ListenAddress address)
        : pipeline_(pipeline),
          options_(options),
          address_(std::move(address)),
          hub_(pipeline, options.jpegQuality) {
        if (options.token && !options.token->empty())
            token_ = *options.token;
        else if (!address_.loopback)
            token_ = makeToken();
    }

    ~WebServerImpl() override { stop(); }

    Status listen() {
        server_.new_task_queue = [] { return new HandOver; };
        server_.handTo(&connections_);
        server_.set_payload_max_length(options_.maxBodyBytes);
        server_.set_default_headers(defaultHeaders());
        server_.set_pre_routing_handler(
            [this](const httplib::Request& req, httplib::Response& res) { return gate(req, res); });
        server_.set_error_handler(httplib::Server::HandlerWithResponse(
            [](const httplib::Request&, httplib::Response& res) {
                if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
                const char* what = res.status == 404   ? "no such path"
                                   : res.status == 413 ? "the request body is over the limit"
                                                       : "bad request";
                res.set_content(errorJson(what), kJson);
                return httplib::Server::HandlerResponse::Handled;
            }));
        routes();

        errno = 0;
        if (address_.port == 0) {
            const int port = server_.bind_to_any_port(address_.host);
            if (port > 0) port_ = port;
        } else if (server_.bind_to_port(address_.host, address_.port)) {
            port_ = address_.port;
        }
        if (port_ <= 0) {
            const int err = errno;
            return makeError(ErrorKind::Io,
                             "cannot listen on " + options_.listen + ": " +
                                 (err ? std::strerror(err) : "the address cannot be bound") +
                                 "; use --listen with another port (e.g. --listen 127.0.0.1:8081) "
                                 "or an address of this machine",
                             err);
        }
        // A failure leaves the library's backlog: the server works, a flood waits longer.
        (void)server_.widenBacklog(kBacklog);
        listener_ = std::thread([this] { server_.listen_after_bind(); });
        // stop() only reaches a server that is running: wait for it (a bound socket starts at
        // once) so an early stop cannot leave the listener behind.
        for (int i = 0; i < 2000 && !server_.is_running(); ++i)
            std::this_thread::sleep_for(1ms);
        return {};
    }

    void stop() override {
        hub_.stop();
        if (server_.is_running() || listener_.joinable()) server_.stop();
        if (listener_.joinable()) listener_.join();
        connections_.stop();
    }

    std::string url() const override {
        std::string host = address_.host;
        if (host == "0.0.0.0" || host == "::") host = firstOutsideAddress();
        if (host.find(':') != std::string::npos) host = "[" + host + "]";
        std::string u = "http://" + host + ":" + std::to_string(port_) + "/";
        if (!token_.empty()) u += "?token=" + token_;
        return u;
    }

    int port() const override { return port_; }
    std::string token() const override { return token_; }

    // The requests in @p bytes as one connection's, answered without a socket (answerBytes).
    std::string answerBytes(std::string_view bytes) {
        MemoryStream stream(bytes);
        // As many requests as a kept-alive connection may carry.
        for (int i = 0; i < kKeepAliveRequests && stream.is_readable(); ++i) {
            bool closed = false;
            if (!server_.answer(stream, i + 1 == kKeepAliveRequests, closed) || closed) break;
        }
        return stream.written();
    }

private:
    using HR = httplib::Server::HandlerResponse;

    // Before any route: the token, the Host of a token-less loopback server, the method.
    HR gate(const httplib::Request& req, httplib::Response& res) {
        if (!token_.empty()) {
            std::string given = req.get_param_value("token");
            const std::string auth = req.get_header_value("Authorization");
            if (given.empty() && auth.rfind("Bearer ", 0) == 0) given = auth.substr(7);
            if (!web::sameSecret(given, token_)) {
                res.status = 401;
                res.set_content(errorJson("a missing or wrong token; open the URL infocus live "
                                          "printed, with its ?token="),
                                kJson);
                return HR::Handled;
            }
        } else {
            // Without a token only a loopback name may be asked for, so a page from elsewhere
            // cannot reach this server through a name it rebinds to 127.0.0.1.
            const std::string host = hostOf(req.get_header_value("Host"));
            if (host != "127.0.0.1" && host != "localhost" && host != "::1" &&
                host != address_.host) {
                res.status = 403;
                res.set_content(errorJson("Host " + host + " is not this loopback server"), kJson);
                return HR::Handled;
            }
        }
        const auto known = methods_.find(req.path);
        if (known == methods_.end()) return HR::Unhandled;  // 404 by the router
        const std::string& allowed = known->second;
        const bool ok = req.method == allowed || (allowed == "GET" && req.method == "HEAD");
        if (!ok) {
            res.status = 405;
            res.set_header("Allow", allowed);
            res.set_content(
                errorJson(req.method + " is not allowed on " + req.path + "; use " + allowed),
                kJson);
            return HR::Handled;
        }
        return HR::Unhandled;
    }

    void routes() {
        for (const web::PageAsset& a : web::pageAssets()) {
            methods_[a.path] = "GET";
            server_.Get(a.path, [this, a](const httplib::Request&, httplib::Response& res) {
                res.headers.erase(kCsp);
                res.set_header(kCsp, pagePolicy_);
                res.set_content(reinterpret_cast<const char*>(a.data), a.size, a.contentType);
            });
        }
        for (const char* p :
             {"/state", "/events", "/stream.mjpg", "/peaking.png", "/magnifier.jpg"})
            methods_[p] = "GET";
        methods_["/control"] = "POST";

        server_.Get("/state", [this](const httplib::Request&, httplib::Response& res) {
            auto s = pipeline_.state();
            if (!s) return noFrame(res);
            res.set_content(liveStateJson(*s), kJson);
        });
        server_.Get("/peaking.png", [this](const httplib::Request&, httplib::Response& res) {
            auto s = pipeline_.state();
            if (!s) return noFrame(res);
            if (s->peaking == PeakingMode::Off || !s->peakingMask)
                return fail(res, 404, "peaking is off; POST {\"peaking\": \"percentile\"}");
            auto png = web::encodeMaskPng(*s->peakingMask);
            if (!png) return fail(res, 500, png.error().message);
            res.set_header("X-Frame", std::to_string(s->frame));
            res.set_content(*png, "image/png");
        });
        server_.Get("/magnifier.jpg", [this](const httplib::Request&, httplib::Response& res) {
            auto s = pipeline_.state();
            if (!s) return noFrame(res);
            if (!s->magnifier)
                return fail(res, 404, "no magnifier placed; POST {\"magnifier\": [x, y, zoom]}");
            auto jpeg = web::encodeGreyJpeg(s->magnifier->crop, options_.jpegQuality);
            if (!jpeg) return fail(res, 500, jpeg.error().message);
            res.set_header("X-Frame", std::to_string(s->frame));
            res.set_content(*jpeg, "image/jpeg");
        });
        server_.Post("/control", [this](const httplib::Request& req, httplib::Response& res) {
            const std::string type = req.get_header_value("Content-Type");
            // A JSON type makes a browser ask first (CORS preflight) before another site's page
            // could post here; a form's type could not.
            if (type.rfind(kJson, 0) != 0)
                return fail(res, 415, "send the command with Content-Type: application/json");
            auto s = pipeline_.state();
            const bool motor = !s || s->hasFocusControl;  // before a state, the pipeline decides
            const web::ControlReply r = web::runControl(req.body, pipeline_, motor);
            res.status = r.httpStatus;
            res.set_content(r.body, kJson);
        });
        server_.Get("/stream.mjpg",
                    [this](const httplib::Request&, httplib::Response& res) { stream(res); });
        server_.Get("/events",
                    [this](const httplib::Request&, httplib::Response& res) { events(res); });
    }

    static void fail(httplib::Response& res, int status, const std::string& message) {
        res.status = status;
        res.set_content(errorJson(message), kJson);
    }
    static void noFrame(httplib::Response& res) { fail(res, 503, "no frame analysed yet"); }

    // Takes a client slot of @p count below @p limit; false when all are taken.
    static bool takeSlot(std::atomic<int>& count, int limit) {
        if (count.fetch_add(1) < limit) return true;
        count.fetch_sub(1);
        return false;
    }

    void stream(httplib::Response& res) {
        if (!takeSlot(hub_.streamClients, options_.maxStreams))
            return fail(res, 503,
                        "all " + std::to_string(options_.maxStreams) +
                            " stream slots are in use; close another view");
        auto last = std::make_shared<std::optional<uint64_t>>();
        res.set_content_provider(
            std::string("multipart/x-mixed-replace; boundary=") + kBoundary,
            [this, last](size_t, httplib::DataSink& sink) {
                auto snap = hub_.waitNewer(std::nullopt, *last, true, kPoll);
                if (hub_.stopping()) return false;
                if (!snap) return sink.is_writable();
                const web::EncodedFrame& f = *snap->jpeg;
                *last = f.frame;
                const std::string head = std::string("--") + kBoundary +
                                         "\r\nContent-Type: image/jpeg\r\nContent-Length: " +
                                         std::to_string(f.jpeg.size()) +
                                         "\r\nX-Frame: " + std::to_string(f.frame) + "\r\n\r\n";
                return sink.write(head.data(), head.size()) &&
                       sink.write(f.jpeg.data(), f.jpeg.size()) && sink.write("\r\n", 2);
            },
            [this](bool) { hub_.streamClients.fetch_sub(1); });
    }

    void events(httplib::Response& res) {
        if (!takeSlot(hub_.eventClients, options_.maxEventClients))
            return fail(res, 503,
                        "all " + std::to_string(options_.maxEventClients) +
                            " event slots are in use; close another view");
        struct Client {
            std::optional<uint64_t> last;
            std::chrono::steady_clock::time_point sent{}, wrote = std::chrono::steady_clock::now();
        };
        auto c = std::make_shared<Client>();
        const auto interval = std::chrono::duration_cast<std::chrono::microseconds>(
            std::chrono::duration<double>(1.0 / options_.maxEventsPerS));
        res.set_content_provider(
            "text/event-stream",
            [this, c, interval](size_t, httplib::DataSink& sink) {
                using Clock = std::chrono::steady_clock;
                // At most maxEventsPerS: wait out the interval, then send the newest state.
                const auto due = c->sent + interval;
                if (const auto now = Clock::now(); now < due)
                    hub_.sleepFor(std::chrono::duration_cast<std::chrono::milliseconds>(due - now) +
                                  std::chrono::milliseconds(1));
                auto snap = hub_.waitNewer(c->last, std::nullopt, false, kPoll);
                if (hub_.stopping()) return false;
                const auto now = Clock::now();
                if (!snap) {
                    if (now - c->wrote < kPingInterval) return sink.is_writable();
                    c->wrote = now;
                    return sink.write(": ping\n\n", 9);
                }
                c->last = snap->state->frame;
                c->sent = c->wrote = now;
                // The shared JSON goes out as it is: a copy per client per event, of varying
                // size, fragmented the request threads' heaps and grew RSS over hours.
                const std::string head = "id: " + std::to_string(snap->state->frame) + "\ndata: ";
                const std::string own = snap->json ? std::string() : liveStateJson(*snap->state);
                const std::string& json = snap->json ? *snap->json : own;
                return sink.write(head.data(), head.size()) &&
                       sink.write(json.data(), json.size()) && sink.write("\n\n", 2);
            },
            [this](bool) { hub_.eventClients.fetch_sub(1); });
    }

    LiveView& pipeline_;
    const WebOptions options_;
    const ListenAddress address_;
    std::string token_;
    int port_ = 0;
    web::FrameHub hub_;
    std::map<std::string, std::string> methods_;  ///< known path → its method
    const std::string pagePolicy_ = pagePolicy();
    HttpServer server_;
    // Every stream and event client holds a worker; a few more answer /state and the page
    // while all stream slots are taken.
    Connections connections_{
        static_cast<size_t>(options_.maxStreams + options_.maxEventClients + 8),
        options_.maxBodyBytes, [this](httplib::Stream& s, bool last, bool& closed) {
            return server_.answer(s, last, closed);
        }};
    std::thread listener_;
};

}  // namespace

Result<ListenAddress> parseListenAddress(std::string_view text) {
    const auto usage = [&](const std::string& why) {
        return makeError(ErrorKind::Usage, "--listen " + std::string(text) + ": " + why +
                                               "; give ADDR:PORT, e.g. --listen 127.0.0.1:8080 "
                                               "or --listen 0.0.0.0:8080");
    };
    const size_t colon = text.rfind(':');
    if (colon == std::string_view::npos || colon + 1 == text.size()) return usage("no port");
    std::string host(text.substr(0, colon));
    const std::string portText(text.substr(colon + 1));
    if (portText.size() > 5 || portText.find_first_not_of("0123456789") != std::string::npos)
        return usage("the port is not a number from 0 to 65535");
    const int port = std::stoi(portText);
    if (port > 65535) return usage("the port is not a number from 0 to 65535");
    ListenAddress a;
    a.port = port;
    if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
        host = host.substr(1, host.size() - 2);
        in6_addr v6{};
        if (inet_pton(AF_INET6, host.c_str(), &v6) != 1) return usage("not an IPv6 address");
        a.loopback = IN6_IS_ADDR_LOOPBACK(&v6);
    } else if (host == "localhost") {
        host = "127.0.0.1";
        a.loopback = true;
    } else {
        in_addr v4{};
        if (inet_pton(AF_INET, host.c_str(), &v4) != 1)
            return usage("\"" + host + "\" is not an IPv4 address");
        a.loopback = (ntohl(v4.s_addr) >> 24) == 127;
    }
    a.host = host;
    return a;
}

std::string answerBytes(WebServer& server, std::string_view bytes) {
    return static_cast<WebServerImpl&>(server).answerBytes(bytes);
}

Result<std::unique_ptr<WebServer>> WebServer::start(LiveView& pipeline, const WebOptions& options) {
    auto address = parseListenAddress(options.listen);
    if (!address) return address.error();
    auto server = std::make_unique<WebServerImpl>(pipeline, options, *address);
    if (Status st = server->listen(); !st) return st.error();
    return std::unique_ptr<WebServer>(std::move(server));
}

}  // namespace infocus
