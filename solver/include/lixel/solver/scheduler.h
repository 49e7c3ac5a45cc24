// The multi-map scheduler (DESIGN §4.5; Chong & Gortler §3-4): for one view and one light,
// which shadow maps exist, how big each is, how a shader picks among them, and what was left
// out and why.
#pragma once

#include <lixel/solver/extent_hull.h>
#include <lixel/solver/light_map.h>
#include <lixel/solver/mesh.h>
#include <lixel/solver/object_index.h>
#include <lixel/solver/plane_map.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace lixel {

// A plane of interest. `plane` is oriented: its normal points to the side the viewer cares about
// (a floor's normal points up), so the plane is lit when plane . light > 0.
struct PlaneOfInterest {
    std::string name;  // for the plan's explanations ("floor", "table")
    Vec4 plane = Vec4::Zero();
    // Empty: the infinite plane. Otherwise a convex polygon on the plane (a table top), vertices
    // counter-clockwise seen from the normal's side, world units; PlanShadowMaps refuses one
    // that is not, naming the vertex where it turns clockwise or winds again.
    std::vector<Vec3> polygon;
};

// A shadow caster or receiver. Bounds are required; the mesh, when present, lets the scheduler
// test whether casters lie inside needed rays and whether they are closed solids.
struct SceneObject {
    std::string name;
    Aabb bounds;
    const Mesh* mesh = nullptr;  // not owned; may be null
    bool closed = true;          // used when mesh is null
};

// The passes a request asks for; depth is always rendered.
struct PassRequest {
    bool second_depth = false;    // paper 003
    bool silhouette_map = false;  // paper 000
    bool volumes = false;         // papers 001, 002 (no map; planned as a pass over the view)
};

enum class MapRole { kPlane, kFallback, kCubeFace };
enum class Pass { kDepth, kSecondDepth, kSilhouetteMap };

// A map of the previous frame's plan (PlannedMap's role, indices, size and twist).
struct PreviousMap {
    MapRole role = MapRole::kPlane;
    int plane_index = -1;
    int cube_face = -1;
    int width = 0;   // lixels
    int height = 0;  // lixels
    double twist_radians = 0.0;
};

// Frame-coherent planning (docs/solver.md, docs/frames.md): from one frame to the next, plane
// maps keep their size while it still holds their needed rectangle with little waste (and a new
// size starts with headroom), the fallback keeps its size while little stretched, the plane
// scale moves in a few steps instead of continuously, and a twist stays unless another saves
// many lixels. The scheduler stays a function of its request: the previous frame's maps come
// with it.
// FrameCoherence's limits (the wire's too): previous maps, scale steps per octave.
inline constexpr int kMaxPreviousMaps = 64;
inline constexpr int kMaxScaleSteps = 64;

struct FrameCoherence {
    std::vector<PreviousMap> previous;  // empty on the first frame
    // A plane map keeps its previous size while its needed rectangle (guard band included) fits
    // inside it and fills at least 1 - waste_bound of it; a new size starts filled to
    // 1 - waste_bound / 2. The fallback keeps its size while the map the budget would fit
    // needs at most 1 / sqrt(1 - waste_bound) of it along either axis. (0, 1).
    double waste_bound = 0.25;
    // The plane scale is rounded down to 2^(-k / scale_steps), k whole; [1, 64].
    int scale_steps = 4;
    // A plane map keeps its previous twist unless the best twist saves this share of lixels;
    // [0, 1).
    double twist_saving = 0.1;
};

// Plane maps only where a shadow can fall (DESIGN §4.2; docs/solver.md, "Footprints"): a plane
// map holds the rectangles around its casters' footprints (the part of the plane in the shadow
// of some object's bounds), each an integer crop of the same plane-optimal matrix, and the rest
// of its needed polygon is lit by construction (LookupRule::unshadowed). Needs the request's
// objects: without them every plane map holds its whole needed polygon.
inline constexpr int kMaxFootprintRectangles = 16;

struct FootprintOptions {
    bool enabled = true;
    // Rectangles one plane's footprints are merged into, at most; [1, kMaxFootprintRectangles].
    int max_per_plane = 2;
    // Rectangles over all planes, at most; a plane that would pass it merges its footprints
    // further, and one left none keeps its whole map; [1, kMaxFootprintRectangles].
    int max_per_plan = 4;
};

