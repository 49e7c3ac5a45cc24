// What bounds upload streams beyond each stream's own size limit (DESIGN §8): a byte budget
// all concurrent uploads share, and a watchdog that ends a stream that stops sending.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <thread>

namespace lixel::service {

class SharedBytes;

// One stream's part of a SharedBytes budget; given back when released or destroyed.
class SharedBytesLease {
public:
    SharedBytesLease() = default;
    SharedBytesLease(const SharedBytesLease&) = delete;
    SharedBytesLease& operator=(const SharedBytesLease&) = delete;
    ~SharedBytesLease() { Release(); }
    void Release();

private:
    friend class SharedBytes;
    SharedBytes* owner_ = nullptr;
    std::uint64_t bytes_ = 0;
};

// Bytes every upload stream together may hold (ServiceOptions::max_upload_bytes_in_flight).
class SharedBytes {
public:
    explicit SharedBytes(std::uint64_t capacity) : capacity_(capacity) {}
    // Takes `bytes` into `lease` (which must hold nothing), or false when the budget cannot
    // hold them now (nothing taken).
    bool Take(std::uint64_t bytes, SharedBytesLease* lease);
    std::uint64_t held() const;
    std::uint64_t capacity() const noexcept { return capacity_; }

private:
    friend class SharedBytesLease;
    void Give(std::uint64_t bytes);

    const std::uint64_t capacity_;
    mutable std::mutex mutex_;
    std::uint64_t held_ = 0;
};

// Streams waiting for their next message, each with a deadline; a thread calls a stream's
// `expire` once when its deadline passes first. The registry is locked while `expire` runs, so
// a stream that calls Arrived or Forget meanwhile waits and then learns it expired; the lock is
// recursive because gRPC may run a reactor's OnDone (which calls Forget) inside Finish.
class IdleStreams {
public:
    explicit IdleStreams(double idle_seconds);
    ~IdleStreams();
    IdleStreams(const IdleStreams&) = delete;
    IdleStreams& operator=(const IdleStreams&) = delete;

    double idle_seconds() const noexcept { return idle_seconds_; }
    // `stream` waits for a message from now on.
    void Waiting(const void* stream, std::function<void()> expire);
    // A message (or the end of the stream) arrived: false when the stream expired first.
    bool Arrived(const void* stream);
    // The stream is gone: never call its `expire` again.
    void Forget(const void* stream);

private:
    struct Entry {
        std::chrono::steady_clock::time_point deadline;
        std::function<void()> expire;
        bool expired = false;
    };
    void Watch();

    const double idle_seconds_;
    std::recursive_mutex mutex_;
    std::condition_variable_any wake_;
    bool stopping_ = false;
    std::map<const void*, Entry> waiting_;
    std::thread thread_;  // last: it uses everything above
};

}  // namespace lixel::service
