// Every field of a plan as text, floats in hex (%a), so that two plans compare bit for bit as
// strings: lixel_plan_dump's output (scripts/compare_plans.sh) and the tests that check a change
// leaves plans as they were (a kept object index against none).
#pragma once

#include <lixel/solver/scheduler.h>

#include <cstdarg>
#include <cstdio>
#include <string>

namespace lixel::plan_text {

// printf into the end of `out`.
[[gnu::format(printf, 2, 3)]] inline void Print(std::string& out, const char* format, ...) {
    char small[256];
    va_list args;
    va_start(args, format);
    const int n = std::vsnprintf(small, sizeof small, format, args);
    va_end(args);
    if (n < 0) return;
    if (static_cast<std::size_t>(n) < sizeof small) {
        out.append(small, static_cast<std::size_t>(n));
        return;
    }
    const std::size_t at = out.size();
    out.resize(at + static_cast<std::size_t>(n) + 1);
    va_start(args, format);
    std::vsnprintf(out.data() + at, static_cast<std::size_t>(n) + 1, format, args);
    va_end(args);
    out.resize(at + static_cast<std::size_t>(n));
}

inline void Number(std::string& out, const char* key, double v) { Print(out, "%s %a\n", key, v); }

template <class Matrix>
void Numbers(std::string& out, const char* key, const Matrix& m) {
    Print(out, "%s", key);
    for (Eigen::Index i = 0; i < m.size(); ++i) Print(out, " %a", m.data()[i]);
    Print(out, "\n");
}

inline void Polytope(std::string& out, const char* key, const ConvexPolytope& p) {
    Print(out, "%s %zu\n", key, p.vertices().size());
    for (const Vec3& v : p.vertices()) Numbers(out, "  v", v);
}

inline void MapText(std::string& out, const PlannedMap& m) {
    Print(out, "map %d %d %d %s %dx%d lixels %lld footprint %d\n", static_cast<int>(m.role),
          m.plane_index, m.cube_face, m.name.c_str(), m.map.width, m.map.height,
          static_cast<long long>(m.lixels), static_cast<int>(m.footprint));
    Numbers(out, " matrix", m.map.matrix);
    Print(out, " passes");
    for (const Pass p : m.passes) Print(out, " %d", static_cast<int>(p));
    Print(out, "\n lookup guard %d unshadowed %d half_planes %zu\n", m.lookup.guard,
          static_cast<int>(m.lookup.unshadowed), m.lookup.half_planes.size());
    for (const Eigen::Vector3d& h : m.lookup.half_planes) Numbers(out, "  half_plane", h);
    Numbers(out, " world_limit", m.lookup.world_limit);
    for (const Vec2& v : m.needed_image) Numbers(out, " needed_image", v);
    for (const Vec3& v : m.needed_polygon) Numbers(out, " needed_polygon", v);
    const SolveDiagnostics& d = m.diagnostics;
    Print(out, " diagnostics %a %a %a %d %d %a %a %a %a %a %d\n", d.residual_lixels,
          d.residual_lixels_float, d.conditioning, static_cast<int>(d.horizon_in_view), d.sign,
          d.depth_resolution, d.depth_step_nearest, d.depth_step_farthest, d.lixels_per_pixel_min,
          d.lixels_per_pixel_max, d.samples);
    Number(out, " scale", m.scale);
    Print(out, " scale_reason %s\n", m.scale_reason.c_str());
    Number(out, " twist", m.twist_radians);
    Number(out, " expected_pixels", m.expected_pixels);
    Print(out, " kept_for %s\n", m.kept_for.c_str());
}

inline std::string PlanText(const Result<Plan>& result) {
    std::string out;
    if (!result) {
        Print(out, "error %s | %s\n", result.error().field.c_str(), result.error().reason.c_str());
        return out;
    }
    const Plan& p = *result;
    Print(out, "maps %zu\n", p.maps.size());
    for (const PlannedMap& m : p.maps) MapText(out, m);
    for (const LeftOut& l : p.left_out)
        Print(out, "left_out %s | %s\n", l.item.c_str(), l.reason.c_str());
    for (const std::string& w : p.warnings) Print(out, "warning %s\n", w.c_str());
    Polytope(out, "hull.view_volume", p.hull.view_volume);
    Polytope(out, "hull.hull", p.hull.hull);
    for (const Vec4& v : p.hull.vertices) Numbers(out, " hull.vertex", v);
    for (const Vec4& v : p.hull.ray_points) Numbers(out, " hull.ray_point", v);
    Numbers(out, "hull.light", p.hull.light);
    Print(out, "hull.light_inside %d\n", static_cast<int>(p.hull.light_inside));
    Number(out, "plane_scale", p.plane_scale);
    Print(out, "total_lixels %lld volumes %d\n", static_cast<long long>(p.total_lixels),
          static_cast<int>(p.volumes));
    return out;
}

}  // namespace lixel::plan_text
