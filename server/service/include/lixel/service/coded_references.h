// The coded frames a server keeps so that a later Render may code an image as differences from
// what its client already holds (RenderRequest.encoding.reference_frames): each image's decoded
// values under its frame id, with the map and pass it belongs to. Bounded in bytes, least
// recently used first out; an id no longer held only costs a keyframe. Frame ids are 64 random
// bits (OpenSSL's RAND_bytes), so a client can name only frames it was sent.
#pragma once

#include <lixel/codec/coded_map.h>
#include <lixel/solver/types.h>

#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <vector>

namespace lixel::service {

// What an image must share with a reference to be coded against it: its map's matrix and size
// (bit for bit) and its kind (the wire's PassKind, corner depth apart).
struct ReferenceKey {
    Mat4 matrix = Mat4::Zero();
    int width = 0;
    int height = 0;
    int kind = 0;
    bool operator==(const ReferenceKey& o) const {
        return kind == o.kind && width == o.width && height == o.height &&
               (matrix.array() == o.matrix.array()).all();
    }
};

struct CodedReference {
    ReferenceKey key;
    std::shared_ptr<const codec::IntegerImage> values;
    int chain = 0;  // frames since its keyframe (0: it is one)
};

class CodedReferences {
  public:
    explicit CodedReferences(std::uint64_t capacity_bytes) : capacity_(capacity_bytes) {}

    // The first of `ids` that is held with `key`, or none.
    std::shared_ptr<const CodedReference> Find(const std::vector<std::uint64_t>& ids,
                                               const ReferenceKey& key);
    // Holds `reference` under its values' frame id, evicting the least recently used beyond the
    // capacity (one larger than the capacity is not held).
    void Put(std::shared_ptr<const CodedReference> reference);

    // Drops the frames `ids` (a session's frames its client no longer holds: a session keeps
    // only its last frame's references, so its memory stays flat). Ids not held are ignored.
    void Forget(const std::vector<std::uint64_t>& ids);

    std::uint64_t bytes() const;
    std::size_t size() const;

  private:
    using Order = std::list<std::uint64_t>;
    struct Held {
        std::shared_ptr<const CodedReference> reference;
        Order::iterator order;
    };
    const std::uint64_t capacity_;
    mutable std::mutex mutex_;
    std::unordered_map<std::uint64_t, Held> held_;
    Order order_;  // most recently used first
    std::uint64_t bytes_ = 0;
};

// A fresh frame id: 64 random bits, never 0.
std::uint64_t NewFrameId();

}  // namespace lixel::service
