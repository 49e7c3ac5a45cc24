// OBJ meshes from bytes in memory (mesh_parsing.h), through tinyobjloader's callback parser:
// the parser hands over each line's numbers and this file keeps only what the budget allows,
// so no file, however it is written, makes the parser itself hold the scene. The numbers are
// read strictly once before the parser runs, since it keeps whatever it could read of a token.
#include <lixel/scene/mesh_builders.h>
#include <lixel/scene/mesh_parsing.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <istream>
#include <map>
#include <optional>
#include <streambuf>
#include <utility>

namespace lixel::scene {
namespace {

// tinyobjloader reads each number as far as it can and keeps what it read: `nan`, `inf`, `0x1p3`
// and `abc` become 0, `1.2.3` becomes 1.2, a missing coordinate takes a default, and face
// indices go through atoi, so `4294967300` wraps to vertex 4. The numbers the builder keeps are
// therefore read first, strictly, by the functions below; a token they pass is one tinyobjloader
// reads whole (its value may differ in the last bit: tinyobjloader's arithmetic is not correctly
// rounded, and the builder refuses what it makes non-finite).

bool IsObjSpace(char c) { return c == ' ' || c == '\t'; }

// The next token of `rest` as tinyobjloader delimits one: spaces and tabs skipped, then up to
// the next space or tab (a line holds no '\r' or '\n' by then).
std::string_view NextToken(std::string_view& rest) {
    std::size_t begin = 0;
    while (begin < rest.size() && IsObjSpace(rest[begin])) ++begin;
    std::size_t end = begin;
    while (end < rest.size() && !IsObjSpace(rest[end])) ++end;
    const std::string_view token = rest.substr(begin, end - begin);
    rest.remove_prefix(end);
    return token;
}

// A token for an error message: its first 32 bytes, those outside printable ASCII (and quotes
// and backslashes) written \xNN, since the bytes are an attacker's.
std::string Quoted(std::string_view token) {
    constexpr std::size_t kShown = 32;
    std::string out = "\"";
    for (const char c : token.substr(0, kShown)) {
        const auto byte = static_cast<unsigned char>(c);
        if (byte >= 0x20 && byte < 0x7f && c != '"' && c != '\\') {
            out += c;
        } else {
            char hex[5];
            std::snprintf(hex, sizeof hex, "\\x%02x", byte);
            out += hex;
        }
    }
    out += token.size() > kShown ? "...\"" : "\"";
    return out;
}

// tinyobjloader allows one leading '+', std::from_chars none: drop it, unless another sign
// follows (`+-1`, which tinyobjloader reads as 0), so that from_chars refuses the token.
std::string_view WithoutPlus(std::string_view token) {
    if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
    return token;
}

// Why `token` is not a coordinate tinyobjloader reads exactly, or nullptr. from_chars' general
// format is the decimal grammar tinyobjloader reads in full (sign, digits, point, exponent),
// never hex, plus `nan` and `inf`, which the finiteness test refuses. tinyobjloader keeps a
// float, so a double past a float's range is refused as well.
const char* CoordinateProblem(std::string_view token) {
    token = WithoutPlus(token);
    const char* const end = token.data() + token.size();
    double value = 0;
    const auto [stop, ec] = std::from_chars(token.data(), end, value);
    if (ec == std::errc::result_out_of_range) {
        // Below the least double (1e-400) a coordinate is 0 to a float, as tinyobjloader reads
        // it; above the largest it is refused. strtod reads the same decimal grammar and tells
        // the two apart (only such tokens are copied).
        const std::string copy(token);
        const double read = std::strtod(copy.c_str(), nullptr);
        return std::abs(read) < 1.0 ? nullptr : "is out of a 32-bit float's range";
    }
    if (ec != std::errc{} || stop != end || !std::isfinite(value)) {
        return "is not a finite decimal number";
    }
    if (!std::isfinite(static_cast<float>(value))) return "is out of a 32-bit float's range";
    return nullptr;
}

// Why one number of a face corner is not an index tinyobjloader's atoi reads exactly, or
// nullptr: an integer that fits an int, and not 0, which OBJ never writes and tinyobjloader
// hands over as "no index".
const char* IndexProblem(std::string_view part) {
    part = WithoutPlus(part);
    const char* const end = part.data() + part.size();
    int value = 0;
    const auto [stop, ec] = std::from_chars(part.data(), end, value);
    if (ec == std::errc::result_out_of_range) return "is out of range";
    if (ec != std::errc{} || stop != end) return "is not an integer";
    if (value == 0) return "is out of range (OBJ counts from 1, or back from -1)";
    return nullptr;
}

// Why a face corner is not i, i/j, i//k or i/j/k with exact indices, or empty.
std::string CornerProblem(std::string_view corner) {
    const auto malformed = [corner] {
        return "face corner " + Quoted(corner) + " is not i, i/j, i//k or i/j/k";
    };
    std::string_view parts[3];
    std::size_t last = 0;
    std::string_view rest = corner;
    for (std::size_t slash = rest.find('/'); slash != rest.npos; slash = rest.find('/')) {
        if (last == 2) return malformed();
        parts[last++] = rest.substr(0, slash);
        rest.remove_prefix(slash + 1);
    }
    parts[last] = rest;
    for (std::size_t k = 0; k <= last; ++k) {
        const bool skipped_texture = k == 1 && last == 2;  // i//k
        if (parts[k].empty() && skipped_texture) continue;
        if (parts[k].empty()) return malformed();
        if (const char* why = IndexProblem(parts[k])) {
            return "face index " + Quoted(parts[k]) + " " + why;
        }
    }
    return {};
}

// Why a `v` or `vn` line's x, y and z are not read exactly, or empty. What follows z (a `v`
// line's w, or the colour extension's r g b) is read into values the builder never uses.
std::string CoordinatesProblem(std::string_view rest, const char* what) {
    for (int axis = 0; axis < 3; ++axis) {
        const std::string_view token = NextToken(rest);
        if (token.empty()) {
            return std::string(what) + " needs 3 coordinates, the line has " + std::to_string(axis);
        }
        if (const char* why = CoordinateProblem(token)) {
            return std::string(what) + " coordinate " + Quoted(token) + " " + why;
        }
    }
    return {};
}

// Why a line's numbers would be misread, or empty. The keywords are matched as tinyobjloader's
// LoadObjWithCallback matches them (leading spaces skipped, the keyword, a space or tab); only
// the lines whose numbers the builder keeps are read: `vt` has no callback here, and names and
// statements tinyobjloader skips hold no numbers it converts.
std::string LineProblem(std::string_view line) {
    while (!line.empty() && IsObjSpace(line.front())) line.remove_prefix(1);
    const auto starts = [line](std::string_view keyword) {
        return line.size() > keyword.size() && line.starts_with(keyword) &&
               IsObjSpace(line[keyword.size()]);
    };
    if (starts("v")) return CoordinatesProblem(line.substr(2), "vertex");
    if (starts("vn")) return CoordinatesProblem(line.substr(3), "normal");
    if (!starts("f")) return {};
    std::string_view rest = line.substr(2);
    for (std::string_view corner = NextToken(rest); !corner.empty(); corner = NextToken(rest)) {
        if (std::string why = CornerProblem(corner); !why.empty()) return why;
    }
    return {};
}

// The budget's own error (a limit, a cancel) under the source's field.
Error StoppedError(const MeshSource& source, const DecodeBudget& budget) {
    return Error{source.field + ": " + budget.error().field, budget.error().reason};
}

// The first line tinyobjloader would misread, named by its 1-based number, or nothing. Lines
// are split as tinyobjloader's safeGetline splits them ("\n", "\r\n" or a lone "\r") and end
// at their first NUL, where its C-string readers stop. One pass, nothing copied; the budget's
// cancellation is polled once a line.
std::optional<Error> FirstMisreadLine(std::string_view text, const MeshSource& source,
                                      DecodeBudget& budget) {
    for (std::size_t number = 1; !text.empty(); ++number) {
        std::size_t end = 0;
        while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
        std::string_view line = text.substr(0, end);
        line = line.substr(0, line.find('\0'));
        const bool crlf = end + 1 < text.size() && text[end] == '\r' && text[end + 1] == '\n';
        text.remove_prefix(std::min(text.size(), end + (crlf ? 2 : 1)));
        if (budget.Cancelled()) return StoppedError(source, budget);
        if (std::string why = LineProblem(line); !why.empty()) {
            return Error{source.field, "line " + std::to_string(number) + ": " + why};
        }
    }
    return std::nullopt;
}

// An istream over bytes that stay where they are (no copy of the upload).
class ViewBuffer final : public std::streambuf {
public:
    explicit ViewBuffer(std::string_view bytes) {
        char* begin = const_cast<char*>(bytes.data());
        setg(begin, begin, begin + bytes.size());
    }
};

// Thrown from a callback to leave the parser at once (an error, a limit, a cancel); the
// parser holds only its line buffers, which unwinding frees.
struct StopParsing {};

class ObjBuilder;

// Materials play no part in shadows, and an uploaded `mtllib` names a file of the server's
// (`mtllib ../../dev/zero`): read nothing, whatever the name; the builder decides whether the
// line itself is an error.
class RefuseMaterials final : public tinyobj::MaterialReader {
public:
    explicit RefuseMaterials(ObjBuilder& builder) : builder_(builder) {}
    bool operator()(const std::string& name, std::vector<tinyobj::material_t>*,
                    std::map<std::string, int>*, std::string* warn, std::string*) override;

private:
    ObjBuilder& builder_;
};

struct Corner {
    std::uint32_t position;
    std::int64_t normal;  // -1: none
};

class ObjBuilder {
public:
    ObjBuilder(const MeshSource& source, DecodeBudget& budget)
        : source_(source), budget_(budget) {}

