// The client shader kit's functions (kit/glsl/lixel_shadows.glsl) against the CPU reference
// (issue 15): at random world points, the kit's lixel_select_map picks the map the solver's
// LookupMap picks, at the lixel the double matrices give, and lixel_hard_shadow answers as the
// stored depth of that texel says, with the block and atlas a client builds from what Render
// streams (lixel::kit: BuildShadowBlock, PackImages). The points are drawn as GL_POINTS, one
// output texel each, so nothing but the kit decides what comes back.
#include <lixel/kit/atlas_layout.h>
#include <lixel/kit/shadow_block.h>
#include <lixel/render/program.h>
#include <lixel/render/readback.h>
#include <lixel/solver/homogeneous.h>
#include <lixel/solver/light_map.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <string_view>

#include "view_setup.h"

namespace lixel::render {
namespace {

// One point per vertex: the kit's answer into the vertex's own texel of a grid.
constexpr std::string_view kProbeVert = R"(#version 450 core
#include "lixel_shadows.glsl"
layout(location = 0) in vec3 a_position;  // relative to the block's origin
uniform ivec2 u_grid;
flat out vec4 v_result;
void main() {
    vec3 s;
    int map = lixel_select_map(a_position, s);
    float lit = map < 0 ? -1.0 : lixel_unshadowed(map) ? 2.0 : lixel_hard_shadow(map, s, 0.0);
    v_result = vec4(float(map), s.x, s.y, lit);
    ivec2 cell = ivec2(gl_VertexID % u_grid.x, gl_VertexID / u_grid.x);
    gl_Position = vec4((vec2(cell) + 0.5) / vec2(u_grid) * 2.0 - 1.0, 0.5, 1.0);
}
)";
constexpr std::string_view kProbeFrag = R"(#version 450 core
flat in vec4 v_result;
layout(location = 0) out vec4 o_result;
void main() { o_result = v_result; }
)";

ShaderLookup ProbeLookup() {
    return [embedded = EmbeddedShaderLookup()](std::string_view name) -> const std::string_view* {
        if (name == "kit_probe.vert") return &kProbeVert;
        if (name == "kit_probe.frag") return &kProbeFrag;
        return embedded(name);
    };
}

// The kit's lixels against the double ones: float positions relative to the origin (|p| < 8)
// and float matrices carry the lixel by a few 1e-5 (2.4e-5 measured at worst over these
// points); within this the kit and the CPU may round a rule's edge or a texel's edge either way.
constexpr double kFloatLixels = 1e-4;

// How far a point's lixel lies from the edges of a map's lookup rule (rectangle and half-planes,
// lixels), in double: where the kit's float and the CPU's double may decide either way.
double RuleMargin(const PlannedMap& m, const Vec4& x) {
    const Vec4 h = m.map.matrix * x;
    if (!(h.w() > 0.0)) return std::numeric_limits<double>::infinity();
    const double sx = h.x() / h.w(), sy = h.y() / h.w();
    const Eigen::Vector4d r = LookupRectangle(m.map, m.lookup);
    double margin = std::min({std::abs(sx - r[0]), std::abs(sy - r[1]), std::abs(sx - r[2]),
                              std::abs(sy - r[3])});
    for (const Eigen::Vector3d& p : m.lookup.half_planes) {
        margin = std::min(margin, std::abs(p.x() * sx + p.y() * sy + p.z()));
    }
    return margin;
}

