// The objects' boxes, built when first asked for (object_boxes.h).
#include "object_boxes.h"

#include <utility>

namespace lixel::scheduling {

ObjectBoxes::ObjectBoxes(std::vector<Aabb> boxes) : boxes_(std::move(boxes)) {
    bounds_.reserve(boxes_.size());
    for (const Aabb& box : boxes_) bounds_.push_back(PolytopeBounds::OfBox(box));
    slots_.assign(boxes_.size(), kNotBuilt);
}

const ConvexPolytope& ObjectBoxes::operator[](std::size_t i) const {
    if (slots_[i] == kNotBuilt) {
        slots_[i] = static_cast<std::uint32_t>(built_.size());
        built_.push_back(ConvexPolytope::FromBox(boxes_[i]));
    }
    return built_[slots_[i]];
}

}  // namespace lixel::scheduling
