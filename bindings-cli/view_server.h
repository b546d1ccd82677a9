// `wave view`'s server: cpp-httplib answers the requests, but a connection reaches one
// of its workers only once its request head (request line and headers) has arrived
// whole. Heads are collected on one thread by poll(), each within a deadline and a size,
// so clients that send their headers a byte at a time (slowloris) or not at all hold a
// socket for a few seconds, never a worker (docs/viewer.md, "Slow clients").
#pragma once

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <cstddef>

namespace wave::cli {

/// The limits of ViewServer (docs/viewer.md, "Slow clients").
struct ViewServerLimits {
    std::chrono::milliseconds head_time{5'000};   ///< a request head must arrive whole within this (from accept or the last answer)
    std::size_t head_bytes = 16 * 1024;            ///< … and within this many bytes (431 otherwise)
    std::size_t connections = 512;                 ///< open connections at most; the oldest waiting for a head goes first
    std::size_t workers = 8;                       ///< threads answering whole requests
    std::size_t requests_per_connection = 100;     ///< then the connection is closed (keep-alive)
    std::chrono::milliseconds write_stall{5'000};  ///< a reader that takes nothing for this long is dropped
};

/// An httplib::Server whose connections are served only once their head is whole (see
/// the file's comment). Bind it with bind_to_port / bind_to_any_port, then serve().
class ViewServer : public httplib::Server {
public:
    explicit ViewServer(ViewServerLimits limits = {}) : limits_(limits) {}

    /// Makes the bound socket ready (non-blocking, a full listen backlog): call it before
    /// telling clients the address. False without a bound socket.
    bool prepare();

    /// Serves until `stop` becomes true (checked every 200 ms; a signal handler may set
    /// it). False when the listening socket failed.
    bool serve(const std::atomic<bool>& stop);

    /// Closes the connection after the current answer: called from a handler (it runs on
    /// the worker serving the request) when it refuses the request, so that a client
    /// without the token never keeps a connection for pipelined requests.
    static void close_after_this_answer();

private:
    ViewServerLimits limits_;
    bool prepared_ = false;
};

}  // namespace wave::cli
