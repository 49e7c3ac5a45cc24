// Limits per client (issue 8, access): concurrent calls and bytes in flight, keyed by the caller's
// identity. A call holds a ClientLease from admission until its reactor is done, whatever the
// outcome (OK, error or cancel), so a client's share is given back on every path.
#pragma once

#include <grpcpp/grpcpp.h>

#include <cstdint>
#include <map>
#include <mutex>
#include <string>

namespace lixel::service {

class ClientLimits;

// One admitted call's share. Movable; gives its share back when released or destroyed.
class ClientLease {
  public:
    ClientLease() = default;
    ClientLease(ClientLease&& other) noexcept { *this = std::move(other); }
    ClientLease& operator=(ClientLease&& other) noexcept;
    ClientLease(const ClientLease&) = delete;
    ClientLease& operator=(const ClientLease&) = delete;
    ~ClientLease() { Release(); }

    // Adds `bytes` (an upload once its header announced them, a response once produced; `what`
    // names them in the refusal) to the call's share; RESOURCE_EXHAUSTED naming
    // max_bytes_in_flight_per_client when the client would go over it (the share is unchanged).
    grpc::Status Grow(std::uint64_t bytes, const char* what = "response");
    void Release();
    bool held() const noexcept { return limits_ != nullptr; }

  private:
    friend class ClientLimits;
    ClientLimits* limits_ = nullptr;
    std::string identity_;
    std::uint64_t bytes_ = 0;
};

class ClientLimits {
  public:
    // 0 means no limit.
    ClientLimits(std::uint64_t max_calls, std::uint64_t max_bytes)
        : max_calls_(max_calls), max_bytes_(max_bytes) {}

    // Admits one call of `identity` carrying `request_bytes`, or RESOURCE_EXHAUSTED naming the
    // limit (max_calls_per_client or max_bytes_in_flight_per_client) it would exceed.
    grpc::Status Acquire(const std::string& identity, std::uint64_t request_bytes,
                         ClientLease* lease);

    // What `identity` holds now (0 and 0 when nothing); for tests and metrics.
    std::uint64_t calls(const std::string& identity) const;
    std::uint64_t bytes(const std::string& identity) const;
    // Identities holding at least one call.
    std::size_t clients() const;

    // The host part of a gRPC peer string: "ipv4:127.0.0.1:5000" -> "ipv4:127.0.0.1",
    // "ipv6:[::1]:5000" -> "ipv6:[::1]".
    static std::string PeerHost(const std::string& peer);

  private:
    friend class ClientLease;
    struct Usage {
        std::uint64_t calls = 0;
        std::uint64_t bytes = 0;
    };
    grpc::Status Grow(const std::string& identity, std::uint64_t bytes, const char* what);
    void Release(const std::string& identity, std::uint64_t bytes);

    const std::uint64_t max_calls_;
    const std::uint64_t max_bytes_;
    mutable std::mutex mutex_;
    std::map<std::string, Usage> usage_;  // only identities with a call in flight
};

}  // namespace lixel::service
