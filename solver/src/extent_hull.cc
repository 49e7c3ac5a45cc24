// The Stamminger-Drettakis extent hull, as an intersection of half-spaces clipped from the
// scene bounds: hull(V ∪ {l}) is bounded exactly by the faces of V that do not separate l from
// V and by the planes through l and an edge of V that support V. Every plane through l and two
// vertices of V that supports V bounds the hull too, so all such pairs are clipped by (V has a
// few dozen vertices at most) and no silhouette-edge search is needed.
#include <lixel/solver/camera.h>
#include <lixel/solver/extent_hull.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/polygon.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace lixel {

namespace {

// A plane through l and two vertices is degenerate when the sine of the angle the two
// vertices subtend at l (or between their offset and a directional light) is below this.
constexpr double kMinPlaneSine = 1e-9;

// Cosine below which a face of V counts as not facing a directional light (rounding of
// n . d for unit vectors).
constexpr double kDirectionTolerance = 1e-12;

Result<Vec4> NormalizeLight(const Vec4& light) {
    if (!AllFinite(light)) return Error{"light", "is not finite"};
    if (light.w() != 0.0) {
        const Vec4 point = light / light.w();
        if (!point.allFinite()) {
            return Error{"light",
                         "point is too far away to represent; pass it as a direction "
                         "(w = 0)"};
        }
        return point;
    }
    const double length = light.head<3>().norm();
    if (!(length > 0.0)) return Error{"light", "direction (w = 0) is the zero vector"};
    return Vec4(light / length);
}

Result<bool> ValidateBounds(const Aabb& bounds) {
    if (!bounds.min.allFinite() || !bounds.max.allFinite()) {
        return Error{"bounds", "is not finite"};
    }
    for (int i = 0; i < 3; ++i) {
        if (!(bounds.min(i) < bounds.max(i))) {
            return Error{"bounds", "has no volume: min must be below max on every axis (axis " +
                                       std::to_string(i) + ": " + ShortestText(bounds.min(i)) +
                                       " >= " + ShortestText(bounds.max(i)) + ")"};
        }
    }
    return true;
}

}  // namespace

Result<ExtentHull> ComputeExtentHull(const Mat4& viewer, const Vec4& light,
                                     const Aabb& bounds) noexcept {
    // The viewport does not enter the frustum; a 1 x 1 one lets ValidateViewer check the matrix.
    if (Result<bool> ok = ValidateViewer(viewer, Viewport{1, 1}, "viewer"); !ok) {
        return ok.error();
    }
    Result<Vec4> l = NormalizeLight(light);
    if (!l) return l.error();
    if (Result<bool> ok = ValidateBounds(bounds); !ok) return ok.error();

    ExtentHull out;
    out.light = *l;
    const bool directional = out.light.w() == 0.0;
    const ConvexPolytope box = ConvexPolytope::FromBox(bounds);

    ConvexPolytope v = box;
    for (const Vec4& plane : FrustumPlanes(viewer)) v.Clip(plane);
    if (v.empty()) {
        return Error{"viewer", "view frustum does not meet scene bounds"};
    }
    const double tol = v.Tolerance();
    const Vec3 l3 = out.light.head<3>();
    out.light_inside = !directional && v.Contains(l3, tol);

    ConvexPolytope h = v;
    if (!out.light_inside) {
        h = box;
        // Faces of V that keep l on their inner side bound the hull (pi . l <= 0, which for
        // w = 0 says the face does not look toward the light, so the sweep never crosses it).
        const double face_tol = directional ? kDirectionTolerance : tol;
        for (std::size_t f = 0; f < v.face_count(); ++f) {
            const Vec4& outward = v.face_plane(f);
            if (outward.dot(out.light) <= face_tol) h.Clip(Vec4(-outward));
        }
        // Supporting planes through l and two vertices of V (silhouette edges among them).
        const std::vector<Vec3> corners = v.vertices();
        for (size_t i = 0; i < corners.size(); ++i) {
            for (size_t j = i + 1; j < corners.size(); ++j) {
                const Vec3& a = corners[i];
                const Vec3& b = corners[j];
                Vec4 plane = Cross4(Point(a), Point(b), out.light);
                const double n_length = plane.head<3>().norm();
                const double reference =
                    directional ? (b - a).norm() : (a - l3).norm() * (b - l3).norm();
                if (!(n_length > kMinPlaneSine * reference)) continue;
                plane /= n_length;
                double lo = 0.0;
                double hi = 0.0;
                for (const Vec3& c : corners) {
                    const double s = plane.head<3>().dot(c) + plane.w();
                    lo = std::min(lo, s);
                    hi = std::max(hi, s);
                }
                if (lo >= -tol) {
                    h.Clip(plane);
                } else if (hi <= tol) {
                    h.Clip(-plane);
                }
            }
        }
    }
    if (h.empty()) {
        // H contains V, so this is rounding in a degenerate V; say so rather than return junk.
        return Error{"viewer", "view volume is too thin to build an extent hull from"};
    }

    const double h_tol = h.Tolerance();
    for (const Vec3& p : h.vertices()) {
        out.vertices.push_back(Point(p));
        if (directional || (p - l3).norm() > h_tol) out.ray_points.push_back(Point(p));
    }
    out.view_volume = std::move(v);
    out.hull = std::move(h);
    return out;
}

}  // namespace lixel
