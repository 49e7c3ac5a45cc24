// Shared upload bytes and the idle-stream watchdog (upload_guards.h).
#include <lixel/service/upload_guards.h>

#include <algorithm>
#include <vector>

namespace lixel::service {

void SharedBytesLease::Release() {
    if (owner_ != nullptr) owner_->Give(bytes_);
    owner_ = nullptr;
    bytes_ = 0;
}

bool SharedBytes::Take(std::uint64_t bytes, SharedBytesLease* lease) {
    std::lock_guard lock(mutex_);
    if (bytes > capacity_ - std::min(held_, capacity_)) return false;
    held_ += bytes;
    lease->owner_ = this;
    lease->bytes_ = bytes;
    return true;
}

std::uint64_t SharedBytes::held() const {
    std::lock_guard lock(mutex_);
    return held_;
}

void SharedBytes::Give(std::uint64_t bytes) {
    std::lock_guard lock(mutex_);
    held_ -= std::min(bytes, held_);
}

IdleStreams::IdleStreams(double idle_seconds)
    : idle_seconds_(idle_seconds), thread_([this] { Watch(); }) {}

IdleStreams::~IdleStreams() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void IdleStreams::Waiting(const void* stream, std::function<void()> expire) {
    std::lock_guard lock(mutex_);
    Entry& e = waiting_[stream];
    e.deadline = std::chrono::steady_clock::now() +
                 std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                     std::chrono::duration<double>(idle_seconds_));
    e.expire = std::move(expire);
    e.expired = false;
}

bool IdleStreams::Arrived(const void* stream) {
    std::lock_guard lock(mutex_);
    const auto it = waiting_.find(stream);
    if (it == waiting_.end()) return true;
    const bool expired = it->second.expired;
    waiting_.erase(it);
    return !expired;
}

void IdleStreams::Forget(const void* stream) {
    std::lock_guard lock(mutex_);
    waiting_.erase(stream);
}

void IdleStreams::Watch() {
    // A tenth of the timeout between looks (at most 100 ms): a stream ends within 10 % of it.
    const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(std::clamp(idle_seconds_ / 10.0, 0.001, 0.1)));
    std::unique_lock lock(mutex_);
    while (!stopping_) {
        wake_.wait_for(lock, period, [this] { return stopping_; });
        if (stopping_) break;
        const auto now = std::chrono::steady_clock::now();
        std::vector<const void*> due;
        for (const auto& [stream, entry] : waiting_) {
            if (!entry.expired && entry.deadline <= now) due.push_back(stream);
        }
        for (const void* stream : due) {
            const auto it = waiting_.find(stream);
            if (it == waiting_.end() || it->second.expired) continue;
            it->second.expired = true;
            std::function<void()> expire = it->second.expire;
            expire();  // may Forget this stream (and so erase `it`) before it returns
        }
    }
}

}  // namespace lixel::service
