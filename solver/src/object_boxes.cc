// The objects' boxes, built when first asked for (object_boxes.h).
#include "object_boxes.h"

#include <utility>

namespace lixel::scheduling {

ObjectBoxes::ObjectBoxes(std::vector<Aabb> boxes) : boxes_(std::move(boxes)) {
    bounds_.reserve(boxes_.size());
    for (const Aabb& box : boxes_) bounds_.push_back(PolytopeBounds::OfBox(box));
    built_.resize(boxes_.size());
}

const ConvexPolytope& ObjectBoxes::operator[](std::size_t i) const {
    if (!built_[i])
        built_[i] = std::make_unique<ConvexPolytope>(ConvexPolytope::FromBox(boxes_[i]));
    return *built_[i];
}

}  // namespace lixel::scheduling
