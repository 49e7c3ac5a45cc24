// The needed regions: each plane of interest's needed polygon (paper §3), the visible part of
// every object and the part some map must hold.
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "scheduler_context.h"

namespace lixel::scheduling {

// A box with at least `thickness` on every axis: a floor slab still has rays to cover.
Aabb Thickened(const Aabb& box, double thickness) {
    Aabb out = box;
    for (int a = 0; a < 3; ++a) {
        if (out.max(a) - out.min(a) < thickness) {
            const double mid = 0.5 * (out.max(a) + out.min(a));
            out.min(a) = mid - 0.5 * thickness;
            out.max(a) = mid + 0.5 * thickness;
        }
    }
    return out;
}

ConvexPolytope ClippedByAll(ConvexPolytope polytope, std::span<const PlaneTest> planes) {
    for (const PlaneTest& p : planes) {
        if (polytope.empty()) break;
        polytope.Clip(p);
    }
    return polytope;
}

// Two finite points on the line where two planes meet; false for (near) parallel planes.
bool MeetingLine(const Vec4& a, const Vec4& b, Vec4& p0, Vec4& p1) {
    const Vec3 direction = a.head<3>().cross(b.head<3>());
    if (!(direction.norm() > 1e-9)) return false;
    const Vec4 through = Cross4(a, b, Direction(direction));  // meets the plane through 0 ⟂ line
    if (!(std::abs(through.w()) > 0.0)) return false;
    const Vec3 point = through.head<3>() / through.w();
    p0 = Point(point);
    p1 = Point(point + direction.normalized() * std::max(1.0, point.norm()));
    return p0.allFinite() && p1.allFinite();
}

// The image of the world line ab in a light map, as (a, b, c) on lixel (x, y, 1), oriented so
// `inside` is on its non-negative side and scaled so the value is a distance in lixels.
Eigen::Vector3d ImageLine(const Mat4& m, const Vec4& a, const Vec4& b, const Vec3& inside) {
    const Vec4 ia = m * a;
    const Vec4 ib = m * b;
    const Vec4 it = m * Point(inside);
    Eigen::Vector3d line =
        Eigen::Vector3d(ia.x(), ia.y(), ia.w()).cross(Eigen::Vector3d(ib.x(), ib.y(), ib.w()));
    if (line.dot(Eigen::Vector3d(it.x(), it.y(), it.w())) * it.w() < 0.0) line = -line;
    const double n = line.head<2>().norm();
    return n > 0.0 ? Eigen::Vector3d(line / n) : line;
}

std::vector<Vec2> ImageHull(const Mat4& m, const std::vector<Vec4>& points) {
    std::vector<Vec2> image;
    for (const Vec4& p : points) {
        const Vec4 q = m * p;
        if (q.w() > 0.0) image.emplace_back(q.x() / q.w(), q.y() / q.w());
    }
    return ConvexHull2d(image);
}

std::vector<Vec4> Points(const std::vector<Vec3>& vertices) {
    std::vector<Vec4> out;
    out.reserve(vertices.size());
    for (const Vec3& v : vertices) out.push_back(Point(v));
    return out;
}

namespace {

// every view ray starts on the near plane, so it does when the whole near face of the frustum
// lies on its front side, by more than `margin` (world units). A plane the viewer faces can still
// cut the near face (a wall just past the eye of a wide view, or any plane across an
// orthographic viewer's near face), and rays that start behind it see what lies there.
bool HidesItsBackSide(const Mat4& viewer_inverse, const Vec4& plane, double margin) {
    for (const double x : {-1.0, 1.0}) {
        for (const double y : {-1.0, 1.0}) {
            const Vec4 corner = viewer_inverse * Vec4(x, y, kClipDepthNear, 1.0);
            if (!corner.allFinite() || corner.w() == 0.0) return false;
            if (!(plane.dot(corner / corner.w()) > margin)) return false;
        }
    }
    return true;
}

// The needed part of every plane of interest (paper §3): inside the view frustum and the scene,
// inside its polygon, on the positive side of every other infinite plane that is kept and hides
// its back side, lit side only.
void FindCandidates(Context& c) {
    const PlanRequest& r = c.request;
    std::vector<Vec4> planes(r.planes.size());
    for (size_t i = 0; i < r.planes.size(); ++i) {
        planes[i] = r.planes[i].plane / r.planes[i].plane.head<3>().norm();
    }
    const auto eye = EyePoint(r.viewer);
    // First every plane on its own: lit, facing the viewer, in view. `polygons[i]` is then its
    // part in view, empty when it is left out.
    std::vector<std::vector<Vec3>> polygons(r.planes.size());
    for (size_t i = 0; i < r.planes.size(); ++i) {
        const std::string name = PlaneName(r, i);
        const bool bounded = !r.planes[i].polygon.empty();
        const double lit = planes[i].dot(c.light);
        if (!(lit > 0.0)) {
            c.plane_left_out.push_back(
                {name,
                 "faces away from the light: the side of interest is in its own "
                 "shadow (P.l = " +
                     Format(lit) + ")"});
            continue;
        }
        if (eye.ok() && planes[i].dot(*eye) <= 0.0) {
            c.plane_left_out.push_back(
                {name, "seen from behind: the viewer is on the plane's back side"});
            continue;
        }
        std::vector<Vec3> polygon =
            bounded ? r.planes[i].polygon : PlaneBoxPolygon(planes[i], c.bounds);
        if (bounded) {
            for (int axis = 0; axis < 3; ++axis) {
                Vec4 lower = Vec4::Zero();
                lower(axis) = 1.0;
                lower.w() = -c.bounds.min(axis) + c.thickness;
                Vec4 upper = Vec4::Zero();
                upper(axis) = -1.0;
                upper.w() = c.bounds.max(axis) + c.thickness;
                ClipPolygonInPlace(polygon, lower);
                ClipPolygonInPlace(polygon, upper);
            }
        }
        for (const Vec4& f : c.frustum) ClipPolygonInPlace(polygon, f);
        if (polygon.size() < 3) {
            c.plane_left_out.push_back(
                {name, "not in view: it does not meet the view frustum inside the scene"});
            continue;
        }
        polygons[i] = std::move(polygon);
    }
    // Then each kept plane gives up what lies behind another kept infinite plane that hides its
    // back side from the viewer (paper §3: C_floor stops at the floor/wall line, where C_wall
    // starts). A plane left out is no such proof: one seen from behind hides its front side, not
    // its back, and the viewer is on its back side; one facing away from the light or not in
    // view has no map to take those rays over.
    const Mat4 viewer_inverse = r.viewer.inverse();
    std::vector<bool> occludes(r.planes.size(), false);
    for (size_t j = 0; j < r.planes.size(); ++j) {
        occludes[j] = !polygons[j].empty() && r.planes[j].polygon.empty() &&
                      HidesItsBackSide(viewer_inverse, planes[j], c.thickness);
    }
    for (size_t i = 0; i < r.planes.size(); ++i) {
        if (polygons[i].empty()) continue;
        Candidate cand;
        cand.index = i;
        cand.name = PlaneName(r, i);
        cand.plane = planes[i];
        cand.bounded = !r.planes[i].polygon.empty();
        std::vector<Vec3> polygon = polygons[i];
        std::string behind;
        std::vector<size_t> reached;  // planes the polygon only reaches: after those it crosses
        for (size_t j = 0; j < r.planes.size(); ++j) {
            if (j == i || !occludes[j]) continue;
            const std::vector<Vec3> clipped = ClipPolygon(polygon, planes[j]);
            if (clipped.size() < 3) {
                behind = PlaneName(r, j);
                polygon.clear();
                break;
            }
            // The meeting line bounds the lookup wherever the polygon reaches it, also when the
            // scene's box already ends the polygon there: without it, this plane's rectangle
            // takes the rays of the other plane's points just past the line, which its lixels
            // sample at a grazing angle.
            double reach = -std::numeric_limits<double>::infinity();
            for (const Vec3& v : polygon) {
                reach = std::max(reach, -(planes[j].head<3>().dot(v) + planes[j].w()));
            }
            // A plane the polygon crosses goes before one it only reaches: the first sets the
            // floor map's twist along its meeting line.
            if (reach > c.thickness) {
                cand.cut_by.push_back(j);
            } else if (reach > -c.thickness) {
                reached.push_back(j);
            }
            polygon = clipped;
        }
        cand.cut_by.insert(cand.cut_by.end(), reached.begin(), reached.end());
        if (polygon.empty()) {
            c.plane_left_out.push_back(
                {cand.name, "needed set empty: all of it in view lies behind " + behind});
            continue;
        }
        cand.polygon = polygon;
        c.candidates.push_back(std::move(cand));
    }
}

// The geometry a map can hold: every object's box inside the extent hull and the map's accepted
// cone (the extent hull alone when there are no objects). Its vertices bound the depth range

// Which part of every object the viewer can see (in view, in front of every infinite plane of
// interest that hides its back side) and which part some map must hold (inside the extent hull).
void FindViewRegions(Context& c) {
    const PlanRequest& r = c.request;
    // An infinite plane of interest is a surface (a floor, a wall): what lies behind it is hidden
    // from a viewer in front of it, so it needs no lookup.
    const Mat4 viewer_inverse = r.viewer.inverse();
    std::vector<Vec4> hiding;  // unit normals, with their indices into r.planes
    std::vector<int> hiding_index;
    for (size_t j = 0; j < r.planes.size(); ++j) {
        const PlaneOfInterest& p = r.planes[j];
        if (!p.polygon.empty()) continue;
        const Vec4 front = p.plane / p.plane.head<3>().norm();
        if (!HidesItsBackSide(viewer_inverse, front, c.thickness)) continue;
        hiding.push_back(front);
        hiding_index.push_back(static_cast<int>(j));
    }
    // What the viewer sees of a box: its part in view, then in front of every hiding plane.
    std::vector<PlaneTest> seen_planes = PlaneTests(c.frustum);
    for (const Vec4& front : hiding) seen_planes.emplace_back(front);
    if (r.objects.empty()) {
        c.held = HeldRegions(c.hull.hull);
        const ConvexPolytope seen = ClippedByAll(ConvexPolytope::FromBox(c.bounds), seen_planes);
        if (!seen.empty()) c.view_regions.push_back({&c.cut_regions.emplace_back(seen), -1, -1});
    }
    // A region no plane cuts is the box itself; one some plane cuts is kept in cut_regions.
    ConvexPolytope scratch;
    const auto keep = [&](const ConvexPolytope& part) {
        return &part == &scratch ? &c.cut_regions.emplace_back(scratch) : &part;
    };
    // The objects some hull face or view plane provably leaves nothing of (ObjectTree) get the
    // empty part the clips would give them, and those every plane holds whole (kInside) the box
    // itself, without the clips. The held parts are clipped when the depth points ask for them.
    std::vector<PlaneTest> inside_hull;
    for (std::size_t f = 0; f < c.hull.hull.face_count(); ++f) {
        inside_hull.emplace_back(-c.hull.hull.face_plane(f));
    }
    std::vector<char> maybe_held, maybe_seen;
    c.object_tree.tree().MarkPossible(inside_hull, maybe_held, true);
    c.object_tree.tree().MarkPossible(seen_planes, maybe_seen, true);
    if (!r.objects.empty()) {
        c.held = HeldRegions(c.object_boxes, std::move(inside_hull), maybe_held);
    }
    for (size_t i = 0; i < c.object_boxes.size(); ++i) {
        c.poll();
        if (!maybe_seen[i]) continue;
        if (c.object_boxes.empty(i)) continue;  // as the clips of an empty polytope find
        ViewRegion v{nullptr, static_cast<int>(i), -1};
        // Held whole by every plane: the box itself, built only if a later step asks for it.
        if (maybe_seen[i] != ObjectTree::kInside) {
            const ConvexPolytope& seen = ClipInto(scratch, c.object_boxes[i], seen_planes);
            if (seen.empty()) continue;
            v.region = keep(seen);
        }
        // A slab standing for the plane itself (a floor mesh at y = 0): its box, unthickened,
        // lies on the plane or behind it, so what the viewer sees of it is on the plane. The test
        // is exact, with no tolerance: a point above the plane by any amount has its light ray
        // meet the plane elsewhere, possibly outside the plane's needed polygon.
        const Aabb& b = r.objects[i].bounds;
        const bool in_bounds = (b.min.array() >= c.bounds.min.array()).all() &&
                               (b.max.array() <= c.bounds.max.array()).all();
        for (size_t k = 0; k < hiding.size() && in_bounds && v.on_plane < 0; ++k) {
            if (hiding[k].dot(HighestCorner(b, hiding[k])) <= 0.0) v.on_plane = hiding_index[k];
        }
        c.view_regions.push_back(std::move(v));
    }
}

}  // namespace

Context MakeContext(const PlanRequest& r, const Aabb& bounds, const ExtentHull& hull) {
    Context c{
        r,  bounds, hull, hull.light, FrustumPlanes(r.viewer), 1e-6 * bounds.Diagonal(), {}, {}, {},
        {}, {},     {},   {},         CancelPoll(&r.cancelled)};
    FindCandidates(c);
    std::vector<Aabb> boxes;
    boxes.reserve(r.objects.size());
    for (const SceneObject& o : r.objects) {
        c.poll();
        boxes.push_back(Thickened(o.bounds, c.thickness));
    }
    c.object_boxes = ObjectBoxes(std::move(boxes));
    c.object_tree = IndexLease(r.object_index.get(), c.object_boxes.bounds());
    FindViewRegions(c);
    return c;
}

}  // namespace lixel::scheduling
