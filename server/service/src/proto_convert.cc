// Messages <-> solver types, with validation that names the field.
#include <lixel/service/proto_convert.h>

#include <charconv>
#include <climits>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace lixel::service {

namespace {

std::string Index(const std::string& field, std::size_t i) {
    return field + "[" + std::to_string(i) + "]";
}

// The name of an object the request leaves unnamed: "object i". Formatted in place, as a plan of
// many unnamed objects builds one for each.
std::string DefaultObjectName(std::size_t i) {
    char text[32] = "object ";
    const auto end = std::to_chars(text + 7, text + sizeof text, i).ptr;
    return std::string(text, end);
}

// A name past kMaxNameBytes, refused naming it; the field is built only then.
Result<bool> CheckName(const std::string& name, const std::string& field) {
    if (name.size() <= kMaxNameBytes) return true;
    return Error{field, "has " + std::to_string(name.size()) + " bytes: a name may take at most " +
                            std::to_string(kMaxNameBytes)};
}

Result<bool> Finite(double value, const std::string& field) {
    if (!std::isfinite(value)) return Error{field, "is not finite"};
    return true;
}

// Whether a box is one a request may carry: finite, min <= max on every axis. The one test,
// which builds no field names, so a loop over many boxes names a field only for a box it
// refuses.
bool AcceptedBox(const Aabb& box) {
    return box.min.allFinite() && box.max.allFinite() && (box.min.array() <= box.max.array()).all();
}

// The box DecodeAabb accepts (present, AcceptedBox), or none.
std::optional<Aabb> AcceptedAabb(const v1::Aabb& box, bool present) {
    const Aabb out{Vec3(box.min().x(), box.min().y(), box.min().z()),
                   Vec3(box.max().x(), box.max().y(), box.max().z())};
    if (!present || !AcceptedBox(out)) return std::nullopt;
    return out;
}

// PlanRequest.packed_objects: six values a box, and names and closed flags that are empty or
// one an object. Refusals name the value (bounds[k]) or the array.
Result<std::vector<SceneObject>> DecodePackedObjects(const v1::PackedObjects& packed,
                                                     const std::string& field) {
    const auto values = static_cast<std::size_t>(packed.bounds_size());
    if (values % 6 != 0) {
        return Error{field + ".bounds", "has " + std::to_string(values) +
                                            " values: six an object (min x, y, z, max x, y, z)"};
    }
    const std::size_t count = values / 6;
    const auto names = static_cast<std::size_t>(packed.names_size());
    const auto closed = static_cast<std::size_t>(packed.closed_size());
    for (const auto& [given, what] : {std::pair{names, ".names"}, std::pair{closed, ".closed"}}) {
        if (given != 0 && given != count) {
            return Error{field + what, "has " + std::to_string(given) + " entries for " +
                                           std::to_string(count) +
                                           " objects: give none or one an object"};
        }
    }
    static constexpr const char* kAxes[3] = {"x", "y", "z"};
    std::vector<SceneObject> out(count);
    const double* v = packed.bounds().data();
    for (std::size_t i = 0; i < count; ++i, v += 6) {
        SceneObject& o = out[i];
        o.bounds = Aabb{Vec3(v[0], v[1], v[2]), Vec3(v[3], v[4], v[5])};
        if (!AcceptedBox(o.bounds)) {
            // Refused: which value, named (the names are built only here).
            for (int k = 0; k < 6; ++k) {
                if (!std::isfinite(v[k])) {
                    return Error{Index(field + ".bounds", 6 * i + k),
                                 std::string("is not finite (object ") + std::to_string(i) + "'s " +
                                     (k < 3 ? "min " : "max ") + kAxes[k % 3] + ")"};
                }
            }
            for (int a = 0; a < 3; ++a) {
                if (!(v[a] <= v[3 + a])) {
                    return Error{Index(field + ".bounds", 6 * i + 3 + a),
                                 "is below its min (object " + std::to_string(i) + "'s max " +
                                     kAxes[a] + ")"};
                }
            }
        }
        const std::string* name = names == 0 ? nullptr : &packed.names(static_cast<int>(i));
        if (name != nullptr && name->size() > kMaxNameBytes) {
            return CheckName(*name, Index(field + ".names", i)).error();
        }
        o.name = name == nullptr || name->empty() ? DefaultObjectName(i) : *name;
        o.closed = closed != 0 && packed.closed(static_cast<int>(i));
    }
    return out;
}

}  // namespace

