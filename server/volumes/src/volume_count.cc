// Segment/ray against homogeneous triangles: solve a T0 + b T1 + c T2 = (X, 1) on the ray with
// a, b, c >= 0, in double. Degenerate (ray in the triangle's plane) crossings count as misses.
#include <lixel/volumes/volume_count.h>

#include <Eigen/LU>
#include <limits>

namespace lixel::volumes {
namespace {

// +1 / -1 for a crossing of the ray origin + t dir, t in (t_min, t_max), 0 for none. For a finite
// triangle det[T0 T1 T2 (-dir, 0)] = n . dir with n its CCW normal, so a ray entering through the
// front (against n) has det < 0 and counts +1.
int Crossing(const Eigen::Vector4d& t0, const Eigen::Vector4d& t1, const Eigen::Vector4d& t2,
             const Vec3& origin, const Vec3& dir, double t_min, double t_max) {
    if (t0.w() == 0.0 && t1.w() == 0.0 && t2.w() == 0.0) return 0;  // dark caps: CountZFail
    Eigen::Matrix4d m;
    m.col(0) = t0;
    m.col(1) = t1;
    m.col(2) = t2;
    m.col(3) = Eigen::Vector4d(-dir.x(), -dir.y(), -dir.z(), 0.0);
    Eigen::FullPivLU<Eigen::Matrix4d> lu(m);
    if (!lu.isInvertible()) return 0;
    const Eigen::Vector4d x = lu.solve(Eigen::Vector4d(origin.x(), origin.y(), origin.z(), 1.0));
    if (x[0] < 0.0 || x[1] < 0.0 || x[2] < 0.0) return 0;
    if (!(x[3] > t_min && x[3] < t_max)) return 0;
    return m.determinant() > 0.0 ? -1 : 1;
}

}  // namespace

int CountZPass(const VolumeMesh& volume, const Vec3& eye, const Vec3& point) {
    int count = 0;
    const Vec3 dir = point - eye;
    for (const std::vector<std::uint32_t>* list : {&volume.sides, &volume.caps}) {
        const std::vector<std::uint32_t>& t = *list;
        for (std::size_t k = 0; k < t.size(); k += 3) {
            count += Crossing(volume.vertices[t[k]], volume.vertices[t[k + 1]],
                              volume.vertices[t[k + 2]], eye, dir, 0.0, 1.0);
        }
    }
    return count;
}

int CountZFail(const VolumeMesh& volume, const Vec3& eye, const Vec3& point) {
    int count = 0;
    const Vec3 dir = point - eye;
    std::vector<std::uint32_t> all = volume.sides;
    all.insert(all.end(), volume.caps.begin(), volume.caps.end());
    for (std::size_t k = 0; k < all.size(); k += 3) {
        const Eigen::Vector4d& t0 = volume.vertices[all[k]];
        const Eigen::Vector4d& t1 = volume.vertices[all[k + 1]];
        const Eigen::Vector4d& t2 = volume.vertices[all[k + 2]];
        if (t0.w() == 0.0 && t1.w() == 0.0 && t2.w() == 0.0) {
            // A dark cap: the ray reaches it at infinity when dir lies in the cone of its three
            // directions. Its orientation against the ray is the limit of the finite formula for
            // a triangle pushed out along those directions (T_i -> (u_i, eps)): the 4x4
            // determinant tends to eps (a + b + c) det[u0 u1 u2], so the crossing is
            // -sign det[u0 u1 u2] and, counted as a face left, adds sign det[u0 u1 u2].
            Eigen::Matrix3d u;
            u.col(0) = t0.head<3>();
            u.col(1) = t1.head<3>();
            u.col(2) = t2.head<3>();
            Eigen::FullPivLU<Eigen::Matrix3d> lu(u);
            if (!lu.isInvertible()) continue;
            const Eigen::Vector3d abc = lu.solve(dir);
            if (abc.minCoeff() < 0.0) continue;
            count -= u.determinant() > 0.0 ? -1 : 1;
            continue;
        }
        count -= Crossing(t0, t1, t2, point, dir, 0.0, std::numeric_limits<double>::infinity());
    }
    return count;
}

}  // namespace lixel::volumes
