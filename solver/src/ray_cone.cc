// Accepted cones of light maps and convex set differences against them.
#include <lixel/solver/polygon.h>
#include <lixel/solver/ray_cone.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace lixel {

namespace {

// Unit normal keeps plane . (x, 1) a distance, which ConvexPolytope's tolerances assume.
Vec4 NormalizedPlane(const RowVec4& row) {
    const Vec4 p = row.transpose();
    const double n = p.head<3>().norm();
    return n > 0.0 ? Vec4(p / n) : p;
}

// Twice the area of a planar polygon in 3D.
double TwiceArea(const std::vector<Vec3>& polygon) {
    Vec3 sum = Vec3::Zero();
    for (size_t i = 0; i < polygon.size(); ++i) {
        sum += polygon[i].cross(polygon[(i + 1) % polygon.size()]);
    }
    return sum.norm();
}

}  // namespace

RayCone AcceptedCone(const LightMap& map, const std::vector<Eigen::Vector3d>& half_planes) {
    return AcceptedCone(map, Eigen::Vector4d(0.0, 0.0, map.width, map.height), half_planes);
}

RayCone AcceptedCone(const LightMap& map, const Eigen::Vector4d& rectangle,
                     const std::vector<Eigen::Vector3d>& half_planes) {
    const RowVec4 r_x = map.matrix.row(0);
    const RowVec4 r_y = map.matrix.row(1);
    const RowVec4 r_w = map.matrix.row(3);
    RayCone cone;
    cone.planes = {NormalizedPlane(r_w),
                   NormalizedPlane(r_x - rectangle[0] * r_w),
                   NormalizedPlane(rectangle[2] * r_w - r_x),
                   NormalizedPlane(r_y - rectangle[1] * r_w),
                   NormalizedPlane(rectangle[3] * r_w - r_y)};
    for (const Eigen::Vector3d& l : half_planes) {
        cone.planes.push_back(NormalizedPlane(l.x() * r_x + l.y() * r_y + l.z() * r_w));
    }
    return cone;
}

RayConeTests::RayConeTests(const RayCone& cone) {
    inside.reserve(cone.planes.size());
    outside.reserve(cone.planes.size());
    for (const Vec4& plane : cone.planes) {
        inside.emplace_back(plane);
        outside.emplace_back(Vec4(-plane));
    }
}

namespace {

// What SubtractInto found: the region is its own only piece, whole, or its pieces were appended.
enum class Subtracted { kWhole, kPieces };

// Subtract, appended to `pieces`; kWhole (and nothing appended) where the result is `region`
// itself, whole: wholly outside one of the cone's planes before any other plane cut it.
Subtracted SubtractInto(const ConvexPolytope& region, const RayConeTests& cone,
                        std::vector<ConvexPolytope>& pieces) {
    const std::size_t first_piece = pieces.size();
    // `inside` stays the region itself until a plane cuts it (most regions lie wholly inside or
    // wholly outside a cone's planes), then a copy. Most pieces come out empty: clip a per-thread
    // scratch copy, whose storage assignment reuses, and copy only the pieces that remain.
    const ConvexPolytope* inside = &region;
    ConvexPolytope cut;
    thread_local ConvexPolytope outside;
    for (std::size_t k = 0; k < cone.inside.size(); ++k) {
        if (inside->empty()) break;
        const auto [within, beyond] = inside->Effects(cone.inside[k], cone.outside[k]);
        if (inside == &region && pieces.size() == first_piece && beyond == ClipEffect::kKeepsAll &&
            within == ClipEffect::kKeepsNothing) {
            return Subtracted::kWhole;  // the only piece, and nothing is left inside
        }
        switch (beyond) {
            case ClipEffect::kKeepsNothing:
                break;
            case ClipEffect::kKeepsAll:
                pieces.push_back(*inside);
                break;
            case ClipEffect::kCuts:
                outside = *inside;
                outside.Clip(cone.outside[k], beyond);
                if (!outside.empty()) pieces.push_back(outside);
                break;
        }
        // What lies inside the last plane is what the cone holds: nothing reads it.
        if (within == ClipEffect::kKeepsAll || k + 1 == cone.inside.size()) continue;
        if (inside == &region) {
            cut = region;
            inside = &cut;
        }
        cut.Clip(cone.inside[k], within);
    }
    return Subtracted::kPieces;
}

}  // namespace