Result<Mat4> DecodeMat4(const v1::Mat4& m, const std::string& field) {
    if (m.m_size() != 16) {
        return Error{field + ".m", "needs 16 values (column-major), got " +
                                       std::to_string(m.m_size())};
    }
    Mat4 out;
    for (int i = 0; i < 16; ++i) {
        if (auto ok = Finite(m.m(i), Index(field + ".m", i)); !ok) return ok.error();
        out(i % 4, i / 4) = m.m(i);
    }
    return out;
}

Result<Vec3> DecodeVec3(const v1::Vec3& v, const std::string& field) {
    const Vec3 out(v.x(), v.y(), v.z());
    if (!out.allFinite()) return Error{field, "is not finite"};
    return out;
}

Result<Vec4> DecodeVec4(const v1::Vec4& v, const std::string& field) {
    const Vec4 out(v.x(), v.y(), v.z(), v.w());
    if (!out.allFinite()) return Error{field, "is not finite"};
    return out;
}

Result<Aabb> DecodeAabb(const v1::Aabb& box, bool present, const std::string& field) {
    if (auto accepted = AcceptedAabb(box, present)) return *accepted;
    // Refused: which part, named (the names are built only here).
    if (!present) return Error{field, "is required"};
    auto min = DecodeVec3(box.min(), field + ".min");
    if (!min) return min.error();
    auto max = DecodeVec3(box.max(), field + ".max");
    if (!max) return max.error();
    if (!(min->array() <= max->array()).all()) return Error{field, "min exceeds max"};
    return Aabb{*min, *max};
}

Result<DecodedCamera> DecodeCamera(const v1::Camera& camera, bool present,
                                   const std::string& field) {
    if (!present) return Error{field, "is required"};
    auto viewer = DecodeMat4(camera.viewer(), field + ".viewer");
    if (!viewer) return viewer.error();
    for (const auto& [size, name] : {std::pair{camera.width(), ".width"},
                                     std::pair{camera.height(), ".height"}}) {
        if (size < 1 || size > static_cast<std::uint32_t>(kMaxImageSide)) {
            return Error{field + name, "must be in [1, " + std::to_string(kMaxImageSide) +
                                           "] pixels, got " + std::to_string(size)};
        }
    }
    return DecodedCamera{*viewer, Viewport{static_cast<int>(camera.width()),
                                           static_cast<int>(camera.height())}};
}

Result<CascadeOptions> DecodeCascades(const v1::Cascades& cascades, const std::string& field) {
    CascadeOptions options;
    if (cascades.count() != 0) {
        if (cascades.count() > static_cast<std::uint32_t>(kMaxCascades)) {
            return Error{field + ".count", "must be in [1, " + std::to_string(kMaxCascades) +
                                               "] (0 means " + std::to_string(kDefaultCascades) +
                                               "), got " + std::to_string(cascades.count())};
        }
        options.count = static_cast<int>(cascades.count());
    }
    if (cascades.has_lambda()) {
        if (!(cascades.lambda() >= 0.0 && cascades.lambda() <= 1.0)) {
            return Error{field + ".lambda",
                         "must be in [0, 1], got " + std::to_string(cascades.lambda())};
        }
        options.lambda = cascades.lambda();
    }
    if (cascades.has_stabilize()) options.stabilize = cascades.stabilize();
    return options;
}

Result<double> DecodeSmoothEpsilon(double epsilon, const std::string& field) {
    if (!(epsilon >= 0.0) || !std::isfinite(epsilon)) {
        return Error{field, "must be a finite length >= 0 (0 means 1e-3)"};
    }
    return epsilon == 0.0 ? kDefaultSmoothEpsilon : epsilon;
}