// Plane maps when the budget cannot hold them all at one lixel per pixel.
enum class ScalePolicy {
    // The leading planes in priority order keep one lixel per pixel (exact there) and the rest
    // share one scale below it, when that is expected to cost less error than one scale for
    // all (their shadows' outline over their scale); else one scale for all (the default).
    kPriority,
    // One continuous scale for every plane map.
    kUniform,
    // One scale 1/k, k whole, for every plane map: each lixel covers k x k whole pixels.
    kInPhase,
};

struct PlanRequest {
    Mat4 viewer = Mat4::Identity();  // Mv, world -> clip, [0, 1] clip depth
    Viewport viewport;               // viewer pixels
    Vec4 light = Vec4::Zero();       // w != 0 point, w == 0 direction toward the light
    std::vector<SceneObject> objects;
    // Union of the objects' bounds when left empty (min > max); world units.
    Aabb scene_bounds{Vec3::Constant(1.0), Vec3::Constant(-1.0)};
    std::vector<PlaneOfInterest> planes;  // priority order: earlier planes win shared rays
    std::int64_t lixel_budget = 512 * 512;  // total over all maps, >= 1
    // Smallest map the fallback gets when it is needed (the paper gave it 128^2 of 512^2).
    std::int64_t fallback_floor = 128 * 128;
    int max_texture_size = kMaxImageSide;  // GL_MAX_TEXTURE_SIZE, [1, kMaxImageSide]
    PassRequest passes;
    FootprintOptions footprints;
    // Plane maps keep their lixel grids in phase with the viewer's pixels: twisted by right
    // angles only (crop.h CropOptions::in_phase), so that at scale 1 every pixel on the plane
    // reads the lixel of its own light ray. false: the paper's twists (§3: the floor/wall line
    // horizontal, else the rotation with the fewest lixels), a few lixels fewer, at the cost
    // of a drifting sampling offset (docs/solver.md, "Twist").
    bool in_phase = true;
    // How plane maps share a budget that cannot hold them all at one lixel per pixel; without
    // coherence (which keeps one stepped scale for all). Chosen by measured misclassification
    // on the planes over random rooms (docs/solver.md, "Budget policy").
    ScalePolicy scale_policy = ScalePolicy::kPriority;
    // Unset: every frame planned on its own (the tightest maps).
    std::optional<FrameCoherence> coherence;
    // Polled while planning (every few dozen objects, receivers or rays, and between steps):
    // true ends the plan with Error{"request", kPlanCancelled}, so a caller's deadline bounds a
    // plan over hundreds of thousands of objects. Empty: never.
    std::function<bool()> cancelled;
    // The object tree kept from one plan of a scene to the next (object_index.h): a caller that
    // plans the same objects frame after frame (a session) gives the same index to each plan,
    // which then refits its tree instead of building one. The plan is the same without it.
    std::shared_ptr<ObjectIndex> object_index;
};

inline constexpr const char* kPlanCancelled = "cancelled or past its deadline while planning";

// Lixels of border every planned map renders around its needed rays: the farthest tap of the
// widest filter past a needed point (PCF and second depth read r <= 4 texels past the lixel they
// fall in, silhouette maps one texel and its corners), plus one for rounding. Taps near a map's
// edge then read the scene's real depths there, not a copy of the edge texels.
inline constexpr int kGuardLixels = 2;

// How far past the needed rectangle (into the guard band) the lookup still accepts a point,
// lixels: needed images within 1e-6 lixel past an integer are snapped onto it by the crop, and
// float lixel coordinates in a shader stray by a few ulps of the map's side; half a lixel of
// real texels takes both in.
inline constexpr double kLookupMargin = 0.5;

