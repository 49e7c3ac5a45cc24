// Homogeneous-coordinate helpers.
#include <lixel/solver/homogeneous.h>

#include <Eigen/LU>

namespace lixel {

Vec4 Cross4(const Vec4& a, const Vec4& b, const Vec4& c) noexcept {
    // Cofactor expansion of det[a b c e_i] along the last column: the result is orthogonal
    // to a, b and c, and non-zero exactly when they are independent.
    Eigen::Matrix3d m;
    Vec4 out;
    const int rows[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
    for (int i = 0; i < 4; ++i) {
        for (int r = 0; r < 3; ++r) {
            m(r, 0) = a(rows[i][r]);
            m(r, 1) = b(rows[i][r]);
            m(r, 2) = c(rows[i][r]);
        }
        const double sign = (i % 2 == 0) ? -1.0 : 1.0;
        out(i) = sign * m.determinant();
    }
    return out;
}

std::vector<Vec4> BoxCorners(const Aabb& box) {
    std::vector<Vec4> corners;
    corners.reserve(8);
    for (int i = 0; i < 8; ++i) corners.push_back(Point(BoxCorner(box, i)));
    return corners;
}

bool AllFinite(const Mat4& m) noexcept { return m.allFinite(); }
bool AllFinite(const Vec4& v) noexcept { return v.allFinite(); }

}  // namespace lixel