    static void OnVertex(void* self, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z,
                         tinyobj::real_t) {
        auto& b = *static_cast<ObjBuilder*>(self);
        b.Tick();
        if (!b.budget_.AddVertices(1)) throw StopParsing{};
        b.positions_.emplace_back(x, y, z);
        b.RefuseNonFinite(b.positions_, "vertex");
    }

    static void OnNormal(void* self, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z) {
        auto& b = *static_cast<ObjBuilder*>(self);
        b.Tick();
        if (!b.budget_.AddVertices(1)) throw StopParsing{};
        b.normals_.emplace_back(x, y, z);
        b.RefuseNonFinite(b.normals_, "normal");
    }

    static void OnFace(void* self, tinyobj::index_t* indices, int count) {
        static_cast<ObjBuilder*>(self)->Face(indices, count);
    }

    static void OnGroup(void* self, const char** names, int count) {
        std::string name;
        for (int i = 0; i < count; ++i) name += (i > 0 ? " " : "") + std::string(names[i]);
        static_cast<ObjBuilder*>(self)->StartMesh(std::move(name));
    }

    static void OnObject(void* self, const char* name) {
        static_cast<ObjBuilder*>(self)->StartMesh(name);
    }

    // The meshes, once the parser is done.
    Result<std::vector<Mesh>> Finish() {
        EndMesh();
        if (meshes_.empty()) {
            return Error{source_.field, "no faces: an OBJ scene needs at least one triangle"};
        }
        return std::move(meshes_);
    }