Result<volumes::SmoothOptions> DecodeSmoothOptions(double epsilon,
                                                   std::optional<double> normal_offset,
                                                   const std::string& prefix) {
    volumes::SmoothOptions options;
    auto decoded = DecodeSmoothEpsilon(epsilon, prefix + "epsilon");
    if (!decoded) return decoded.error();
    options.epsilon = *decoded;
    options.normal_offset = normal_offset.value_or(kPaperOffsetPerEpsilon * options.epsilon);
    if (!(options.normal_offset >= 0.0) || !std::isfinite(options.normal_offset)) {
        return Error{prefix + "normal_offset", "must be a finite length >= 0"};
    }
    return options;
}

Result<volumes::SmoothOptions> DecodeSmoothVolumes(const v1::SmoothVolumes& smooth,
                                                   const std::string& field) {
    return DecodeSmoothOptions(smooth.epsilon(),
                               smooth.has_normal_offset() ? std::optional(smooth.normal_offset())
                                                          : std::nullopt,
                               field + ".");
}

Result<Vec4> DecodeLight(const v1::Light& light, bool present, const std::string& field) {
    if (!present || !light.has_position()) return Error{field + ".position", "is required"};
    auto position = DecodeVec4(light.position(), field + ".position");
    if (!position) return position.error();
    if (position->isZero(0.0)) return Error{field + ".position", "is zero: not a light"};
    return *position;
}

Result<bool> CheckConvexCounterClockwise(const std::vector<Vec3>& polygon, const Vec3& normal,
                                         const std::string& field) {
    const std::size_t n = polygon.size();
    if (n == 0) return true;
    // Every turn to the left of the plane's normal, and the turns adding up to one full turn
    // (a pentagram turns left at every corner but winds twice).
    double winding = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
        const Vec3 a = polygon[(k + 1) % n] - polygon[k];
        const Vec3 b = polygon[(k + 2) % n] - polygon[(k + 1) % n];
        const double turn = a.cross(b).dot(normal);
        const double scale = a.norm() * b.norm() * normal.norm();
        if (!(turn > 1e-12 * scale)) {
            return Error{Index(field, static_cast<int>((k + 1) % n)),
                         turn < -1e-12 * scale
                             ? "turns clockwise about the plane's normal: the polygon must be "
                               "convex and counter-clockwise seen from the normal's side"
                             : "is collinear with its neighbours or repeats one: the polygon must "
                               "be strictly convex"};
        }
        winding += std::atan2(turn / normal.norm(), a.dot(b));
    }
    if (std::abs(winding - 2.0 * std::numbers::pi) > 1e-6) {
        return Error{field, "winds " + std::to_string(winding / (2.0 * std::numbers::pi)) +
                                " times around its centre: a convex polygon winds once"};
    }
    return true;
}

Result<PlaneOfInterest> DecodePlane(const v1::PlaneOfInterest& plane, std::size_t index,
                                    const std::string& field) {
    PlaneOfInterest out;
    if (auto named = CheckName(plane.name(), field + ".name"); !named) return named.error();
    out.name = plane.name().empty() ? std::to_string(index) : plane.name();
    if (!plane.has_plane()) return Error{field + ".plane", "is required"};
    auto p = DecodeVec4(plane.plane(), field + ".plane");
    if (!p) return p.error();
    if (!(p->head<3>().norm() > 0.0)) {
        return Error{field + ".plane", "normal (a, b, c) is zero: not a plane"};
    }
    out.plane = *p;
    if (plane.polygon_size() != 0 && plane.polygon_size() < 3) {
        return Error{field + ".polygon", "needs 0 or at least 3 vertices"};
    }
    if (static_cast<std::size_t>(plane.polygon_size()) > kMaxPolygonVertices) {
        return Error{field + ".polygon", "has more than " + std::to_string(kMaxPolygonVertices) +
                                             " vertices"};
    }
    for (int k = 0; k < plane.polygon_size(); ++k) {
        auto v = DecodeVec3(plane.polygon(k), Index(field + ".polygon", k));
        if (!v) return v.error();
        out.polygon.push_back(*v);
    }
    if (auto convex = CheckConvexCounterClockwise(out.polygon, out.plane.head<3>(),
                                                  field + ".polygon");
        !convex) {
        return convex.error();
    }
    return out;
}

