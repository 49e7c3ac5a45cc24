// LRU scene cache with a byte cap, and content ids.
#include <lixel/service/scene_cache.h>

#include <openssl/evp.h>

#include <cstdio>

namespace lixel::service {

std::shared_ptr<const SceneRecord> SceneCache::Get(const std::string& id) {
    std::lock_guard lock(mutex_);
    const auto it = index_.find(id);
    if (it == index_.end()) return nullptr;
    lru_.splice(lru_.begin(), lru_, it->second);
    return it->second->scene;
}

bool SceneCache::Put(const std::string& id, std::shared_ptr<const SceneRecord> scene) {
    if (scene == nullptr || scene->bytes > byte_cap_) return false;
    std::lock_guard lock(mutex_);
    if (const auto it = index_.find(id); it != index_.end()) {
        lru_.splice(lru_.begin(), lru_, it->second);
        return true;
    }
    bytes_ += scene->bytes;
    lru_.push_front(Entry{id, std::move(scene)});
    index_[id] = lru_.begin();
    EvictLocked();
    return true;
}

void SceneCache::EvictLocked() {
    while (bytes_ > byte_cap_ && lru_.size() > 1) {
        const Entry& last = lru_.back();
        bytes_ -= last.scene->bytes;
        index_.erase(last.id);
        lru_.pop_back();
        ++evictions_;
    }
}

bool SceneCache::Contains(const std::string& id) const {
    std::lock_guard lock(mutex_);
    return index_.contains(id);
}

std::uint64_t SceneCache::bytes() const {
    std::lock_guard lock(mutex_);
    return bytes_;
}

std::size_t SceneCache::size() const {
    std::lock_guard lock(mutex_);
    return lru_.size();
}

std::uint64_t SceneCache::evictions() const {
    std::lock_guard lock(mutex_);
    return evictions_;
}

std::string ContentId(int format, const std::string& content, const std::string& planes) {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    EVP_MD_CTX* ctx = EVP_MD_CTX_new();
    const unsigned char tag = static_cast<unsigned char>(format);
    EVP_DigestInit_ex(ctx, EVP_sha256(), nullptr);
    EVP_DigestUpdate(ctx, &tag, 1);
    // The planes' length first, so that no split of planes and content gives another's id.
    const std::uint64_t planes_size = planes.size();
    EVP_DigestUpdate(ctx, &planes_size, sizeof planes_size);
    EVP_DigestUpdate(ctx, planes.data(), planes.size());
    EVP_DigestUpdate(ctx, content.data(), content.size());
    EVP_DigestFinal_ex(ctx, digest, &length);
    EVP_MD_CTX_free(ctx);
    std::string id = "sha256:";
    char hex[3];
    for (unsigned int i = 0; i < length; ++i) {
        std::snprintf(hex, sizeof hex, "%02x", digest[i]);
        id += hex;
    }
    return id;
}

}  // namespace lixel::service
