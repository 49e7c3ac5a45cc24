// Seen receivers and their worst aliasing for the baselines (baseline_receivers.h).
#include "baseline_receivers.h"

#include <lixel/solver/camera.h>

#include <cmath>
#include <limits>

namespace lixel::baseline_focus {

namespace {

// The entry of the segment a + t (b - a), t in [0, 1], into `box` (slabs; a flat box is a
// rectangle, entered where the segment crosses its plane): t and the entered face's outward
// normal, or t = infinity.
struct Entry {
    double t = std::numeric_limits<double>::infinity();
    Vec3 normal = Vec3::Zero();
};
Entry EnterBox(const Vec3& a, const Vec3& b, const Aabb& box) {
    const Vec3 d = b - a;
    double t_in = 0.0, t_out = 1.0;
    Vec3 normal = Vec3::Zero();
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0) {
            if (a[k] < box.min[k] || a[k] > box.max[k]) return {};
            continue;
        }
        const double t0 = (box.min[k] - a[k]) / d[k];
        const double t1 = (box.max[k] - a[k]) / d[k];
        const double enter = std::min(t0, t1);
        if (enter > t_in) {
            t_in = enter;
            normal = Vec3::Zero();
            normal[k] = d[k] > 0.0 ? -1.0 : 1.0;
        }
        t_out = std::min(t_out, std::max(t0, t1));
    }
    if (t_in > t_out || normal.isZero(0.0)) return {};  // missed, or began inside
    return {t_in, normal};
}

}  // namespace

std::vector<Receiver> SampleSeenReceivers(const BaselineInput& input, int per_side) {
    std::vector<Receiver> out;
    const Mat4 unproject = PixelMatrix(input.viewer, input.viewport).inverse();
    if (!unproject.allFinite()) return out;
    for (int i = 0; i < per_side; ++i) {
        for (int j = 0; j < per_side; ++j) {
            const double x = (i + 0.5) / per_side * input.viewport.width;
            const double y = (j + 0.5) / per_side * input.viewport.height;
            const Vec4 near = unproject * Vec4(x, y, kClipDepthNear, 1.0);
            const Vec4 far = unproject * Vec4(x, y, kClipDepthFar, 1.0);
            if (!(std::abs(near.w()) > 0.0) || !(std::abs(far.w()) > 0.0)) continue;
            const Vec3 a = near.head<3>() / near.w(), b = far.head<3>() / far.w();
            Entry nearest;
            for (const Aabb& box : input.receivers) {
                const Entry e = EnterBox(a, b, box);
                if (e.t < nearest.t) nearest = e;
            }
            if (!std::isfinite(nearest.t)) continue;
            const Vec3 p = a + nearest.t * (b - a);
            out.push_back({p, Vec4(nearest.normal.x(), nearest.normal.y(), nearest.normal.z(),
                                   -nearest.normal.dot(p))});
        }
    }
    return out;
}

double WorstAliasing(const LightMap& map, const BaselineInput& input,
                     const std::vector<Receiver>& seen) {
    const SolveDiagnostics d = DiagnoseMap(map, input.light, input.viewer, input.viewport, seen);
    if (d.samples == 0 || !(d.lixels_per_pixel_min > 0.0)) {
        return std::numeric_limits<double>::infinity();
    }
    return 1.0 / d.lixels_per_pixel_min;
}

}  // namespace lixel::baseline_focus
