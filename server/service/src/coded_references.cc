// The server's held coded frames.
#include <lixel/service/coded_references.h>
#include <openssl/rand.h>

#include <cstring>
#include <stdexcept>

namespace lixel::service {

namespace {

std::uint64_t BytesOf(const CodedReference& r) {
    return r.values ? r.values->values.size() * sizeof(std::uint32_t) + 256 : 256;
}

}  // namespace

std::shared_ptr<const CodedReference> CodedReferences::Find(const std::vector<std::uint64_t>& ids,
                                                            const ReferenceKey& key) {
    std::lock_guard lock(mutex_);
    for (std::uint64_t id : ids) {
        auto found = held_.find(id);
        if (found == held_.end() || !(found->second.reference->key == key)) continue;
        order_.splice(order_.begin(), order_, found->second.order);
        return found->second.reference;
    }
    return nullptr;
}

void CodedReferences::Put(std::shared_ptr<const CodedReference> reference) {
    if (!reference || !reference->values) return;
    const std::uint64_t bytes = BytesOf(*reference);
    if (bytes > capacity_) return;
    const std::uint64_t id = reference->values->frame_id;
    std::lock_guard lock(mutex_);
    if (auto old = held_.find(id); old != held_.end()) {
        bytes_ -= BytesOf(*old->second.reference);
        order_.erase(old->second.order);
        held_.erase(old);
    }
    while (bytes_ + bytes > capacity_ && !order_.empty()) {
        auto last = held_.find(order_.back());
        bytes_ -= BytesOf(*last->second.reference);
        held_.erase(last);
        order_.pop_back();
    }
    order_.push_front(id);
    held_.emplace(id, Held{std::move(reference), order_.begin()});
    bytes_ += bytes;
}

void CodedReferences::Forget(const std::vector<std::uint64_t>& ids) {
    std::lock_guard lock(mutex_);
    for (std::uint64_t id : ids) {
        const auto held = held_.find(id);
        if (held == held_.end()) continue;
        bytes_ -= BytesOf(*held->second.reference);
        order_.erase(held->second.order);
        held_.erase(held);
    }
}

std::uint64_t CodedReferences::bytes() const {
    std::lock_guard lock(mutex_);
    return bytes_;
}

std::size_t CodedReferences::size() const {
    std::lock_guard lock(mutex_);
    return held_.size();
}

std::uint64_t NewFrameId() {
    for (;;) {
        unsigned char random[8];
        if (RAND_bytes(random, sizeof random) != 1) throw std::runtime_error("RAND_bytes failed");
        std::uint64_t id = 0;
        std::memcpy(&id, random, sizeof id);
        if (id != 0) return id;
    }
}

}  // namespace lixel::service
