// fuzz_input.h: the fuzz harnesses' shared reader of structured input and their checks of the
// solver's contract (Result<T> never holds NaN or Inf).
#pragma once

#include <lixel/solver/camera.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/mesh.h>
#include <lixel/solver/scheduler.h>
#include <lixel/solver/types.h>

#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

namespace lixel::fuzz {

// Doubles as the solver meets them on the wire: one byte picks a special value (NaN, +-Inf,
// denormals, huge, zero), a small number (k - 72) / 8 that keeps geometry sensible, or eight
// raw bytes (every bit pattern).
inline double PickDouble(FuzzedDataProvider& in) {
    static constexpr double kSpecial[] = {
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.5,
        10.0,
        std::numeric_limits<double>::quiet_NaN(),
        std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity(),
        std::numeric_limits<double>::denorm_min(),
        -std::numeric_limits<double>::denorm_min(),
        std::numeric_limits<double>::min(),
        std::numeric_limits<double>::max(),
        -std::numeric_limits<double>::max(),
        1e-300,
        1e300,
    };
    constexpr int kSpecials = sizeof(kSpecial) / sizeof(kSpecial[0]);
    const int k = in.ConsumeIntegral<std::uint8_t>();
    if (k < kSpecials) return kSpecial[k];
    if (k < 144) return (k - 72) / 8.0;
    double raw = 0.0;
    const auto bytes = in.ConsumeBytes<unsigned char>(sizeof(raw));
    if (!bytes.empty()) std::memcpy(&raw, bytes.data(), bytes.size());
    return raw;
}

inline Vec3 PickVec3(FuzzedDataProvider& in) {
    const double x = PickDouble(in), y = PickDouble(in), z = PickDouble(in);
    return {x, y, z};
}

inline Vec4 PickVec4(FuzzedDataProvider& in) {
    const double x = PickDouble(in), y = PickDouble(in), z = PickDouble(in), w = PickDouble(in);
    return {x, y, z, w};
}

// Either sixteen picked doubles or a look-at perspective viewer with picked parameters (most
// random matrices are refused at once; a camera reaches the solver's inner code).
inline Mat4 PickViewer(FuzzedDataProvider& in) {
    if (in.ConsumeBool()) {
        Mat4 m;
        for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = PickDouble(in);
        return m;
    }
    const Vec3 eye = PickVec3(in);
    const Vec3 target = PickVec3(in);
    const Vec3 up = in.ConsumeBool() ? Vec3(0.0, 1.0, 0.0) : PickVec3(in);
    const double fovy = in.ConsumeBool() ? 0.9 : PickDouble(in);
    const double aspect = in.ConsumeBool() ? 1.0 : PickDouble(in);
    const double near = in.ConsumeBool() ? 0.1 : PickDouble(in);
    const double far = in.ConsumeBool() ? 100.0 : PickDouble(in);
    return Perspective(fovy, aspect, near, far) * LookAt(eye, target, up);
}

inline int PickSide(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegral<std::uint8_t>() % 4) {
        case 0: return in.ConsumeIntegral<int>();
        case 1: return in.ConsumeIntegralInRange<int>(1, 64);
        default: return in.ConsumeIntegralInRange<int>(1, kMaxImageSide);
    }
}

[[noreturn]] inline void Fail(const char* what) {
    std::fprintf(stderr, "lixel fuzz: contract broken: %s\n", what);
    std::abort();
}

template <class Derived>
inline void CheckFinite(const Eigen::MatrixBase<Derived>& m, const char* what) {
    if (!m.allFinite()) Fail(what);
}

inline void CheckFinite(double x, const char* what) {
    if (!std::isfinite(x)) Fail(what);
}

inline void CheckMap(const LightMap& map, const char* what) {
    CheckFinite(map.matrix, what);
    if (map.width < 1 || map.width > kMaxImageSide || map.height < 1 ||
        map.height > kMaxImageSide) {
        Fail(what);
    }
}

// A plan's promises: finite maps within the budget, and a lookup that never reads past a map.
inline void CheckPlan(const PlanRequest& request, const Plan& plan, FuzzedDataProvider& in) {
    std::int64_t total = 0;
    for (const PlannedMap& m : plan.maps) {
        CheckMap(m.map, "planned map");
        if (m.lookup.unshadowed) {
            // Lit where it accepts: no texels, no passes, on a plane's own side.
            if (m.lixels != 0 || !m.passes.empty()) Fail("unshadowed map with texels");
            if (m.lookup.world_limit == Vec4::Zero()) Fail("unshadowed map without its plane");
        } else if (m.lixels != static_cast<std::int64_t>(m.map.width) * m.map.height) {
            Fail("planned map lixels");
        }
        for (const Eigen::Vector3d& h : m.lookup.half_planes) CheckFinite(h, "lookup half-plane");
        CheckFinite(m.scale, "planned map scale");
        if (m.role == MapRole::kPlane && (m.scale_reason.empty() || !(m.scale > 0.0) ||
                                          m.scale > 1.0)) {
            Fail("plane map scale outside (0, 1] or without its reason");
        }
        CheckFinite(m.expected_pixels, "planned map expected pixels");
        total += m.lixels;
    }
    if (total != plan.total_lixels || total > request.lixel_budget) Fail("plan over budget");
    int rectangles = 0;
    for (const PlannedMap& m : plan.maps) rectangles += m.footprint ? 1 : 0;
    if (rectangles > request.footprints.max_per_plan) Fail("footprint rectangles over the limit");
    CheckFinite(plan.plane_scale, "plan scale");
    for (int i = 0; i < 4 && in.remaining_bytes() > 0; ++i) {
        const Vec4 x = in.ConsumeBool() ? Vec4(PickVec3(in).homogeneous()) : PickVec4(in);
        const int index = LookupMap(plan, x);
        if (index < -1 || index >= static_cast<int>(plan.maps.size())) Fail("lookup index");
    }
}

// Loaded or uploaded meshes are usable: whole triangles, indices inside the positions, normals
// absent or one per position.
inline void CheckMeshes(const std::vector<Mesh>& meshes) {
    for (const Mesh& mesh : meshes) {
        if (mesh.indices.size() % 3 != 0) Fail("mesh index count not a multiple of 3");
        for (std::uint32_t index : mesh.indices) {
            if (index >= mesh.positions.size()) Fail("mesh index out of range");
        }
        if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size()) {
            Fail("mesh normals do not match positions");
        }
    }
}

}  // namespace lixel::fuzz
