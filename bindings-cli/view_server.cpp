// `wave view`'s server (view_server.h): heads collected by poll() on one thread, whole
// requests answered by httplib on a few workers.
#include "view_server.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace wave::cli {
namespace {

using Clock = std::chrono::steady_clock;

thread_local bool close_after = false;  // set by a handler refusing the request it answers

// A client connection: its socket, the bytes read and not yet answered, when its next
// head is due, and how many requests it has had.
struct Connection {
    int fd = -1;
    std::string bytes;
    Clock::time_point due;
    std::size_t requests = 0;
};

bool head_is_whole(const std::string& bytes) { return bytes.find("\r\n\r\n") != std::string::npos; }

void drop(int fd) {
    ::shutdown(fd, SHUT_RDWR);
    ::close(fd);
}

// A last short answer to a connection about to be dropped: never waits (best effort).
void answer_and_drop(int fd, const char* status) {
    const std::string text = std::string("HTTP/1.1 ") + status + "\r\nConnection: close\r\nContent-Length: 0\r\n\r\n";
    (void)!::send(fd, text.data(), text.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    drop(fd);
}

void address_of(int fd, bool peer, std::string& ip, int& port) {
    sockaddr_storage a{};
    socklen_t length = sizeof a;
    const int rc = peer ? ::getpeername(fd, reinterpret_cast<sockaddr*>(&a), &length)
                        : ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &length);
    ip.clear();
    port = 0;
    if (rc != 0) return;
    char text[INET6_ADDRSTRLEN] = {};
    if (a.ss_family == AF_INET) {
        const auto* v4 = reinterpret_cast<const sockaddr_in*>(&a);
        if (::inet_ntop(AF_INET, &v4->sin_addr, text, sizeof text)) ip = text;
        port = ntohs(v4->sin_port);
    } else if (a.ss_family == AF_INET6) {
        const auto* v6 = reinterpret_cast<const sockaddr_in6*>(&a);
        if (::inet_ntop(AF_INET6, &v6->sin6_addr, text, sizeof text)) ip = text;
        port = ntohs(v6->sin6_port);
    }
}

// The stream a worker answers one request through. Reads come from the head already
// collected, never from the socket: the viewer answers GET and HEAD only, whose bodies
// httplib does not read, so a worker never waits for a client's bytes. Writes go to the
// socket, waiting at most `stall` each time for the client to take some.
class HeadStream final : public httplib::Stream {
public:
    HeadStream(int fd, std::string bytes, std::chrono::milliseconds stall) : fd_(fd), bytes_(std::move(bytes)), stall_(stall) {}

    bool is_readable() const override { return at_ < bytes_.size(); }
    bool is_writable() const override {
        pollfd p{fd_, POLLOUT, 0};
        return ::poll(&p, 1, static_cast<int>(stall_.count())) > 0 && (p.revents & (POLLERR | POLLHUP | POLLNVAL)) == 0;
    }
    ssize_t read(char* ptr, size_t size) override {
        const std::size_t n = std::min(size, bytes_.size() - at_);
        if (n == 0) return -1;
        std::memcpy(ptr, bytes_.data() + at_, n);
        at_ += n;
        return static_cast<ssize_t>(n);
    }
    ssize_t write(const char* ptr, size_t size) override {
        for (;;) {
            const ssize_t n = ::send(fd_, ptr, size, MSG_NOSIGNAL | MSG_DONTWAIT);
            if (n >= 0) return n;
            if (errno == EINTR) continue;
            if ((errno != EAGAIN && errno != EWOULDBLOCK) || !is_writable()) return -1;
        }
    }
    void get_remote_ip_and_port(std::string& ip, int& port) const override { address_of(fd_, true, ip, port); }
    void get_local_ip_and_port(std::string& ip, int& port) const override { address_of(fd_, false, ip, port); }
    socket_t socket() const override { return fd_; }

    std::string rest() const { return bytes_.substr(at_); }  // a pipelined next request's first bytes

private:
    int fd_;
    std::string bytes_;
    std::size_t at_ = 0;
    std::chrono::milliseconds stall_;
};

}  // namespace

void ViewServer::close_after_this_answer() { close_after = true; }

bool ViewServer::prepare() {
    const int listener = svr_sock_;
    if (listener == INVALID_SOCKET) return false;
    if (prepared_) return true;
    const int flags = ::fcntl(listener, F_GETFL, 0);
    if (flags < 0 || ::fcntl(listener, F_SETFL, flags | O_NONBLOCK) != 0) return false;
    // httplib listens with a backlog of 5: a page opening more connections at once than
    // the loop accepts between two polls would wait a second for its SYN to be resent.
    prepared_ = ::listen(listener, SOMAXCONN) == 0;
    return prepared_;
}

