// Uploaded scenes by content id, least recently used first out once the byte cap is reached.
// The server keeps no other per-client state (DESIGN §8), so a client that gets NOT_FOUND after
// an eviction or on another instance simply uploads again.
#pragma once

#include <lixel/service/proto_convert.h>

#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>

namespace lixel::service {

class SceneCache {
public:
    explicit SceneCache(std::uint64_t byte_cap) : byte_cap_(byte_cap) {}

    // The scene, marked most recently used; null when absent. Held scenes stay valid for their
    // holders after eviction.
    std::shared_ptr<const SceneRecord> Get(const std::string& id);

    // Inserts (or refreshes) a scene; evicts least recently used ones to stay under the cap. A
    // scene larger than the cap on its own is refused (false).
    bool Put(const std::string& id, std::shared_ptr<const SceneRecord> scene);

    bool Contains(const std::string& id) const;
    std::uint64_t bytes() const;
    std::size_t size() const;
    std::uint64_t evictions() const;

private:
    struct Entry {
        std::string id;
        std::shared_ptr<const SceneRecord> scene;
    };
    void EvictLocked();

    const std::uint64_t byte_cap_;
    mutable std::mutex mutex_;
    std::list<Entry> lru_;  // front: most recent
    std::unordered_map<std::string, std::list<Entry>::iterator> index_;
    std::uint64_t bytes_ = 0;
    std::uint64_t evictions_ = 0;
};

// "sha256:<hex>" of a format tag, the header's planes of interest (serialized) and the content:
// equal uploads get equal ids anywhere, and the same meshes with other planes are another scene.
std::string ContentId(int format, const std::string& content, const std::string& planes = {});

}  // namespace lixel::service