TEST(KitFunctions, PickTheSolversMapTexelAndAnswerAtRandomPoints) {
    using testing::TestScene;
    GlContext& context = testing::Context();
    const GlApi& gl = context.gl();
    const TestScene s = testing::SquareOverFloor(128);
    PlanRequest request;
    request.viewer = s.viewer;
    request.viewport = s.viewport;
    request.light = s.light;
    for (const Mesh& m : s.meshes) request.objects.push_back({m.name, m.Bounds(), &m, m.closed});
    request.scene_bounds = s.bounds;
    // The plate's top first (a bounded plane: four half-planes in its lookup), then the floor.
    PlaneOfInterest plate{"plate", Vec4(0, 1, 0, -1.22), {}};
    plate.polygon = {Vec3(-0.3, 1.22, -0.4), Vec3(-0.3, 1.22, 0.6), Vec3(0.7, 1.22, 0.6),
                     Vec3(0.7, 1.22, -0.4)};
    request.planes = {plate, PlaneOfInterest{"floor", Vec4(0, 1, 0, 0), {}}};
    request.lixel_budget = 128 * 128;
    request.fallback_floor = 64 * 64;
    auto plan = PlanShadowMaps(request);
    ASSERT_TRUE(plan.ok()) << plan.error().Message();
    ASSERT_GE(plan->maps.size(), 2u) << "the plate's and the floor's maps";
    ASSERT_EQ(plan->maps[0].lookup.half_planes.size(), 4u);

    // The maps as Render streams them, then the client's block and atlas from them.
    auto scene = UploadScene(context, s.meshes, s.origin);
    ASSERT_TRUE(scene.ok()) << scene.error().Message();
    auto rendered = testing::TheRenderer().RenderMaps(*scene, plan->maps, plan->hull.light);
    ASSERT_TRUE(rendered.ok()) << rendered.error().Message();
    // Unshadowed maps have no texels: only the others go into the atlas.
    std::vector<FloatImage> depths(plan->maps.size());
    std::vector<kit::ImageView> views;
    std::vector<std::size_t> textured;
    for (std::size_t i = 0; i < rendered->size(); ++i) {
        if (plan->maps[i].lookup.unshadowed) continue;
        auto image = ReadDepth(context, *(*rendered)[i].depth);
        ASSERT_TRUE(image.ok()) << image.error().Message();
        depths[i] = std::move(image).value();
        textured.push_back(i);
    }
    for (const std::size_t i : textured) views.push_back({depths[i].width, depths[i].height, depths[i].pixels});
    auto atlas = kit::PackImages(views, kit::kAtlasBorder, 16384);
    ASSERT_TRUE(atlas.ok()) << atlas.error().Message();
    std::vector<kit::KitMap> kit_maps;
    for (std::size_t i = 0; i < plan->maps.size(); ++i) {
        kit_maps.push_back(kit::MakeKitMap(plan->maps[i].map, plan->maps[i].lookup, s.origin));
    }
    for (std::size_t k = 0; k < textured.size(); ++k) {
        kit_maps[textured[k]].origin_a = atlas->origins[k];
    }
    auto block = kit::BuildShadowBlock(kit_maps, Viewport{atlas->width, atlas->height});
    ASSERT_TRUE(block.ok()) << block.error().Message();

    // Random points: just above the floor (lit or in the plate's shadow), on and above the
    // plate, and anywhere in the scene's box (some held by no map).
    constexpr int kGrid = 128;
    constexpr int kPoints = kGrid * kGrid;
    std::mt19937 rng(12351);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Vec3> points;
    for (int i = 0; i < kPoints; ++i) {
        const double x = -4.0 + 8.0 * u(rng), z = -4.0 + 8.0 * u(rng);
        switch (i % 3) {
            case 0: points.emplace_back(x, 0.01, z); break;
            case 1: points.emplace_back(-0.3 + u(rng), 1.2201 + 0.1 * u(rng), -0.4 + u(rng)); break;
            default: points.emplace_back(x, -0.5 + 2.5 * u(rng), z); break;
        }
    }
    std::vector<float> relative;
    for (const Vec3& p : points) {
        const Eigen::Vector3f r = (p - s.origin).cast<float>();
        relative.insert(relative.end(), {r.x(), r.y(), r.z()});
    }

    auto program = BuildProgram(context, {"kit_probe.vert", "kit_probe.frag"}, {}, ProbeLookup());
    ASSERT_TRUE(program.ok()) << program.error().Message();
    GLuint ids[4] = {};
    gl.CreateBuffers(2, ids);
    GlBuffer vertices(gl, ids[0]), uniforms(gl, ids[1]);
    gl.NamedBufferStorage(vertices.id(), static_cast<GLsizeiptr>(relative.size() * 4),
                          relative.data(), 0);
    gl.NamedBufferStorage(uniforms.id(), static_cast<GLsizeiptr>(block->size()), block->data(), 0);
    gl.CreateVertexArrays(1, ids);
    GlVertexArray vao(gl, ids[0]);
    gl.VertexArrayVertexBuffer(vao.id(), 0, vertices.id(), 0, 12);
    gl.EnableVertexArrayAttrib(vao.id(), 0);
    gl.VertexArrayAttribFormat(vao.id(), 0, 3, GL_FLOAT, GL_FALSE, 0);
    gl.VertexArrayAttribBinding(vao.id(), 0, 0);
    gl.CreateTextures(GL_TEXTURE_2D, 2, ids);
    GlTexture atlas_texture(gl, ids[0]), result(gl, ids[1]);
    gl.TextureStorage2D(atlas_texture.id(), 1, GL_R32F, atlas->width, atlas->height);
    gl.TextureSubImage2D(atlas_texture.id(), 0, 0, 0, atlas->width, atlas->height, GL_RED,
                         GL_FLOAT, atlas->texels.data());
    for (const GLenum p : {GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER}) {
        gl.TextureParameteri(atlas_texture.id(), p, GL_NEAREST);
    }
    gl.TextureStorage2D(result.id(), 1, GL_RGBA32F, kGrid, kGrid);
    gl.CreateFramebuffers(1, ids);
    GlFramebuffer framebuffer(gl, ids[0]);
    gl.NamedFramebufferTexture(framebuffer.id(), GL_COLOR_ATTACHMENT0, result.id(), 0);
    gl.NamedFramebufferDrawBuffer(framebuffer.id(), GL_COLOR_ATTACHMENT0);
    ASSERT_EQ(gl.CheckNamedFramebufferStatus(framebuffer.id(), GL_FRAMEBUFFER),
              static_cast<GLenum>(GL_FRAMEBUFFER_COMPLETE));
    const float clear[4] = {-9.0f, 0.0f, 0.0f, -9.0f};
    gl.ClearNamedFramebufferfv(framebuffer.id(), GL_COLOR, 0, clear);

    const GLuint id = program->id();
    gl.UniformBlockBinding(id, gl.GetUniformBlockIndex(id, "LixelShadowMaps"), 3);
    gl.BindBufferBase(GL_UNIFORM_BUFFER, 3, uniforms.id());
    gl.BindTextureUnit(5, atlas_texture.id());
    gl.ProgramUniform1i(id, program->Uniform("lixel_atlas_a"), 5);
    gl.ProgramUniform2i(id, program->Uniform("u_grid"), kGrid, kGrid);
    gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer.id());
    gl.Viewport(0, 0, kGrid, kGrid);
    gl.Disable(GL_DEPTH_TEST);
    gl.Disable(GL_BLEND);
    gl.UseProgram(id);
    gl.BindVertexArray(vao.id());
    gl.DrawArrays(GL_POINTS, 0, kPoints);
    gl.BindVertexArray(0);
    gl.UseProgram(0);
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    std::vector<float> out(static_cast<std::size_t>(kPoints) * 4);
    gl.GetTextureImage(result.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(out.size() * 4),
                       out.data());
    ASSERT_TRUE(context.Check("kit probe").ok());

    int held = 0, lit = 0, shadowed = 0, map_differs = 0, map_near_edge = 0, unshadowed = 0;
    int on_plate = 0, on_floor = 0;  // points the plate's and the floor's maps take
    int texel_checked = 0, answer_checked = 0, answer_near_equal = 0;
    double worst_lixel = 0.0;
    std::vector<int> per_map(plan->maps.size() + 1, 0);
    for (int i = 0; i < kPoints; ++i) {
        const float* r = &out[static_cast<std::size_t>(i) * 4];
        ASSERT_NE(r[0], -9.0f) << "point " << i << " was not drawn";
        const Vec4 x = Point(points[static_cast<std::size_t>(i)]);
        const int expected = LookupMap(*plan, x);
        const int got = static_cast<int>(std::lround(r[0]));
        ++per_map[static_cast<std::size_t>(expected + 1)];
        if (expected >= 0) {
            on_plate += plan->maps[static_cast<std::size_t>(expected)].plane_index == 0;
            on_floor += plan->maps[static_cast<std::size_t>(expected)].plane_index == 1;
        }
        if (got != expected) {
            ++map_differs;
            // Only a point on a rule's edge, within float's reach of it, may go the other way.
            const double margin = std::min(
                expected >= 0 ? RuleMargin(plan->maps[expected], x) : 1e30,
                got >= 0 && got < static_cast<int>(plan->maps.size()) ? RuleMargin(plan->maps[got], x)
                                                                      : 1e30);
            EXPECT_LT(margin, kFloatLixels) << "point " << i << ": kit map " << got << ", LookupMap "
                                    << expected;
            map_near_edge += margin < kFloatLixels;
            continue;
        }
        if (expected < 0) continue;
        ++held;
        const PlannedMap& m = plan->maps[static_cast<std::size_t>(expected)];
        if (m.lookup.unshadowed) {  // the kit's own verdict, with no texel read
            EXPECT_EQ(r[3], 2.0f) << "point " << i << " in " << m.name;
            ++unshadowed;
            continue;
        }
        const Vec4 h = m.map.matrix * x;
        const double sx = h.x() / h.w(), sy = h.y() / h.w();
        worst_lixel = std::max({worst_lixel, std::abs(r[1] - sx), std::abs(r[2] - sy)});
        // The same texel, unless the lixel lies within the float error of a texel edge.
        const double edge = std::min({sx - std::floor(sx), std::ceil(sx) - sx,
                                      sy - std::floor(sy), std::ceil(sy) - sy});
        if (edge < kFloatLixels) continue;
        ++texel_checked;
        EXPECT_EQ(std::floor(r[1]), std::floor(sx)) << "point " << i;
        EXPECT_EQ(std::floor(r[2]), std::floor(sy)) << "point " << i;
        // The answer the texel's stored depth gives, unless the point's depth rounds to it.
        const FloatImage& d = depths[static_cast<std::size_t>(expected)];
        const double stored = d.at(static_cast<int>(std::floor(sx)), static_cast<int>(std::floor(sy)));
        const double depth = StoredDepthOf(m.map, x);
        if (std::abs(depth - stored) < 1e-5) {
            ++answer_near_equal;
            continue;
        }
        ++answer_checked;
        const float want = depth >= stored ? 1.0f : 0.0f;
        EXPECT_EQ(r[3], want) << "point " << i << ": depth " << depth << ", stored " << stored;
        (want > 0.5f ? lit : shadowed) += 1;
    }
    std::printf("[ measured ] %d points: %d held by no map, %d by the plate's maps, %d by the "
                "floor's (%d unshadowed); map differs at %d (%d within 1e-4 lixel of a rule's "
                "edge); worst lixel error %.2e; texels compared %d; answers compared %d (%d lit, "
                "%d shadowed), %d within 1e-5 of the stored depth\n",
                kPoints, per_map[0], on_plate, on_floor, unshadowed, map_differs, map_near_edge,
                worst_lixel, texel_checked, answer_checked, lit, shadowed, answer_near_equal);
    EXPECT_LT(worst_lixel, kFloatLixels);
    EXPECT_GT(on_plate, kPoints / 10);
    EXPECT_GT(on_floor, kPoints / 20);
    EXPECT_GT(unshadowed, kPoints / 20);
    // Most lit points are the unshadowed entries' now (10939 measured); the texels still
    // answer a few hundred of each (209 lit, 229 shadowed measured).
    EXPECT_GT(lit, kPoints / 100);
    EXPECT_GT(shadowed, kPoints / 100);
    EXPECT_GT(texel_checked, (held - unshadowed) * 9 / 10);
}

}  // namespace
}  // namespace lixel::render