bool ViewServer::serve(const std::atomic<bool>& stop) {
    if (!prepare()) return false;
    const int listener = svr_sock_;
    int wake[2] = {-1, -1};  // workers hand kept-alive connections back through it
    if (::pipe2(wake, O_NONBLOCK | O_CLOEXEC) != 0) return false;
    // The Keep-Alive header httplib writes says what this server does.
    set_keep_alive_max_count(limits_.requests_per_connection);
    set_keep_alive_timeout(std::max<time_t>(1, static_cast<time_t>(limits_.head_time.count() / 1000)));

    std::mutex mutex;
    std::condition_variable wanted;
    std::deque<Connection> ready;      // heads whole, waiting for a worker
    std::vector<Connection> returned;  // answered and kept alive: their next head is collected again
    bool quitting = false;
    std::atomic<std::size_t> open{0};

    const auto work = [&] {
        for (;;) {
            Connection c;
            {
                std::unique_lock lock(mutex);
                wanted.wait(lock, [&] { return quitting || !ready.empty(); });
                if (quitting) return;
                c = std::move(ready.front());
                ready.pop_front();
            }
            close_after = false;
            ++c.requests;
            const bool last = c.requests >= limits_.requests_per_connection;
            HeadStream stream(c.fd, std::move(c.bytes), limits_.write_stall);
            bool closed = false;
            const bool ok = process_request(stream, last, closed, nullptr);
            if (!ok || closed || last || close_after || stop) {
                drop(c.fd);
                --open;
                continue;
            }
            c.bytes = stream.rest();
            {
                std::lock_guard lock(mutex);
                returned.push_back(std::move(c));
            }
            const char byte = 1;
            (void)!::write(wake[1], &byte, 1);
        }
    };
    std::vector<std::thread> workers;
    for (std::size_t i = 0; i < std::max<std::size_t>(1, limits_.workers); ++i) workers.emplace_back(work);

    std::vector<Connection> collecting;  // waiting for their head
    const auto hand_over = [&](Connection& c) {
        std::lock_guard lock(mutex);
        ready.push_back(std::move(c));
        wanted.notify_one();
    };
    bool ok = true;
    std::vector<pollfd> fds;
    char buffer[4096];
    while (!stop) {
        {
            std::vector<Connection> back;
            {
                std::lock_guard lock(mutex);
                back.swap(returned);
            }
            for (Connection& c : back) {
                c.due = Clock::now() + limits_.head_time;
                if (head_is_whole(c.bytes))
                    hand_over(c);  // already pipelined
                else
                    collecting.push_back(std::move(c));
            }
        }
        fds.assign({{listener, POLLIN, 0}, {wake[0], POLLIN, 0}});
        auto next = Clock::now() + std::chrono::milliseconds(200);
        for (const Connection& c : collecting) {
            fds.push_back({c.fd, POLLIN, 0});
            next = std::min(next, c.due);
        }
        const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(next - Clock::now()).count();
        if (::poll(fds.data(), fds.size(), static_cast<int>(std::clamp<long long>(wait, 0, 200))) < 0 && errno != EINTR) {
            ok = false;
            break;
        }
        const auto now = Clock::now();
        if (fds[1].revents & POLLIN)
            while (::read(wake[0], buffer, sizeof buffer) > 0) {
            }
        // What came: whole heads go to the workers; late or oversized ones are dropped.
        std::vector<Connection> still;
        for (std::size_t i = 0; i < collecting.size(); ++i) {
            Connection& c = collecting[i];
            bool gone = false;
            if (fds[i + 2].revents & (POLLIN | POLLHUP | POLLERR)) {
                const ssize_t n = ::recv(c.fd, buffer, sizeof buffer, MSG_DONTWAIT);
                if (n > 0)
                    c.bytes.append(buffer, static_cast<std::size_t>(n));
                else if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR))
                    gone = true;
            }
            if (!gone && head_is_whole(c.bytes)) {
                hand_over(c);
                continue;
            }
            if (gone) {
                drop(c.fd);
            } else if (c.bytes.size() > limits_.head_bytes) {
                answer_and_drop(c.fd, "431 Request Header Fields Too Large");
            } else if (now >= c.due) {
                if (c.bytes.empty())
                    drop(c.fd);  // an idle connection
                else
                    answer_and_drop(c.fd, "408 Request Timeout");
            } else {
                still.push_back(std::move(c));
                continue;
            }
            --open;
        }
        collecting.swap(still);
        if (fds[0].revents & (POLLERR | POLLNVAL)) {
            ok = false;
            break;
        }
        if (fds[0].revents & POLLIN)
            for (;;) {
                const int fd = ::accept4(listener, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
                if (fd < 0) break;  // none left (EAGAIN), or a transient error: poll() again
                if (open >= limits_.connections) {
                    // Full: the connection that has waited longest for its head goes.
                    const auto oldest = std::min_element(collecting.begin(), collecting.end(),
                                                         [](const Connection& a, const Connection& b) { return a.due < b.due; });
                    if (oldest == collecting.end()) {
                        drop(fd);  // every connection is being answered
                        continue;
                    }
                    drop(oldest->fd);
                    collecting.erase(oldest);
                    --open;
                }
                collecting.push_back({fd, {}, now + limits_.head_time, 0});
                ++open;
            }
    }

    {
        std::lock_guard lock(mutex);
        quitting = true;
    }
    wanted.notify_all();
    // Answers being written stop at their next chunk (httplib checks svr_sock_).
    ::close(svr_sock_.exchange(INVALID_SOCKET));
    for (std::thread& t : workers) t.join();
    for (const Connection& c : collecting) drop(c.fd);
    for (const Connection& c : ready) drop(c.fd);
    for (const Connection& c : returned) drop(c.fd);
    ::close(wake[0]);
    ::close(wake[1]);
    return ok;
}

}  // namespace wave::cli
