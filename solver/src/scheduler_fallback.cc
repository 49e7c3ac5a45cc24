// The fallback over the rays the plane maps leave uncovered, or the cube faces that hold them when
// the light lies among those rays (DESIGN §4.3), each with what it is kept for.
#include "scheduler_context.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lixel::scheduling {
namespace {

constexpr const char* kCubeFaceNames[kCubeFaces] = {"+x", "-x", "+y", "-y", "+z", "-z"};
// Longest side over shortest side allowed for a fallback or cube-face map.
constexpr int kMaxMapAspect = 16;

// Whether the maps accept every light ray through the needed polygon of plane of interest
// `plane` (to Subtract's sliver tolerance); false when that plane is no candidate, since nothing
// then vouches for the objects on it.
bool PlaneHeld(const Context& c, const std::vector<RayCone>& cones, int plane) {
    for (const Candidate& cand : c.candidates) {
        if (static_cast<int>(cand.index) != plane) continue;
        return SubtractAll(cand.polygon, cones).empty();
    }
    return false;
}

}  // namespace

// The visible regions' parts no map accepts: what the fallback (or cube faces) must cover. An
// object lying on a plane whose needed polygon the maps hold needs nothing more: its visible
// points are points of that polygon (paper §2: every point of P in view images on P's map).
std::vector<UncoveredPiece> Uncovered(const Context& c, const std::vector<PlannedMap>& maps) {
    std::vector<RayCone> cones;
    cones.reserve(maps.size());
    for (const PlannedMap& m : maps) cones.push_back(LookupCone(m.map, m.lookup));
    std::vector<RayConeTests> cone_tests;
    cone_tests.reserve(cones.size());
    for (const RayCone& cone : cones) cone_tests.emplace_back(cone);
    std::vector<int> plane_held(c.request.planes.size(), -1);  // -1 unknown, 0 no, 1 yes
    std::vector<UncoveredPiece> out;
    for (const ViewRegion& v : c.view_regions) {
        c.poll();
        if (v.on_plane >= 0) {
            int& held = plane_held[v.on_plane];
            if (held < 0) held = PlaneHeld(c, cones, v.on_plane) ? 1 : 0;
            if (held == 1) continue;
        }
        // Most regions of a crowded view lie inside some map's cone: nothing to subtract.
        if (SubtractAllLeavesNothing(RegionBounds(c, v), cone_tests)) continue;
        for (ConvexPolytope& piece : SubtractAll(RegionOf(c, v), std::span(cone_tests))) {
            out.push_back({std::move(piece), v.object});
        }
    }
    return out;
}

