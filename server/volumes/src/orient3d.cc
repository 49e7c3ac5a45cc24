// A filtered exact orientation predicate (Shewchuk 1997): the double evaluation with error bound
// A of predicates.c, then nonoverlapping expansions (Two-Sum, Two-Product by Dekker's split,
// Grow-Expansion, Scale-Expansion with zero elimination). Compiled with -ffp-contract=off: the
// bound and the error-free transformations assume every operation is rounded on its own.
#include <lixel/volumes/orient3d.h>

#include <cmath>
#include <cstddef>
#include <vector>

namespace lixel::volumes {
namespace {

using Expansion = std::vector<double>;  // nonoverlapping, increasing magnitude, no zeros

constexpr double kEpsilon = 0x1p-53;  // half an ulp of 1: the unit roundoff
// predicates.c, o3derrboundA: |det - fl(det)| <= this times the permanent, when every matrix
// entry is one correctly rounded operation on the inputs.
constexpr double kErrorBoundA = (7.0 + 56.0 * kEpsilon) * kEpsilon;
constexpr double kSplitter = 0x1p27 + 1.0;  // Dekker: splits a double into two 26-bit halves
// Below this permanent the filter's relative bound could be spoiled by underflow: go exact.
constexpr double kTinyPermanent = 0x1p-900;

// a + b = s + e exactly (Knuth's Two-Sum).
void TwoSum(double a, double b, double& s, double& e) {
    s = a + b;
    const double bv = s - a;
    const double av = s - bv;
    e = (a - av) + (b - bv);
}

void Split(double a, double& hi, double& lo) {
    const double c = kSplitter * a;
    const double big = c - a;
    hi = c - big;
    lo = a - hi;
}

// a * b = p + e exactly (Dekker's Two-Product).
void TwoProduct(double a, double b, double& p, double& e) {
    p = a * b;
    double ahi, alo, bhi, blo;
    Split(a, ahi, alo);
    Split(b, bhi, blo);
    const double err1 = p - ahi * bhi;
    const double err2 = err1 - alo * bhi;
    const double err3 = err2 - ahi * blo;
    e = alo * blo - err3;
}

Expansion Of(double a) { return a == 0.0 ? Expansion{} : Expansion{a}; }

// a - b as an expansion of at most two terms.
Expansion Difference(double a, double b) {
    double s, e;
    TwoSum(a, -b, s, e);
    Expansion out;
    if (e != 0.0) out.push_back(e);
    if (s != 0.0) out.push_back(s);
    return out;
}

// Shewchuk's Grow-Expansion with zero elimination: e + b.
Expansion Grow(const Expansion& e, double b) {
    Expansion out;
    double q = b;
    for (const double c : e) {
        double s, h;
        TwoSum(q, c, s, h);
        if (h != 0.0) out.push_back(h);
        q = s;
    }
    if (q != 0.0) out.push_back(q);
    return out;
}

// Expansion-Sum: e + f, by growing e with every component of f.
Expansion Sum(const Expansion& e, const Expansion& f) {
    Expansion out = e;
    for (const double c : f) out = Grow(out, c);
    return out;
}

Expansion Negate(Expansion e) {
    for (double& c : e) c = -c;
    return e;
}

// Shewchuk's Scale-Expansion with zero elimination: e * b.
Expansion Scale(const Expansion& e, double b) {
    Expansion out;
    if (e.empty() || b == 0.0) return out;
    double q, h;
    TwoProduct(e[0], b, q, h);
    if (h != 0.0) out.push_back(h);
    for (std::size_t i = 1; i < e.size(); ++i) {
        double p1, p0, s;
        TwoProduct(e[i], b, p1, p0);
        TwoSum(q, p0, s, h);
        if (h != 0.0) out.push_back(h);
        TwoSum(p1, s, q, h);
        if (h != 0.0) out.push_back(h);
    }
    if (q != 0.0) out.push_back(q);
    return out;
}

Expansion Product(const Expansion& e, const Expansion& f) {
    Expansion out;
    for (const double c : f) out = Sum(out, Scale(e, c));
    return out;
}

// The sign of a nonoverlapping expansion is the sign of its largest component.
int Sign(const Expansion& e) { return e.empty() ? 0 : (e.back() > 0.0) - (e.back() < 0.0); }

int ExactLightFacing(const Vec3& a, const Vec3& b, const Vec3& c, const Vec4& l) {
    Expansion u[3], v[3], m[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = Difference(b[k], a[k]);
        v[k] = Difference(c[k], a[k]);
        double p, e;
        TwoProduct(l.w(), a[k], p, e);
        // l_k - (p + e), p + e = l_w a_k exactly.
        m[k] = Grow(Grow(Of(l[k]), -p), -e);
    }
    const Expansion nx = Sum(Product(v[1], m[2]), Negate(Product(v[2], m[1])));
    const Expansion ny = Sum(Product(v[2], m[0]), Negate(Product(v[0], m[2])));
    const Expansion nz = Sum(Product(v[0], m[1]), Negate(Product(v[1], m[0])));
    return Sign(Sum(Sum(Product(nx, u[0]), Product(ny, u[1])), Product(nz, u[2])));
}

}  // namespace

int LightFacingSign(const Vec3& a, const Vec3& b, const Vec3& c, const Vec4& l) noexcept {
    const double w = l.w();
    // The filter needs each entry to be one rounded operation: l_w a is exact for l_w = 0 or 1.
    if (w == 0.0 || w == 1.0) {
        const double ux = b.x() - a.x(), uy = b.y() - a.y(), uz = b.z() - a.z();
        const double vx = c.x() - a.x(), vy = c.y() - a.y(), vz = c.z() - a.z();
        const double mx = w == 0.0 ? l.x() : l.x() - a.x();
        const double my = w == 0.0 ? l.y() : l.y() - a.y();
        const double mz = w == 0.0 ? l.z() : l.z() - a.z();
        // The same three-term cofactor sum as predicates.c's orient3d, rows u, v, m.
        const double vymz = vy * mz, vzmy = vz * my;
        const double vzmx = vz * mx, vxmz = vx * mz;
        const double vxmy = vx * my, vymx = vy * mx;
        const double det = ux * (vymz - vzmy) + uy * (vzmx - vxmz) + uz * (vxmy - vymx);
        const double permanent = (std::abs(vymz) + std::abs(vzmy)) * std::abs(ux) +
                                 (std::abs(vzmx) + std::abs(vxmz)) * std::abs(uy) +
                                 (std::abs(vxmy) + std::abs(vymx)) * std::abs(uz);
        if (permanent == 0.0) return 0;  // an entry of every term is an exact zero
        const double bound = kErrorBoundA * permanent;
        if (permanent > kTinyPermanent && (det > bound || -det > bound)) return det > 0.0 ? 1 : -1;
    }
    return ExactLightFacing(a, b, c, l);
}

int Orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) noexcept {
    // det[a - d; b - d; c - d] is LightFacingSign with corners d, a, b and the point light c.
    return LightFacingSign(d, a, b, Vec4(c.x(), c.y(), c.z(), 1.0));
}

}  // namespace lixel::volumes