namespace {

// FrameCoherence (lixel.proto): zeros mean the defaults, each refusal names its field.
Result<FrameCoherence> DecodeCoherence(const v1::FrameCoherence& message,
                                       const std::string& field) {
    FrameCoherence out;
    out.waste_bound = message.waste_bound() == 0.0 ? 0.25 : message.waste_bound();
    if (!(out.waste_bound > 0.0 && out.waste_bound < 1.0)) {
        return Error{field + ".waste_bound", "must be in (0, 1) (0 means 0.25), got " +
                                                 std::to_string(message.waste_bound())};
    }
    const std::uint32_t steps = message.scale_steps() == 0 ? 4 : message.scale_steps();
    if (steps > static_cast<std::uint32_t>(kMaxScaleSteps)) {
        return Error{field + ".scale_steps", "must be in [1, 64] (0 means 4), got " +
                                                 std::to_string(message.scale_steps())};
    }
    out.scale_steps = static_cast<int>(steps);
    out.twist_saving = message.has_twist_saving() ? message.twist_saving() : 0.1;
    if (!(out.twist_saving >= 0.0 && out.twist_saving < 1.0)) {
        return Error{field + ".twist_saving", "must be in [0, 1) (unset means 0.1), got " +
                                                  std::to_string(message.twist_saving())};
    }
    if (message.previous_size() > kMaxPreviousMaps) {
        return Error{field + ".previous", "has " + std::to_string(message.previous_size()) +
                                              " maps, at most 64"};
    }
    for (int i = 0; i < message.previous_size(); ++i) {
        const v1::PreviousMap& p = message.previous(i);
        const std::string path = Index(field + ".previous", i);
        PreviousMap map;
        switch (p.role()) {
            case v1::MAP_ROLE_PLANE: map.role = MapRole::kPlane; break;
            case v1::MAP_ROLE_FALLBACK: map.role = MapRole::kFallback; break;
            case v1::MAP_ROLE_CUBE_FACE: map.role = MapRole::kCubeFace; break;
            default:
                return Error{path + ".role", "unknown value " + std::to_string(p.role())};
        }
        map.plane_index = p.plane_index();
        map.cube_face = p.cube_face();
        for (const auto& [side, name] : {std::pair{p.width(), ".width"},
                                         std::pair{p.height(), ".height"}}) {
            if (side < 1 || side > static_cast<std::uint32_t>(kMaxImageSide)) {
                return Error{path + name, "must be in [1, " + std::to_string(kMaxImageSide) +
                                              "], got " + std::to_string(side)};
            }
        }
        map.width = static_cast<int>(p.width());
        map.height = static_cast<int>(p.height());
        if (auto ok = Finite(p.twist_radians(), path + ".twist_radians"); !ok) return ok.error();
        map.twist_radians = p.twist_radians();
        out.previous.push_back(map);
    }
    return out;
}

}  // namespace

SceneRecord MakeSceneRecord(scene::Scene scene) {
    SceneRecord record;
    record.default_viewer = scene.camera.Viewer();
    record.default_viewport = scene.camera.viewport;
    std::uint64_t bytes = sizeof(SceneRecord);
    for (const Mesh& m : scene.meshes) {
        bytes += m.positions.size() * sizeof(Eigen::Vector3f) +
                 m.normals.size() * sizeof(Eigen::Vector3f) + m.indices.size() * 4 +
                 m.name.size() + AdjacencyBytesBound(m);
    }
    record.bytes = bytes;
    record.mesh_bounds = scene.MeshBounds();
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        const auto [it, fresh] =
            record.mesh_index.emplace(scene.meshes[m].name, static_cast<std::uint32_t>(m));
        if (!fresh) it->second = kAmbiguousMesh;
    }
    record.scene = std::move(scene);
    return record;
}