std::vector<ConvexPolytope> Subtract(const ConvexPolytope& region, const RayConeTests& cone) {
    std::vector<ConvexPolytope> pieces;
    if (SubtractInto(region, cone, pieces) == Subtracted::kWhole) pieces.push_back(region);
    return pieces;
}

std::vector<ConvexPolytope> Subtract(const ConvexPolytope& region, const RayCone& cone) {
    return Subtract(region, RayConeTests(cone));
}

std::vector<std::vector<Vec3>> Subtract(const std::vector<Vec3>& polygon, const RayCone& cone) {
    std::vector<std::vector<Vec3>> pieces;
    if (polygon.size() < 3) return pieces;
    // Slivers below this share of the polygon's area are rounding, not uncovered receivers.
    const double min_area = 1e-9 * TwiceArea(polygon);
    std::vector<Vec3> inside = polygon;
    for (const Vec4& plane : cone.planes) {
        if (inside.size() < 3) break;
        std::vector<Vec3> outside = ClipPolygon(inside, -plane);
        if (outside.size() >= 3 && TwiceArea(outside) > min_area) pieces.push_back(outside);
        ClipPolygonInPlace(inside, plane);
    }
    return pieces;
}

namespace {

template <typename Piece, typename Cone>
std::vector<Piece> SubtractEach(const Piece& whole, std::span<const Cone> cones) {
    std::vector<Piece> remaining = {whole};
    for (const Cone& cone : cones) {
        if (remaining.empty()) break;
        std::vector<Piece> next;
        for (const Piece& piece : remaining) {
            for (Piece& rest : Subtract(piece, cone)) next.push_back(std::move(rest));
        }
        remaining = std::move(next);
    }
    return remaining;
}

// The same for polytopes, where a piece a cone leaves whole moves on without a copy.
std::vector<ConvexPolytope> SubtractEach(const ConvexPolytope& whole,
                                         std::span<const RayConeTests> cones) {
    std::vector<ConvexPolytope> remaining;
    bool first = true;  // `whole` itself, not yet copied into `remaining`
    std::vector<ConvexPolytope> next, pieces;
    for (const RayConeTests& cone : cones) {
        if (first) {
            if (SubtractInto(whole, cone, remaining) == Subtracted::kWhole) {
                remaining.push_back(whole);
            }
            first = false;
            continue;
        }
        if (remaining.empty()) break;
        next.clear();
        for (ConvexPolytope& piece : remaining) {
            pieces.clear();
            if (SubtractInto(piece, cone, pieces) == Subtracted::kWhole) {
                next.push_back(std::move(piece));
                continue;
            }
            for (ConvexPolytope& rest : pieces) next.push_back(std::move(rest));
        }
        std::swap(remaining, next);
    }
    if (first) remaining.push_back(whole);
    return remaining;
}

}  // namespace

std::vector<ConvexPolytope> SubtractAll(const ConvexPolytope& region,
                                        std::span<const RayCone> cones) {
    return SubtractEach(region, cones);
}

std::vector<ConvexPolytope> SubtractAll(const ConvexPolytope& region,
                                        std::span<const RayConeTests> cones) {
    return SubtractEach(region, cones);
}

std::vector<std::vector<Vec3>> SubtractAll(const std::vector<Vec3>& polygon,
                                           std::span<const RayCone> cones) {
    return SubtractEach(polygon, cones);
}

bool SubtractAllLeavesNothing(const PolytopeBounds& b, std::span<const RayConeTests> cones) {
    std::size_t clips = 0;  // the most planes the parts reaching the next cone are clipped by
    for (const RayConeTests& cone : cones) {
        if (clips > kKeepsNothingClips) return false;
        if (std::all_of(cone.outside.begin(), cone.outside.end(),
                        [&](const PlaneTest& t) { return b.KeepsNothingOf(t); })) {
            return true;
        }
        clips += cone.inside.size();
    }
    return false;
}

}  // namespace lixel