    const Error& error() const { return error_; }

    void MaterialLibrary(const std::string& name) {
        if (source_.refuse_material_libraries) {
            Fail("mtllib \"" + name.substr(0, 96) +
                 "\": an upload never names a file; remove the mtllib line (materials play no "
                 "part in shadows)");
        }
    }

private:
    void Tick() {
        if (budget_.Cancelled()) throw StopParsing{};
    }

    void Fail(std::string reason) {
        error_ = Error{source_.field, std::move(reason)};
        throw StopParsing{};
    }

    // The text's numbers are all finite decimals (FirstMisreadLine), but tinyobjloader's own
    // arithmetic can still overflow: `0e500` is 0 times 5^500, NaN.
    void RefuseNonFinite(const std::vector<Eigen::Vector3f>& values, const char* what) {
        if (values.back().allFinite()) return;
        Fail(std::string(what) + " " + std::to_string(values.size()) +
             " is not finite as tinyobjloader computes it; write its numbers with fewer digits "
             "or a smaller exponent");
    }

    std::string MeshName() const {
        return name_.empty() ? source_.stem + "[" + std::to_string(meshes_.size()) + "]" : name_;
    }

    // Resolves one corner's 1-based or negative (relative) index against `count` entries.
    bool Resolve(int raw, std::size_t count, std::size_t* out) const {
        if (raw > 0 && static_cast<std::size_t>(raw) <= count) {
            *out = static_cast<std::size_t>(raw) - 1;
            return true;
        }
        if (raw < 0 && static_cast<std::size_t>(-static_cast<std::int64_t>(raw)) <= count) {
            *out = count - static_cast<std::size_t>(-static_cast<std::int64_t>(raw));
            return true;
        }
        return false;
    }