Result<PlanRequest> DecodePlanRequest(const v1::PlanRequest& message, const SceneRecord* record,
                                      const std::string& field,
                                      std::vector<MeshInstance>* instances) {
    const scene::Scene* scene = record != nullptr ? &record->scene : nullptr;
    PlanRequest out;
    if (message.has_camera()) {
        auto camera = DecodeCamera(message.camera(), true, field + ".camera");
        if (!camera) return camera.error();
        out.viewer = camera->viewer;
        out.viewport = camera->viewport;
    } else if (record != nullptr) {
        out.viewer = record->default_viewer;
        out.viewport = record->default_viewport;
    } else {
        return Error{field + ".camera", "is required"};
    }
    if (message.has_light()) {
        auto light = DecodeLight(message.light(), true, field + ".light");
        if (!light) return light.error();
        out.light = *light;
    } else if (scene != nullptr) {
        out.light = scene->light;
    } else {
        return Error{field + ".light", "is required"};
    }
    for (int i = 0; i < message.planes_size(); ++i) {
        auto plane = DecodePlane(message.planes(i), i, Index(field + ".planes", i));
        if (!plane) return plane.error();
        out.planes.push_back(*plane);
    }
    if (out.planes.empty() && scene != nullptr) out.planes = scene->planes;

    if (message.instances_size() > 0 && (record == nullptr || instances == nullptr)) {
        return Error{field + ".instances", record == nullptr
                                               ? "need a scene_id: instances place its meshes"
                                               : "not taken by this call"};
    }
    if (scene != nullptr && message.has_packed_objects()) {
        // A new field, so nothing relies on it being ignored the way `objects` is with a scene.
        return Error{field + ".packed_objects",
                     "given with scene_id: the scene's meshes are the objects (instances place "
                     "them)"};
    }
    if (scene != nullptr && message.instances_size() > 0) {
        auto placed = DecodeInstances(message.instances(), *record, field + ".instances");
        if (!placed) return placed.error();
        *instances = std::move(placed).value();
        out.objects = scene::InstanceObjects(scene->meshes, record->mesh_bounds, *instances);
        // The objects are the instances that cast or receive: none is the instances' doing,
        // named as such (the solver would name its own "objects").
        if (out.objects.empty()) {
            return Error{field + ".instances",
                         "none casts or receives: nothing bounds the scene (give some instance "
                         "casts or receives)"};
        }
    } else if (scene != nullptr) {
        if (instances != nullptr) instances->clear();
        out.objects = scene->Objects();
    } else if (message.has_packed_objects()) {
        if (message.objects_size() > 0) {
            return Error{field + ".packed_objects", "given with objects: give one of the two"};
        }
        auto packed = DecodePackedObjects(message.packed_objects(), field + ".packed_objects");
        if (!packed) return packed.error();
        out.objects = std::move(packed).value();
        if (out.objects.empty()) {
            return Error{field + ".packed_objects",
                         "holds no object and no scene_id: nothing bounds the scene"};
        }
    } else {
        out.objects.reserve(static_cast<std::size_t>(message.objects_size()));
        for (int i = 0; i < message.objects_size(); ++i) {
            const auto& o = message.objects(i);
            // The field's name only for a box DecodeAabb refuses: building it for every object
            // cost a tenth of a 10 000-object Plan call.
            const std::optional<Aabb> bounds = AcceptedAabb(o.bounds(), o.has_bounds());
            if (!bounds) {
                const std::string path = Index(field + ".objects", i) + ".bounds";
                return DecodeAabb(o.bounds(), o.has_bounds(), path).error();
            }
            if (o.name().size() > kMaxNameBytes) {
                return CheckName(o.name(), Index(field + ".objects", i) + ".name").error();
            }
            SceneObject& object = out.objects.emplace_back();
            object.bounds = *bounds;
            object.name = o.name().empty() ? DefaultObjectName(i) : o.name();
            object.closed = o.closed();
        }
        if (out.objects.empty()) {
            return Error{field + ".objects", "empty and no scene_id: nothing bounds the scene"};
        }
    }

    const std::uint64_t budget = message.lixel_budget() == 0 ? 512 * 512 : message.lixel_budget();
    if (budget > kMaxLixelBudget) {
        return Error{field + ".lixel_budget", "must be at most 2^28, got " +
                                                  std::to_string(message.lixel_budget())};
    }
    out.lixel_budget = static_cast<std::int64_t>(budget);
    const std::uint64_t floor = message.fallback_floor() == 0 ? 128 * 128 : message.fallback_floor();
    if (floor > budget) {
        // Also when the request leaves the floor at its default and asks for a smaller budget:
        // say which value it is, so the client knows what to set.
        return Error{field + ".fallback_floor",
                     (message.fallback_floor() == 0 ? "the default 16384 (128 x 128)"
                                                    : std::to_string(floor)) +
                         " exceeds the lixel budget " + std::to_string(budget) +
                         ": give a fallback_floor at most the budget"};
    }
    out.fallback_floor = static_cast<std::int64_t>(floor);
    const std::uint32_t max_side =
        message.max_texture_size() == 0 ? kMaxImageSide : message.max_texture_size();
    if (max_side > static_cast<std::uint32_t>(kMaxImageSide)) {
        return Error{field + ".max_texture_size", "must be in [1, 16384]"};
    }
    out.max_texture_size = static_cast<int>(max_side);
    out.passes.second_depth = message.passes().second_depth();
    out.passes.silhouette_map = message.passes().silhouette_map();
    out.passes.volumes = message.passes().volumes();
    out.in_phase = !message.free_twist();
    switch (message.scale_policy()) {
        case v1::SCALE_POLICY_PRIORITY:
            out.scale_policy = ScalePolicy::kPriority;
            break;
        case v1::SCALE_POLICY_UNIFORM:
            out.scale_policy = ScalePolicy::kUniform;
            break;
        case v1::SCALE_POLICY_IN_PHASE:
            out.scale_policy = ScalePolicy::kInPhase;
            break;
        default:
            return Error{field + ".scale_policy",
                         "is not a ScalePolicy (got " + std::to_string(message.scale_policy()) +
                             ")"};
    }
    if (message.has_footprints()) {
        const v1::Footprints& f = message.footprints();
        out.footprints.enabled = !f.disabled();
        const auto limit = [&](std::uint32_t value, int fallback, const char* name,
                               int& into) -> Result<bool> {
            const std::uint32_t v = value == 0 ? static_cast<std::uint32_t>(fallback) : value;
            if (v > static_cast<std::uint32_t>(kMaxFootprintRectangles)) {
                return Error{field + ".footprints." + name,
                             "must be in [1, " + std::to_string(kMaxFootprintRectangles) +
                                 "], got " + std::to_string(value)};
            }
            into = static_cast<int>(v);
            return true;
        };
        if (auto ok = limit(f.max_per_plane(), FootprintOptions{}.max_per_plane, "max_per_plane",
                            out.footprints.max_per_plane);
            !ok) {
            return ok.error();
        }
        if (auto ok = limit(f.max_per_plan(), FootprintOptions{}.max_per_plan, "max_per_plan",
                            out.footprints.max_per_plan);
            !ok) {
            return ok.error();
        }
    }
    if (message.has_coherence()) {
        auto coherence = DecodeCoherence(message.coherence(), field + ".coherence");
        if (!coherence) return coherence.error();
        out.coherence = std::move(*coherence);
    }
    return out;
}

