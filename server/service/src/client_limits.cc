// Per-client admission: counts under one mutex, entries dropped when a client holds nothing.
#include <lixel/service/client_limits.h>

#include <string_view>

namespace lixel::service {

namespace {

grpc::Status Exhausted(const char* limit, const std::string& what, std::uint64_t max) {
    return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                        std::string(limit) + ": " + what + ", over the limit of " +
                            std::to_string(max) + " per client; retry later");
}

}  // namespace

ClientLease& ClientLease::operator=(ClientLease&& other) noexcept {
    if (this != &other) {
        Release();
        limits_ = other.limits_;
        identity_ = std::move(other.identity_);
        bytes_ = other.bytes_;
        other.limits_ = nullptr;
        other.bytes_ = 0;
    }
    return *this;
}

grpc::Status ClientLease::Grow(std::uint64_t bytes, const char* what) {
    if (limits_ == nullptr) return grpc::Status::OK;
    grpc::Status status = limits_->Grow(identity_, bytes, what);
    if (status.ok()) bytes_ += bytes;
    return status;
}

void ClientLease::Release() {
    if (limits_ == nullptr) return;
    limits_->Release(identity_, bytes_);
    limits_ = nullptr;
    bytes_ = 0;
}

grpc::Status ClientLimits::Acquire(const std::string& identity, std::uint64_t request_bytes,
                                   ClientLease* lease) {
    lease->Release();
    std::lock_guard lock(mutex_);
    Usage& usage = usage_[identity];
    if (max_calls_ != 0 && usage.calls + 1 > max_calls_) {
        const std::uint64_t calls = usage.calls;
        if (usage.calls == 0) usage_.erase(identity);
        return Exhausted("max_calls_per_client", std::to_string(calls) + " calls already in flight",
                         max_calls_);
    }
    if (max_bytes_ != 0 && usage.bytes + request_bytes > max_bytes_) {
        const std::uint64_t held = usage.bytes;
        if (usage.calls == 0) usage_.erase(identity);
        return Exhausted("max_bytes_in_flight_per_client",
                         std::to_string(request_bytes) + " request bytes on top of " +
                             std::to_string(held) + " in flight",
                         max_bytes_);
    }
    ++usage.calls;
    usage.bytes += request_bytes;
    lease->limits_ = this;
    lease->identity_ = identity;
    lease->bytes_ = request_bytes;
    return grpc::Status::OK;
}

grpc::Status ClientLimits::Grow(const std::string& identity, std::uint64_t bytes,
                                const char* what) {
    std::lock_guard lock(mutex_);
    Usage& usage = usage_[identity];  // present: the lease holds a call
    if (max_bytes_ != 0 && usage.bytes + bytes > max_bytes_) {
        return Exhausted("max_bytes_in_flight_per_client",
                         std::to_string(bytes) + " " + what + " bytes on top of " +
                             std::to_string(usage.bytes) + " in flight",
                         max_bytes_);
    }
    usage.bytes += bytes;
    return grpc::Status::OK;
}

void ClientLimits::Release(const std::string& identity, std::uint64_t bytes) {
    std::lock_guard lock(mutex_);
    const auto it = usage_.find(identity);
    if (it == usage_.end()) return;
    it->second.calls -= it->second.calls > 0 ? 1 : 0;
    it->second.bytes -= std::min(bytes, it->second.bytes);
    if (it->second.calls == 0) usage_.erase(it);
}

std::uint64_t ClientLimits::calls(const std::string& identity) const {
    std::lock_guard lock(mutex_);
    const auto it = usage_.find(identity);
    return it == usage_.end() ? 0 : it->second.calls;
}

std::uint64_t ClientLimits::bytes(const std::string& identity) const {
    std::lock_guard lock(mutex_);
    const auto it = usage_.find(identity);
    return it == usage_.end() ? 0 : it->second.bytes;
}

std::size_t ClientLimits::clients() const {
    std::lock_guard lock(mutex_);
    return usage_.size();
}

std::string ClientLimits::PeerHost(const std::string& peer) {
    const std::string_view p = peer;
    const auto colon = p.rfind(':');
    const auto scheme = p.find(':');
    // "unix:/path" and the like have no port: the whole string is the identity.
    if (colon == std::string_view::npos || colon == scheme) return peer;
    return std::string(p.substr(0, colon));
}

}  // namespace lixel::service
