// Smooth silhouettes (paper 002): the contour of the smooth surface that a coarse mesh's vertex
// normals describe, as seen from the light, adaptively subdivided to a world-space tolerance.
//
// Steps (paper 002 §3): (a) accurate silhouette points on edges where the facing value
// f = n . (l_xyz - l_w v) of the vertex normals changes sign (Hertzmann and Zorin), traced into
// loops across the mesh; (b) each point displaced along a cubic Hermite curve through its edge;
// (c) each loop segment subdivided (Listing 1) until the midpoint moves less than epsilon.
//
// The loops are the boundary of the lit region R = {f > 0} of every triangle, f interpolated
// linearly per triangle from its own corners' normals. Where a crease gives an edge two normals
// per end, the two sides disagree on R and the boundary runs along the crease; where the normals
// switch along a loop, the loop gets a zero-length edge between the two normals (paper 002 §3.3),
// which keeps the crease's corner.
#pragma once

#include <lixel/solver/mesh.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>
#include <lixel/volumes/edge_adjacency.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lixel::volumes {

// The defaults the service and the report use (issue 16): a subdivision tolerance of 1e-3
// world units, and the offset along -n at paper 002's ratio to it (an offset of 0.15 with
// epsilon 0.01, in units the paper does not name: the ratio is what carries over).
inline constexpr double kDefaultSmoothEpsilon = 1e-3;
inline constexpr double kPaperOffsetPerEpsilon = 15.0;

struct SmoothOptions {
    // Paper 002, Eq. 2: subdivide until |(p0 + p1) / 2 - p| < epsilon, world units, > 0.
    // The paper's Table 1 uses 0.01 on models about one unit across.
    double epsilon = 0.01;
    // Paper 002 §5: smooth points move this far along -n against light leaks where the smooth
    // contour leaves the discrete mesh (the paper uses 0.15 in its scenes' units). World units,
    // >= 0; 0 keeps the points on the smooth contour.
    double normal_offset = 0.0;
    // Step (b): Hermite displacement of the accurate points. Off gives Hertzmann-Zorin loops.
    bool displace = true;
    // Step (c): subdivision. Off gives the displaced accurate points only.
    bool subdivide = true;
    // Recursion depth limit per segment (2^depth pieces at most), in [0, 30].
    int max_depth = 12;
    // The most points step (c) may emit over all loops; 0: no bound. An epsilon far below the
    // mesh's scale splits every segment into 2^max_depth pieces, so a caller with a memory budget
    // sets this: the silhouette is refused ("options.max_points") when it would pass it, before
    // the loops hold more.
    std::size_t max_points = 0;
};

struct SmoothVertex {
    Vec3 position;              // p: on the smooth contour, minus normal_offset * normal
    Vec3 base;                  // p': on the mesh, (1 - u) p'_i + u p'_(i+1) (paper 002 §4)
    Vec3 normal;                // unit, interpolated
    std::uint32_t segment = 0;  // index of the accurate segment it was subdivided from
    double u = 0.0;             // parameter on that segment's Hermite curve, [0, 1)
    bool corner = false;        // a crease corner: the edge to the next vertex has zero length
};

// A polyline; closed (the last vertex joins the first) unless the boundary could not be closed.
struct SmoothLoop {
    std::vector<SmoothVertex> vertices;
    bool closed = true;
};

// The accurate segment every SmoothVertex::segment refers to: its Hermite curve before
// subdivision (for checking the epsilon criterion and errors).
struct AccurateSegment {
    Vec3 p0, p1, t0, t1;  // Hermite control data (zero tangents for a crease corner)
};

struct SmoothStats {
    std::size_t accurate_points = 0;  // loop vertices after step (a)
    std::size_t output_points = 0;    // after step (c)
    std::size_t crease_corners = 0;   // zero-length edges inserted
    std::size_t open_chains = 0;      // loops that could not be closed (should be 0)
    std::size_t depth_limited = 0;    // segments that hit max_depth before epsilon
};

struct SmoothSilhouette {
    std::vector<SmoothLoop> loops;
    std::vector<AccurateSegment> segments;
    // Per kept triangle, OrientTriangles (orientation.h): the windings the loops were traced in,
    // which ExtrudeSmoothVolume winds its caps by.
    std::vector<std::int8_t> orientation;
    SmoothStats stats;
};

// Facing value f = n . (l_xyz - l_w v) per input vertex (normalised normal): > 0 lit.
std::vector<double> FacingValues(const Mesh& mesh, const Vec4& light);

// The point at canonical parameter x on adjacency edge e (0 at e.a, 1 at e.b), formed the same
// way wherever it is needed so loops and caps meet bit for bit.
Vec3 EdgePoint(const EdgeAdjacency& adjacency, std::uint32_t edge, double x);

// Where f changes sign along edge e for a side whose facing values at e.a and e.b are fa, fb
// (one > 0, the other <= 0): x = fa / (fa - fb), snapped to the end within 2^-40 of it. A loop
// passing a hair from a mesh vertex (f there a rounding error away from 0) then passes through
// it, instead of zigzagging among crossings whose positions round to collinear points (issue
// 16.4: such a zigzag puts loop vertices inside the strips' edges).
inline double CrossingParameter(double fa, double fb) {
    constexpr double kSnap = 0x1p-40;
    const double x = fa / (fa - fb);
    return x < kSnap ? 0.0 : (x > 1.0 - kSnap ? 1.0 : x);
}

// The loops do not depend on the input's windings: each connected component is wound
// consistently from its geometry first (OrientTriangles).
// Errors: "mesh.normals" (missing or wrong count, or a zero / non-finite normal), "light",
// "options.epsilon" (not > 0), "options.normal_offset" (< 0), "options.max_depth",
// "options.max_points" (the loops would pass it),
// "adjacency" (not built from this mesh), "mesh" (not orientable).
Result<SmoothSilhouette> ComputeSmoothSilhouette(const Mesh& mesh, const EdgeAdjacency& adjacency,
                                                 const Vec4& light, const SmoothOptions& options);

}  // namespace lixel::volumes