Result<SceneRecord> DecodeScene(const v1::Scene& message, const std::string& field) {
    scene::Scene scene;
    scene.name = message.name();
    if (message.meshes_size() == 0) return Error{field + ".meshes", "is empty: no geometry"};
    for (int i = 0; i < message.meshes_size(); ++i) {
        const v1::Mesh& m = message.meshes(i);
        const std::string path = Index(field + ".meshes", i);
        if (m.positions_size() == 0 || m.positions_size() % 3 != 0) {
            return Error{path + ".positions", "needs a non-zero multiple of 3 values, got " +
                                                  std::to_string(m.positions_size())};
        }
        if (m.normals_size() != 0 && m.normals_size() != m.positions_size()) {
            return Error{path + ".normals", "needs one normal per vertex or none"};
        }
        if (m.indices_size() == 0 || m.indices_size() % 3 != 0) {
            return Error{path + ".indices", "needs a non-zero multiple of 3 indices, got " +
                                                std::to_string(m.indices_size())};
        }
        Mesh mesh;
        mesh.name = m.name().empty() ? "mesh " + std::to_string(i) : m.name();
        mesh.closed = m.closed();
        const int vertices = m.positions_size() / 3;
        for (int v = 0; v < vertices; ++v) {
            const Eigen::Vector3f p(m.positions(3 * v), m.positions(3 * v + 1),
                                    m.positions(3 * v + 2));
            if (!p.allFinite()) return Error{Index(path + ".positions", 3 * v), "is not finite"};
            mesh.positions.push_back(p);
            if (m.normals_size() != 0) {
                const Eigen::Vector3f n(m.normals(3 * v), m.normals(3 * v + 1),
                                        m.normals(3 * v + 2));
                if (!n.allFinite()) return Error{Index(path + ".normals", 3 * v), "is not finite"};
                if (!(std::abs(n.norm() - 1.0f) <= 1e-3f)) {
                    return Error{Index(path + ".normals", 3 * v),
                                 "has length " + std::to_string(n.norm()) +
                                     ": normals must be of unit length (within 1e-3) or absent"};
                }
                mesh.normals.push_back(n);
            }
        }
        for (int k = 0; k < m.indices_size(); ++k) {
            if (m.indices(k) >= static_cast<std::uint32_t>(vertices)) {
                return Error{Index(path + ".indices", k),
                             "is " + std::to_string(m.indices(k)) + ", out of range for " +
                                 std::to_string(vertices) + " vertices"};
            }
            mesh.indices.push_back(m.indices(k));
        }
        scene.meshes.push_back(std::move(mesh));
    }
    for (int i = 0; i < message.planes_size(); ++i) {
        auto plane = DecodePlane(message.planes(i), i, Index(field + ".planes", i));
        if (!plane) return plane.error();
        scene.planes.push_back(*plane);
    }
    if (message.has_default_light()) {
        auto light = DecodeLight(message.default_light(), true, field + ".default_light");
        if (!light) return light.error();
        scene.light = *light;
    }
    SceneRecord record = MakeSceneRecord(std::move(scene));
    if (message.has_default_camera()) {
        auto camera = DecodeCamera(message.default_camera(), true, field + ".default_camera");
        if (!camera) return camera.error();
        record.default_viewer = camera->viewer;
        record.default_viewport = camera->viewport;
        record.scene.camera.viewport = camera->viewport;
    }
    return record;
}

