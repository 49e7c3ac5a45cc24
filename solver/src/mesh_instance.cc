// Mesh instances: their matrices' checks and transformed bounds (mesh_instance.h).
#include <lixel/solver/mesh_instance.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>
#include <limits>

namespace lixel {

std::vector<MeshInstance> IdentityInstances(std::size_t meshes) {
    std::vector<MeshInstance> instances(meshes);
    for (std::size_t m = 0; m < meshes; ++m) instances[m].mesh = static_cast<std::uint32_t>(m);
    return instances;
}

Result<bool> CheckInstanceMatrix(const Mat4& m, const std::string& field) {
    for (int i = 0; i < 16; ++i) {
        if (!std::isfinite(m.data()[i])) {
            return Error{field, "m[" + std::to_string(i) + "] is not finite"};
        }
        if (std::abs(m.data()[i]) > kMaxInstanceEntry) {
            return Error{field, "m[" + std::to_string(i) + "] is beyond 1e15 in magnitude"};
        }
    }
    if (m(3, 0) != 0.0 || m(3, 1) != 0.0 || m(3, 2) != 0.0 || m(3, 3) != 1.0) {
        return Error{field, "not affine: its last row must be exactly (0, 0, 0, 1)"};
    }
    const Eigen::JacobiSVD<Mat3> svd(m.topLeftCorner<3, 3>());
    const Vec3 sigma = svd.singularValues();  // descending
    if (!(sigma[2] > kMinInstanceConditioning * sigma[0])) {
        return Error{field, "singular: its linear part's singular values " +
                                std::to_string(sigma[0]) + " and " + std::to_string(sigma[2]) +
                                " are more than 1e6 apart"};
    }
    return true;
}

Aabb TransformBounds(const Aabb& box, const Mat4& m) {
    if (!(box.min.array() <= box.max.array()).all()) return box;
    // Every corner carried in double: an affine map's image of a box is the hull of its
    // corners, and the identity (or a translation by a representable offset) gives the box
    // back exactly, so a mesh in place plans as it does unplaced.
    Aabb out{Vec3::Constant(std::numeric_limits<double>::infinity()),
             Vec3::Constant(-std::numeric_limits<double>::infinity())};
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3 p((corner & 1) ? box.max.x() : box.min.x(),
                     (corner & 2) ? box.max.y() : box.min.y(),
                     (corner & 4) ? box.max.z() : box.min.z());
        const Vec3 q = m.topLeftCorner<3, 3>() * p + m.topRightCorner<3, 1>();
        out.min = out.min.cwiseMin(q);
        out.max = out.max.cwiseMax(q);
    }
    return out;
}

Mat4 RelativeObjectToWorld(const Mat4& m, const Vec3& origin) {
    Mat4 relative = m;
    relative.topRightCorner<3, 1>() =
        m.topLeftCorner<3, 3>() * origin + m.topRightCorner<3, 1>() - origin;
    return relative;
}

bool Mirrors(const Mat4& m) { return m.topLeftCorner<3, 3>().determinant() < 0.0; }

Vec4 ObjectSpaceLight(const Mat4& m, const Vec4& light) {
    // m^-1 = [A^-1 | -A^-1 t]: a solve, not an explicit inverse, and w carried as given.
    const Eigen::PartialPivLU<Mat3> lu(m.topLeftCorner<3, 3>());
    const Vec3 xyz = lu.solve(light.head<3>() - light.w() * m.topRightCorner<3, 1>());
    return Vec4(xyz.x(), xyz.y(), xyz.z(), light.w());
}

double LargestStretch(const Mat4& m) {
    return Eigen::JacobiSVD<Mat3>(m.topLeftCorner<3, 3>()).singularValues()[0];
}

}  // namespace lixel