// The lookup rule of one map (paper §3): a world point X belongs to this map when
// q = (M X).w > 0, its lixel (x, y) lies in the lookup rectangle (LookupRectangle: the map less
// its guard band, widened by kLookupMargin), every half-plane a x + b y + c >= 0 holds, and
// X lies in the world half-space world_limit . X >= 0 (X with w = 1). Maps are tried in plan
// order; the fallback accepts what is left. A rule that is `unshadowed` answers "lit" for what
// it accepts.
struct LookupRule {
    std::vector<Eigen::Vector3d> half_planes;  // (a, b, c) on lixel coordinates
    int guard = 0;  // lixels of guard band on every side; 0: the lookup takes the whole map
    // A world plane (a, b, c, d): a cascade's view depth limit (cascades.h); zero, which every
    // point satisfies, for every other map.
    Vec4 world_limit = Vec4::Zero();
    // No caster reaches the rays this rule accepts (a plane's needed polygon outside every
    // footprint, on or above the plane, which world_limit then is): a point it accepts is lit
    // with no lookup. Its map has no texels (lixels 0, no passes, nothing rendered or
    // streamed); the map's width, height and guard give the lookup rectangle as for any map.
    bool unshadowed = false;
};

// [x0, x1) x [y0, y1) in lixels, as (x0, y0, x1, y1): [0, width) x [0, height) without a guard
// band, else the map less `guard` lixels on every side, widened by kLookupMargin. Inline: the
// lookup asks for it at every point it tests.
inline Eigen::Vector4d LookupRectangle(const LightMap& map, const LookupRule& rule) noexcept {
    if (rule.guard <= 0) return {0.0, 0.0, double(map.width), double(map.height)};
    const double inset = rule.guard - kLookupMargin;
    return {inset, inset, map.width - inset, map.height - inset};
}

struct PlannedMap {
    MapRole role = MapRole::kPlane;
    int plane_index = -1;  // into PlanRequest::planes for kPlane
    int cube_face = -1;    // 0..5 (+x, -x, +y, -y, +z, -z) for kCubeFace
    std::string name;      // "plane floor", "fallback", "cube +x"
    LightMap map;
    std::vector<Pass> passes;
    LookupRule lookup;
    // The needed rays as a convex polygon in this map's lixel coordinates.
    std::vector<Vec2> needed_image;
    // For plane maps: the needed part of the plane in world units (a footprint rectangle's part
    // of it, empty when the rectangle holds only shadows out of view). The diagnostics: a plane
    // map's solve's; for the fallback and cube faces, the figures that hold for any map
    // (map_diagnostics.h: lixels per pixel, depth steps) at samples of the region kept for.
    std::vector<Vec3> needed_polygon;
    SolveDiagnostics diagnostics;
    double scale = 1.0;            // lixels per viewer pixel on the plane (plane maps), else 0
    std::string scale_reason;      // plane maps: why they got `scale`, in words
    // Plane maps: the crop's rotation against the plane-optimal image, counter-clockwise; 0 for
    // others.
    double twist_radians = 0.0;
    std::int64_t lixels = 0;       // width * height
    double expected_pixels = 0.0;  // viewer pixels expected to read this map
    // For the fallback and cube faces: what they are kept for, in words (the objects with parts
    // in view whose light rays no plane map holds). Empty for plane maps.
    std::string kept_for;
    // A plane map holding one rectangle of its plane's casters' footprints: an integer crop of
    // the same plane-optimal matrix as the plane's other rectangles and its unshadowed entry,
    // which follows them in the plan.
    bool footprint = false;
};

struct LeftOut {
    std::string item;    // "plane table", "fallback", "cube -y", "pass silhouette_map"
    std::string reason;  // why, in words
};

struct Plan {
    std::vector<PlannedMap> maps;  // in lookup order: planes by priority, then fallback or cubes
    std::vector<LeftOut> left_out;
    std::vector<std::string> warnings;  // e.g. second depth on open casters needs a bias
    ExtentHull hull;
    double plane_scale = 1.0;  // the plane maps' scale below 1 (ScalePolicy), else 1
    std::int64_t total_lixels = 0;  // never above PlanRequest::lixel_budget
    // Silhouette shadow volumes were asked for and some caster lies in the view's rays; they are
    // a pass over the view, not a map.
    bool volumes = false;
};

Result<Plan> PlanShadowMaps(const PlanRequest& request) noexcept;

// The CPU twin of the shader's map selection: the index into plan.maps of the first map whose
// lookup rule accepts world point `x` (homogeneous), or -1 when none does.
int LookupMap(const Plan& plan, const Vec4& x) noexcept;

// Whether one map's rule accepts `x` (the body of LookupMap's loop).
bool LookupAccepts(const PlannedMap& map, const Vec4& x) noexcept;

}  // namespace lixel