void EncodePackedObjects(std::span<const SceneObject> objects, v1::PackedObjects* out) {
    out->Clear();
    // A message holds at most 2 GiB, far fewer than INT_MAX / 6 boxes: the reserve is a hint.
    if (objects.size() <= static_cast<std::size_t>(INT_MAX / 6)) {
        out->mutable_bounds()->Reserve(static_cast<int>(6 * objects.size()));
    }
    bool named = false, closed = false;
    for (const SceneObject& o : objects) {
        for (const Vec3& corner : {o.bounds.min, o.bounds.max}) {
            for (int a = 0; a < 3; ++a) out->add_bounds(corner(a));
        }
        named = named || !o.name.empty();
        closed = closed || o.closed;
    }
    for (const SceneObject& o : objects) {
        if (named) out->add_names(o.name);
        if (closed) out->add_closed(o.closed);
    }
}

void EncodeMat4(const Mat4& m, v1::Mat4* out) {
    out->clear_m();
    for (int i = 0; i < 16; ++i) out->add_m(m(i % 4, i / 4));
}

void EncodeVec3(const Vec3& v, v1::Vec3* out) {
    out->set_x(v.x());
    out->set_y(v.y());
    out->set_z(v.z());
}

void EncodeVec4(const Vec4& v, v1::Vec4* out) {
    out->set_x(v.x());
    out->set_y(v.y());
    out->set_z(v.z());
    out->set_w(v.w());
}

void EncodeLightMap(const LightMap& map, v1::LightMap* out) {
    EncodeMat4(map.matrix, out->mutable_matrix());
    out->set_width(static_cast<std::uint32_t>(map.width));
    out->set_height(static_cast<std::uint32_t>(map.height));
    EncodeMat4(GlProjection(map), out->mutable_gl_projection());
}

void EncodeDiagnostics(const SolveDiagnostics& d, v1::SolveDiagnostics* out) {
    out->set_residual_lixels(d.residual_lixels);
    out->set_residual_lixels_float(d.residual_lixels_float);
    out->set_conditioning(d.conditioning);
    out->set_horizon_in_view(d.horizon_in_view);
    out->set_sign(d.sign);
    out->set_depth_resolution(d.depth_resolution);
    out->set_depth_step_nearest(d.depth_step_nearest);
    out->set_depth_step_farthest(d.depth_step_farthest);
    out->set_lixels_per_pixel_min(d.lixels_per_pixel_min);
    out->set_lixels_per_pixel_max(d.lixels_per_pixel_max);
}