    void Face(const tinyobj::index_t* indices, int count) {
        Tick();
        if (count < 3) return;  // points and lines cast no shadow
        if (!budget_.AddTriangles(static_cast<std::uint64_t>(count - 2))) throw StopParsing{};
        const std::size_t first = corners_.size();
        for (int k = 0; k < count; ++k) {
            std::size_t position = 0;
            if (!Resolve(indices[k].vertex_index, positions_.size(), &position)) {
                Fail("object '" + MeshName() + "' face " + std::to_string(faces_) + " corner " +
                     std::to_string(k) + ": vertex index " +
                     std::to_string(indices[k].vertex_index) + " out of range (" +
                     std::to_string(positions_.size()) + " vertices so far)");
            }
            std::int64_t normal = -1;
            if (indices[k].normal_index != 0) {
                std::size_t n = 0;
                if (!Resolve(indices[k].normal_index, normals_.size(), &n)) {
                    Fail("object '" + MeshName() + "' face " + std::to_string(faces_) +
                         " corner " + std::to_string(k) + ": normal index " +
                         std::to_string(indices[k].normal_index) + " out of range (" +
                         std::to_string(normals_.size()) + " normals so far)");
                }
                normal = static_cast<std::int64_t>(n);
            }
            corners_.push_back({static_cast<std::uint32_t>(position), normal});
        }
        // A fan from the first corner: OBJ polygons are planar and convex.
        for (int k = 1; k + 1 < count; ++k) {
            triangles_.insert(triangles_.end(),
                              {first, first + static_cast<std::size_t>(k),
                               first + static_cast<std::size_t>(k) + 1});
        }
        ++faces_;
    }

    void StartMesh(std::string name) {
        Tick();
        EndMesh();
        name_ = std::move(name);
        while (!name_.empty() && (name_.back() == ' ' || name_.back() == '\t' ||
                                  name_.back() == '\r')) {
            name_.pop_back();
        }
    }

    void EndMesh() {
        if (triangles_.empty()) {
            corners_.clear();
            return;
        }
        Mesh mesh;
        mesh.name = MeshName();
        bool all_normals = true;
        for (const Corner& c : corners_) all_normals &= c.normal >= 0;
        std::map<std::pair<std::uint32_t, std::int64_t>, std::uint32_t> shared;
        std::vector<std::uint32_t> local(corners_.size());
        for (std::size_t k = 0; k < corners_.size(); ++k) {
            const Corner& c = corners_[k];
            const auto key = std::make_pair(c.position, all_normals ? c.normal : -1);
            auto [it, added] =
                shared.emplace(key, static_cast<std::uint32_t>(mesh.positions.size()));
            if (added) {
                mesh.positions.push_back(positions_[c.position]);
                if (all_normals) {
                    const Eigen::Vector3f& n = normals_[static_cast<std::size_t>(c.normal)];
                    mesh.normals.push_back(n.norm() > 0 ? n.normalized() : n);
                }
            }
            local[k] = it->second;
        }
        mesh.indices.reserve(triangles_.size());
        for (const std::size_t corner : triangles_) mesh.indices.push_back(local[corner]);
        mesh.closed = IsClosedByPosition(mesh);
        meshes_.push_back(std::move(mesh));
        corners_.clear();
        triangles_.clear();
    }

    const MeshSource& source_;
    DecodeBudget& budget_;
    std::vector<Eigen::Vector3f> positions_;
    std::vector<Eigen::Vector3f> normals_;
    std::string name_;
    std::vector<Corner> corners_;         // the current mesh's face corners, in file order
    std::vector<std::size_t> triangles_;  // indices into corners_, three per triangle
    std::size_t faces_ = 0;
    std::vector<Mesh> meshes_;
    Error error_;
};

bool RefuseMaterials::operator()(const std::string& name, std::vector<tinyobj::material_t>*,
                                 std::map<std::string, int>*, std::string* warn, std::string*) {
    builder_.MaterialLibrary(name);
    if (warn != nullptr) warn->clear();
    return false;
}

}  // namespace

Result<std::vector<Mesh>> ParseObj(std::string_view text, const MeshSource& source,
                                   DecodeBudget& budget) {
    if (std::optional<Error> misread = FirstMisreadLine(text, source, budget)) return *misread;
    ObjBuilder builder(source, budget);
    tinyobj::callback_t callbacks;
    callbacks.vertex_cb = &ObjBuilder::OnVertex;
    callbacks.normal_cb = &ObjBuilder::OnNormal;
    callbacks.index_cb = &ObjBuilder::OnFace;
    callbacks.group_cb = &ObjBuilder::OnGroup;
    callbacks.object_cb = &ObjBuilder::OnObject;
    ViewBuffer buffer(text);
    std::istream stream(&buffer);
    RefuseMaterials materials(builder);
    std::string warn, err;
    try {
        if (!tinyobj::LoadObjWithCallback(stream, callbacks, &builder, &materials, &warn, &err)) {
            return Error{source.field, "OBJ parse failed: " +
                                           (err.empty() ? std::string("unknown error") : err)};
        }
        return builder.Finish();
    } catch (const StopParsing&) {
        if (budget.stopped()) return StoppedError(source, budget);
        return builder.error();
    }
}

}  // namespace lixel::scene
