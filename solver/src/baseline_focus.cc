// The focus shared by every baseline map (baseline_focus.h).
#include "baseline_focus.h"

#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_frustum.h>
#include <lixel/solver/polygon.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace lixel::baseline_focus {

Vec4 NormalizedLight(const Vec4& light) {
    if (light.w() != 0.0) return light / light.w();
    return light / light.head<3>().norm();
}

Result<bool> ValidateInput(const BaselineInput& input, const ExtentHull& hull) {
    if (Result<bool> ok = ValidateViewer(input.viewer, input.viewport, "viewer"); !ok) {
        return ok.error();
    }
    if (!AllFinite(input.light)) return Error{"light", "is not finite"};
    if (input.light.w() == 0.0 && !(input.light.head<3>().norm() > 0.0)) {
        return Error{"light", "direction (w = 0) is the zero vector"};
    }
    if (input.lixel_budget < 1) {
        return Error{"lixel_budget", "must be >= 1, got " + std::to_string(input.lixel_budget)};
    }
    for (size_t i = 0; i < input.receivers.size(); ++i) {
        const Aabb& box = input.receivers[i];
        if (!box.min.allFinite() || !box.max.allFinite()) {
            return Error{"receivers[" + std::to_string(i) + "]", "is not finite"};
        }
        if (!(box.min.array() <= box.max.array()).all()) {
            return Error{"receivers[" + std::to_string(i) + "]", "has min > max on some axis"};
        }
    }
    const Vec4 l = NormalizedLight(input.light);
    if (!l.allFinite() || (l.w() == 0.0) != (hull.light.w() == 0.0) ||
        !((l - hull.light).norm() <= kSameLightTolerance * std::max(1.0, l.norm()))) {
        return Error{"hull", "was computed for a different light"};
    }
    if (hull.light_inside) {
        return Error{"hull",
                     "the light lies inside the extent hull: no single map holds C_tot "
                     "(use cube faces)"};
    }
    if (hull.ray_points.empty()) return Error{"hull", "has no vertices"};
    return true;
}

void AppendBoxInView(const Aabb& box, const ConvexPolytope& view,
                     const std::vector<Vec3>& view_vertices, std::vector<Vec4>& out) {
    const double slack = view.Tolerance();
    for (int axis = 0; axis < 3; ++axis) {
        const int b = (axis + 1) % 3;
        const int c = (axis + 2) % 3;
        for (const double side : {box.min(axis), box.max(axis)}) {
            std::vector<Vec3> face(4);
            const double corner_b[4] = {box.min(b), box.max(b), box.max(b), box.min(b)};
            const double corner_c[4] = {box.min(c), box.min(c), box.max(c), box.max(c)};
            for (int k = 0; k < 4; ++k) {
                face[k](axis) = side;
                face[k](b) = corner_b[k];
                face[k](c) = corner_c[k];
            }
            for (const PolytopeFace& f : view.faces()) {
                if (face.empty()) break;
                face = ClipPolygon(face, Vec4(-f.outward_plane + Vec4(0.0, 0.0, 0.0, slack)));
            }
            for (const Vec3& p : face) out.push_back(Point(p));
        }
    }
    for (const Vec3& v : view_vertices) {
        if ((v.array() >= box.min.array() - slack).all() &&
            (v.array() <= box.max.array() + slack).all()) {
            out.push_back(Point(v));
        }
    }
}

std::vector<Vec4> HullInReceiverRays(const ExtentHull& hull, const std::vector<Vec4>& receivers) {
    Result<Mat4> basis = LightFrustumBasis(hull.light, receivers);
    if (!basis) return {};
    std::vector<Vec2> images;
    images.reserve(receivers.size());
    for (const Vec4& r : receivers) {
        const Vec4 p = *basis * r;
        if (!(p.w() > 0.0)) return {};
        images.emplace_back(p.x() / p.w(), p.y() / p.w());
    }
    const std::vector<Vec2> outline = ConvexHull2d(std::move(images));
    if (outline.size() < 3) return {};
    ConvexPolytope part = hull.hull;
    auto clip = [&](const RowVec4& plane) {
        const double n = plane.head<3>().norm();
        if (n > 0.0) part.Clip(Vec4(plane.transpose() / n));
    };
    for (size_t i = 0; i < outline.size() && !part.empty(); ++i) {
        const Vec2 a = outline[i];
        const Vec2 edge = outline[(i + 1) % outline.size()] - a;
        // Counter-clockwise outline: the inside is to the left, n . (x - a) >= 0, times q > 0.
        const Vec2 n(-edge.y(), edge.x());
        clip(n.x() * basis->row(0) + n.y() * basis->row(1) - n.dot(a) * basis->row(3));
    }
    if (hull.light.w() != 0.0) clip(basis->row(3));  // in front of the light, not its mirror
    if (part.empty()) return {};
    // The cone's apex, the light, is a vertex when the light is in the bounds, and rounding may
    // leave others a hair from it where no map's q has a sign to trust: casters that near the
    // light are depth-clamped anyway (FitDepthRow's floor is 1e-4 of the range). R's own
    // vertices go in whole, so the rounding of the clip never loses a receiver.
    std::vector<Vec4> points;
    const Vec3 light = hull.light.head<3>() / (hull.light.w() != 0.0 ? hull.light.w() : 1.0);
    const double near_light = std::max(part.Tolerance(), kNearLightRelative * part.Size());
    for (const Vec3& p : part.vertices()) {
        if (hull.light.w() == 0.0 || (p - light).norm() > near_light) points.push_back(Point(p));
    }
    points.insert(points.end(), receivers.begin(), receivers.end());
    return points;
}

Focus FocusOf(const BaselineInput& input, const ExtentHull& hull) {
    Focus focus;
    const std::vector<Vec3> view_vertices = hull.view_volume.vertices();
    for (const Aabb& box : input.receivers) {
        AppendBoxInView(box, hull.view_volume, view_vertices, focus.receivers);
    }
    if (!focus.receivers.empty()) {
        focus.points = HullInReceiverRays(hull, focus.receivers);
        focus.on_receivers = !focus.points.empty();
    }
    if (!focus.on_receivers) {
        focus.receivers.clear();
        for (const Vec3& v : view_vertices) focus.receivers.push_back(Point(v));
        focus.points = hull.ray_points;
    }
    return focus;
}

bool ViewerAxis(const Mat4& viewer, Vec3& eye, Vec3& forward, double& scale) {
    Result<Vec4> e = EyePoint(viewer);
    if (!e || !(std::abs(e->w()) > 1e-12 * e->head<3>().norm())) return false;
    eye = e->head<3>() / e->w();
    const RowVec4 r_w = viewer.row(3);
    scale = r_w.head<3>().norm();
    if (!(scale > 0.0)) return false;
    forward = r_w.head<3>().transpose() / scale;
    return eye.allFinite();
}

void ViewDepths(const Focus& focus, const Vec3& eye, const Vec3& forward, double& z_near,
                double& z_far) {
    z_near = std::numeric_limits<double>::infinity();
    z_far = -z_near;
    for (const Vec4& r : focus.receivers) {
        const double t = forward.dot(r.head<3>() - eye);
        z_near = std::min(z_near, t);
        z_far = std::max(z_far, t);
    }
}

}  // namespace lixel::baseline_focus