void EncodePlan(const Plan& plan, v1::PlanResponse* out) {
    for (const PlannedMap& m : plan.maps) {
        v1::PlannedMap* pm = out->add_maps();
        pm->set_name(m.name);
        pm->set_role(m.role == MapRole::kPlane      ? v1::MAP_ROLE_PLANE
                     : m.role == MapRole::kFallback ? v1::MAP_ROLE_FALLBACK
                                                    : v1::MAP_ROLE_CUBE_FACE);
        pm->set_plane_index(m.plane_index);
        pm->set_cube_face(m.cube_face);
        EncodeLightMap(m.map, pm->mutable_map());
        for (Pass p : m.passes) {
            pm->add_passes(p == Pass::kDepth         ? v1::PASS_DEPTH
                           : p == Pass::kSecondDepth ? v1::PASS_SECOND_DEPTH
                                                     : v1::PASS_SILHOUETTE_MAP);
        }
        for (const Eigen::Vector3d& h : m.lookup.half_planes) {
            v1::HalfPlane* hp = pm->add_lookup();
            hp->set_a(h.x());
            hp->set_b(h.y());
            hp->set_c(h.z());
        }
        pm->set_scale(m.scale);
        pm->set_scale_reason(m.scale_reason);
        pm->set_lixels(static_cast<std::uint64_t>(m.lixels));
        pm->set_expected_pixels(m.expected_pixels);
        pm->set_kept_for(m.kept_for);
        pm->set_guard(static_cast<std::uint32_t>(m.lookup.guard));
        pm->set_twist_radians(m.twist_radians);
        pm->set_footprint(m.footprint);
        pm->set_unshadowed(m.lookup.unshadowed);
        if (!m.lookup.world_limit.isZero()) {
            const Vec4& h = m.lookup.world_limit;
            v1::Vec4* limit = pm->mutable_world_limit();
            limit->set_x(h.x());
            limit->set_y(h.y());
            limit->set_z(h.z());
            limit->set_w(h.w());
        }
        if (m.diagnostics.samples > 0) EncodeDiagnostics(m.diagnostics, pm->mutable_diagnostics());
    }
    for (const LeftOut& l : plan.left_out) {
        v1::LeftOut* lo = out->add_left_out();
        lo->set_item(l.item);
        lo->set_reason(l.reason);
    }
    for (const std::string& w : plan.warnings) out->add_warnings(w);
    out->set_total_lixels(static_cast<std::uint64_t>(plan.total_lixels));
    out->set_plane_scale(plan.plane_scale);
    out->set_volumes(plan.volumes);
}

void EncodeScene(const SceneRecord& record, v1::Scene* out) {
    const scene::Scene& scene = record.scene;
    out->set_name(scene.name);
    for (const Mesh& mesh : scene.meshes) {
        v1::Mesh* m = out->add_meshes();
        m->set_name(mesh.name);
        m->set_closed(mesh.closed);
        for (const Eigen::Vector3f& p : mesh.positions) {
            m->add_positions(p.x());
            m->add_positions(p.y());
            m->add_positions(p.z());
        }
        for (const Eigen::Vector3f& n : mesh.normals) {
            m->add_normals(n.x());
            m->add_normals(n.y());
            m->add_normals(n.z());
        }
        for (std::uint32_t i : mesh.indices) m->add_indices(i);
    }
    for (const PlaneOfInterest& p : scene.planes) {
        v1::PlaneOfInterest* pp = out->add_planes();
        pp->set_name(p.name);
        EncodeVec4(p.plane, pp->mutable_plane());
        for (const Vec3& v : p.polygon) EncodeVec3(v, pp->add_polygon());
    }
    EncodeVec4(scene.light, out->mutable_default_light()->mutable_position());
    v1::Camera* camera = out->mutable_default_camera();
    EncodeMat4(record.default_viewer, camera->mutable_viewer());
    camera->set_width(static_cast<std::uint32_t>(record.default_viewport.width));
    camera->set_height(static_cast<std::uint32_t>(record.default_viewport.height));
}

}  // namespace lixel::service