namespace {

std::vector<Vec4> VerticesOf(const std::vector<UncoveredPiece>& pieces) {
    std::vector<Vec4> points;
    for (const UncoveredPiece& p : pieces) {
        for (const Vec3& v : p.piece.vertices()) points.push_back(Point(v));
    }
    return points;
}

// What the fallback or the cube faces are kept for, in words: the objects with visible parts
// whose light rays no plane map holds.
std::string KeptFor(const Context& c, const std::vector<UncoveredPiece>& uncovered) {
    std::vector<int> objects;
    for (const UncoveredPiece& p : uncovered) {
        if (std::find(objects.begin(), objects.end(), p.object) == objects.end()) {
            objects.push_back(p.object);
        }
    }
    if (objects.size() == 1 && objects[0] < 0) {
        return "kept for the scene bounds in view: the request names no objects, so any point "
               "in view may need it";
    }
    constexpr size_t kNamed = 4;
    std::string names;
    for (size_t k = 0; k < objects.size() && k < kNamed; ++k) {
        const SceneObject& o = c.request.objects[objects[k]];
        names += (names.empty() ? "" : ", ") +
                 (o.name.empty() ? "objects[" + std::to_string(objects[k]) + "]" : o.name);
    }
    if (objects.size() > kNamed) {
        names += " and " + std::to_string(objects.size() - kNamed) + " more";
    }
    return "kept for objects in view with light rays no plane map holds: " + names;
}

// The fallback: one conventional map over HULL(C_tot - ∪ C_plane) (paper §3), or, when the
// light sits among the uncovered rays, the cube faces that hold some of them.
const LightMap& MapOf(const LightMap& map) { return map; }
const LightMap& MapOf(const CubeFaceMap& face) { return face.map; }

// A budget-sized size whose sides also respect the GL maximum texture size.
MapSize BudgetSize(std::int64_t budget, int max_side) {
    const std::int64_t square = static_cast<std::int64_t>(max_side) * max_side;
    return MapSize{0, 0, std::min(budget, square)};
}

// Refits with a smaller budget until both sides are within `max_side` (an elongated map can
// exceed it even when its area fits).
template <class Fit>
auto FitWithinSide(Fit fit, std::int64_t budget, int max_side) -> decltype(fit(MapSize{})) {
    MapSize size = BudgetSize(budget, max_side);
    auto fitted = fit(size);
    for (int attempt = 0; attempt < 30 && fitted.ok(); ++attempt) {
        const LightMap& m = MapOf(*fitted);
        const int side = std::max(m.width, m.height);
        if (side <= max_side) break;
        const double shrink = static_cast<double>(max_side) / side;
        size.lixel_budget = std::max<std::int64_t>(
            1, static_cast<std::int64_t>(static_cast<double>(size.lixel_budget) * shrink * shrink *
                                         0.999));
        fitted = fit(size);
    }
    // A sliver of uncovered rays would get a map one lixel thick (16384 x 1 on a 256^2 budget):
    // useless across the sliver and too long for a silhouette map's corner ring. Cap the aspect
    // ratio; the lixels are then longer across the sliver than along it, which costs nothing.
    if (fitted.ok()) {
        const LightMap& m = MapOf(*fitted);
        const int long_side = std::max(m.width, m.height);
        const int short_side = std::min(m.width, m.height);
        if (long_side > kMaxMapAspect * short_side) {
            const std::int64_t area = std::min<std::int64_t>(
                budget, static_cast<std::int64_t>(max_side) * max_side / kMaxMapAspect);
            const int s = std::max(1, static_cast<int>(std::sqrt(
                                          static_cast<double>(area) / kMaxMapAspect)));
            const int l = std::min(max_side, kMaxMapAspect * s);
            fitted = fit(m.width >= m.height ? MapSize{l, s, 0} : MapSize{s, l, 0});
        }
    }
    return fitted;
}

// FitWithinSide with room for a guard band of `guard` lixels: the band's lixels come out of the
// budget and its width out of the side, so the guarded map stays within both. A fit that keeps
// a side the limit cannot shrink (a map FitWithinSide leaves at the GL maximum) gets a narrower
// band, written back to `guard`.
template <class Fit>
auto FitWithGuard(Fit fit, std::int64_t budget, int max_side, int& guard)
    -> decltype(fit(MapSize{})) {
    std::int64_t interior = budget;
    auto fitted = FitWithinSide(fit, interior, max_side - 2 * guard);
    for (int attempt = 0; attempt < 16 && fitted.ok(); ++attempt) {
        const LightMap& m = MapOf(*fitted);
        const std::int64_t total =
            static_cast<std::int64_t>(m.width + 2 * guard) * (m.height + 2 * guard);
        if (total <= budget) break;
        // Sizes step by whole rows and columns: take one more of the short side each time.
        interior -= total - budget + std::min(m.width, m.height);
        if (interior < 1) {
            return Error{"lixel_budget", "too small for a map and its guard band (" +
                                             std::to_string(budget) + " lixels)"};
        }
        fitted = FitWithinSide(fit, interior, max_side - 2 * guard);
    }
    if (fitted.ok()) {
        const LightMap& m = MapOf(*fitted);
        guard = std::max(0, std::min(guard, (max_side - std::max(m.width, m.height)) / 2));
        if (static_cast<std::int64_t>(m.width + 2 * guard) * (m.height + 2 * guard) > budget) {
            return Error{"lixel_budget", "no map and guard band of " + std::to_string(guard) +
                                             " lixels fits " + std::to_string(budget) + " lixels"};
        }
    }
    return fitted;
}

// The figures plane maps report (map_diagnostics.h), for a fallback or cube face: at samples
// of the faces of the region it is kept for, where its own lookup takes them.
SolveDiagnostics DiagnoseHeld(const Context& c, const PlannedMap& m,
                              std::span<const Receiver> receivers) {
    std::vector<std::uint8_t> held(receivers.size());
    for (std::size_t i = 0; i < receivers.size(); ++i) {
        c.poll();
        held[i] = LookupAccepts(m, Point(receivers[i].point)) ? 1 : 0;
    }
    return DiagnoseMap(m.map, c.light, c.request.viewer, c.request.viewport, receivers, held);
}

// The fallback as one light frustum over `points` (the uncovered pieces' vertices), with the
// previous frame's size where frame coherence keeps it; false when no frustum fits.
bool AddFallbackMap(const Context& c, const std::vector<Vec4>& points, const std::string& kept_for,
                    const std::vector<Receiver>& receivers, std::int64_t budget, Plan& plan) {
    const int max_side = c.request.max_texture_size;
    int guard = GuardFor(budget, max_side);
    // FitFrustum at each size the guard band and coherence try: its basis (the cone's axis and
    // the image's turn) depends on the points alone, so it is found once.
    const Result<Mat4> basis = LightFrustumBasis(c.light, points);
    const auto fit = [&](const MapSize& size) -> Result<LightMap> {
        if (!basis) return basis.error();
        return FitImageRectangle(*basis, c.light, points, size);
    };
    auto fallback = FitWithGuard(fit, budget, max_side, guard);
    // Frame coherence: the previous fallback's size, when it fits what is left of the budget,
    // holds at least 1 - waste_bound of the map that budget fits, and the map fitted to its
    // own lixels is stretched onto it by at least sqrt(1 - waste_bound) along each axis: its
    // lixels grow by at most 1 / sqrt(1 - waste) along one axis (1.15 at the default 0.25)
    // and shrink along the other, as the fallback's rays turn with the view.
    const PreviousMap* previous = PreviousOf(c.request, MapRole::kFallback);
    const std::int64_t previous_area =
        previous != nullptr ? static_cast<std::int64_t>(previous->width) * previous->height
                            : 0;
    if (fallback.ok() && previous_area > 0 && previous_area <= budget &&
        std::max(previous->width, previous->height) <= max_side) {
        int kept_guard = GuardFor(previous_area, max_side);
        auto natural = FitWithGuard(fit, previous_area, max_side, kept_guard);
        const std::int64_t w = natural.ok() ? natural->width + 2 * kept_guard : 0;
        const std::int64_t h = natural.ok() ? natural->height + 2 * kept_guard : 0;
        const double least = std::sqrt(1.0 - c.request.coherence->waste_bound);
        // And the kept size holds at least 1 - waste_bound of the lixels the whole budget
        // would fit: as the plane maps give lixels back, the fallback grows into them.
        const double full = static_cast<double>(fallback->width + 2 * guard) *
                            static_cast<double>(fallback->height + 2 * guard);
        if (natural.ok() && previous->width >= least * static_cast<double>(w) &&
            previous->height >= least * static_cast<double>(h) &&
            static_cast<double>(previous_area) >=
                (1.0 - c.request.coherence->waste_bound) * full) {
            auto kept = fit(MapSize{previous->width - 2 * kept_guard,
                                    previous->height - 2 * kept_guard, 0});
            if (kept.ok()) {
                fallback = std::move(kept);
                guard = kept_guard;
            }
        }
    }
    if (fallback.ok()) {
        PlannedMap m;
        m.role = MapRole::kFallback;
        m.name = "fallback";
        m.kept_for = kept_for;
        m.map = *fallback;
        AddGuardBand(m.map, guard);
        m.lookup.guard = guard;
        m.passes = {Pass::kDepth};
        m.needed_image = ImageHull(m.map.matrix, points);
        m.scale = 0.0;
        m.lixels = static_cast<std::int64_t>(m.map.width) * m.map.height;
        RefitDepth(c, m, points);
        m.diagnostics = DiagnoseHeld(c, m, receivers);
        plan.maps.push_back(std::move(m));
        plan.left_out.push_back({"cube faces", "not needed: one frustum holds the fallback's "
                                               "rays (the light is outside them)"});
        return true;
    }
    return false;
}

// The cube faces whose pyramids meet an uncovered piece, each cropped to the rays it holds,
// sharing `budget` by the area of their rectangles.
Result<bool> AddCubeFaces(const Context& c, const std::vector<UncoveredPiece>& uncovered,
                          const std::string& kept_for, const std::vector<Receiver>& receivers,
                          std::int64_t budget, Plan& plan) {
    const int max_side = c.request.max_texture_size;
    // More than a hemisphere of rays: keep the faces whose pyramids meet an uncovered piece,
    // each cropped to the rays it holds.
    std::vector<ConvexPolytope> regions;
    regions.reserve(uncovered.size());
    for (const UncoveredPiece& piece : uncovered) regions.push_back(piece.piece);
    std::vector<int> kept;
    std::vector<double> areas;  // of each kept face's rectangle, tangent units^2
    for (int face = 0; face < kCubeFaces; ++face) {
        auto probe = FitCubeFaceCropped(c.light, face, regions, MapSize{1, 1, 0});
        if (probe.ok() && probe->holds_points) {
            kept.push_back(face);
            areas.push_back((probe->tangent_max - probe->tangent_min).prod());
        } else {
            plan.left_out.push_back({std::string("cube ") + kCubeFaceNames[face],
                                     "holds no needed rays"});
        }
    }
    if (kept.empty()) return true;
    const std::int64_t faces = static_cast<std::int64_t>(kept.size());
    if (budget < faces) {
        return Error{"lixel_budget", "too small for the " + std::to_string(kept.size()) +
                                         " cube faces the light inside the scene needs"};
    }
    // Shared by the area each face's rectangle takes in its own projective image (tangent
    // units), so every face gets the same lixels per unit of image and a lixel subtends the same
    // tangent extent on both sides of a seam. One lixel each, then the rest by cumulative
    // floors, which sum to the budget exactly.
    double total_area = 0.0;
    for (double a : areas) total_area += a;
    const std::int64_t spare = budget - faces;
    std::vector<std::int64_t> shares(kept.size());
    double cumulative = 0.0;
    std::int64_t given = 0;
    for (size_t k = 0; k < kept.size(); ++k) {
        cumulative += areas[k];
        const std::int64_t upto =
            k + 1 == kept.size()
                ? spare
                : std::min(spare, static_cast<std::int64_t>(std::floor(
                                      static_cast<double>(spare) * (cumulative / total_area))));
        shares[k] = 1 + std::max<std::int64_t>(0, upto - given);
        given = std::max(given, upto);
    }
    for (size_t k = 0; k < kept.size(); ++k) {
        const int face = kept[k];
        int guard = GuardFor(shares[k], max_side);
        auto fitted = FitWithGuard(
            [&](const MapSize& size) { return FitCubeFaceCropped(c.light, face, regions, size); },
            shares[k], max_side, guard);
        if (!fitted) return fitted.error();
        PlannedMap m;
        m.role = MapRole::kCubeFace;
        m.cube_face = face;
        m.kept_for = kept_for;
        m.name = std::string("cube ") + kCubeFaceNames[face];
        m.map = fitted->map;
        AddGuardBand(m.map, guard);
        m.lookup.guard = guard;
        m.passes = {Pass::kDepth};
        m.needed_image = fitted->needed_image;
        for (Vec2& p : m.needed_image) p += Vec2(guard, guard);
        m.scale = 0.0;
        m.lixels = static_cast<std::int64_t>(m.map.width) * m.map.height;
        RefitDepth(c, m);
        m.diagnostics = DiagnoseHeld(c, m, receivers);
        plan.maps.push_back(std::move(m));
    }
    plan.left_out.push_back({"fallback", "replaced by cube faces: the light lies among the rays "
                                         "left to cover, more than one frustum can hold"});
    return true;
}

}  // namespace

Result<bool> AddFallback(const Context& c, const std::vector<UncoveredPiece>& uncovered,
                         std::int64_t budget, Plan& plan) {
    const std::vector<Vec4> points = VerticesOf(uncovered);
    const std::string kept_for = KeptFor(c, uncovered);
    std::vector<ConvexPolytope> pieces;
    pieces.reserve(uncovered.size());
    for (const UncoveredPiece& piece : uncovered) pieces.push_back(piece.piece);
    const std::vector<Receiver> receivers = RegionReceivers(pieces);
    if (!c.hull.light_inside && AddFallbackMap(c, points, kept_for, receivers, budget, plan)) {
        return true;
    }
    return AddCubeFaces(c, uncovered, kept_for, receivers, budget, plan);
}

}  // namespace lixel::scheduling
