// The lookup rule's CPU twin (Chong & Gortler §3): maps in order, in-bounds and half-plane
// tests, first acceptance wins. The view shader runs the same tests in the same order.
#include <lixel/solver/scheduler.h>

namespace lixel {

bool LookupAccepts(const PlannedMap& map, const Vec4& x) noexcept {
    const Vec4 p = map.map.matrix * x;
    if (!(p.w() > 0.0)) return false;
    // Signed by w so that any homogeneous representative of a finite point gives one answer.
    if (map.lookup.world_limit.dot(x) * (x.w() < 0.0 ? -1.0 : 1.0) < 0.0) return false;
    const double u = p.x() / p.w();
    const double v = p.y() / p.w();
    const Eigen::Vector4d r = LookupRectangle(map.map, map.lookup);
    if (!(u >= r[0] && u < r[2] && v >= r[1] && v < r[3])) return false;
    for (const Eigen::Vector3d& h : map.lookup.half_planes) {
        if (h.x() * u + h.y() * v + h.z() < 0.0) return false;
    }
    return true;
}

int LookupMap(const Plan& plan, const Vec4& x) noexcept {
    for (size_t i = 0; i < plan.maps.size(); ++i) {
        if (LookupAccepts(plan.maps[i], x)) return static_cast<int>(i);
    }
    return -1;
}

}  // namespace lixel
