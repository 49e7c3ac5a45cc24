// The view pass: uniforms for the plan's maps, the method's textures, one draw of the scene.
#include <lixel/render/map_atlas.h>
#include <lixel/render/map_transform.h>
#include <lixel/render/view_pass.h>
#include <lixel/solver/camera.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace lixel::render {
namespace {

constexpr GLuint kAtlasUnitA = 0;
constexpr GLuint kAtlasUnitB = 1;
// The uniform buffer binding point of the kit's LixelShadowMaps block.
constexpr GLuint kShadowBlockBinding = 0;

std::string MapField(std::size_t i, const char* what) {
    return "maps[" + std::to_string(i) + "]" + what;
}

// `needs_maps`: false for the bare variant, which looks nothing up.
Result<bool> ValidateRequest(const ViewRequest& r, int max_texture_size, bool needs_maps) {
    if (auto ok = ValidateViewer(r.viewer, r.viewport, "viewer"); !ok) return ok;
    if (r.viewport.width > max_texture_size || r.viewport.height > max_texture_size) {
        return Error{"viewport",
                     "larger than the GL maximum texture size " + std::to_string(max_texture_size)};
    }
    if (!r.light.allFinite() || (r.light.head<3>().isZero() && r.light.w() == 0.0)) {
        return Error{"light", "not finite, or a zero direction"};
    }
    if (needs_maps && r.maps.empty()) return Error{"maps", "no maps to look up"};
    if (r.maps.size() > static_cast<std::size_t>(kMaxViewMaps)) {
        return Error{"maps", std::to_string(r.maps.size()) + " maps; the view pass takes at most " +
                                 std::to_string(kMaxViewMaps)};
    }
    static_assert(kAtlasBorder >= 4, "the atlas border holds the widest filter's taps");
    const std::pair<const char*, float> biases[] = {
        {"options.depth_bias", r.options.depth_bias},
        {"options.slope_bias", r.options.slope_bias},
        {"options.max_bias", r.options.max_bias},
        {"options.second_depth_bias", r.options.second_depth_bias},
        {"options.open_second_depth_bias", r.options.open_second_depth_bias}};
    for (const auto& [field, value] : biases) {
        // A negative or NaN bias shadows every receiver by itself.
        if (!(value >= 0.0f && std::isfinite(value))) {
            return Error{field, std::to_string(value) + " is not a finite value >= 0"};
        }
    }
    if (r.options.pcf_radius < 1 || r.options.pcf_radius > 4) {
        return Error{"options.pcf_radius",
                     std::to_string(r.options.pcf_radius) + " outside [1, 4]"};
    }
    for (std::size_t i = 0; i < r.maps.size(); ++i) {
        const ViewMap& m = r.maps[i];
        const std::string field = MapField(i, "");
        // Each map and its border must fit the atlas, one texture of the GL's maximum size.
        if (auto ok = ValidateLightMap(m.map, max_texture_size - 2 * kAtlasBorder, field.c_str());
            !ok) {
            return ok;
        }
        if (m.lookup.half_planes.size() > static_cast<std::size_t>(kMaxHalfPlanes)) {
            return Error{MapField(i, ".lookup.half_planes"),
                         "more than " + std::to_string(kMaxHalfPlanes) + " half-planes"};
        }
        for (const Eigen::Vector3d& h : m.lookup.half_planes) {
            if (!h.allFinite()) return Error{MapField(i, ".lookup.half_planes"), "not finite"};
        }
        if (!m.lookup.world_limit.allFinite()) {
            return Error{MapField(i, ".lookup.world_limit"), "not finite"};
        }
        if (m.lookup.unshadowed) continue;  // lit where it accepts: no texels to read
        const DepthMap* needed = nullptr;
        const char* name = "";
        switch (r.method) {
            case ShadowMethod::kDepth:
            case ShadowMethod::kPcf:
                needed = m.depth;
                name = ".depth";
                break;
            case ShadowMethod::kSecondDepth:
                needed = m.second_depth;
                name = ".second_depth";
                break;
            case ShadowMethod::kSilhouette:
                needed = m.silhouette ? &m.silhouette->corners : nullptr;
                name = ".silhouette";
                break;
        }
        if (needed == nullptr || !needed->texture) {
            return Error{MapField(i, name),
                         std::string("not rendered; ") + ShadowMethodName(r.method) + " needs it"};
        }
        const LightMap& rendered =
            r.method == ShadowMethod::kSilhouette ? m.silhouette->map : needed->map;
        if (rendered.width != m.map.width || rendered.height != m.map.height ||
            rendered.matrix != m.map.matrix) {
            return Error{MapField(i, name), "rendered for another map"};
        }
    }
    return true;
}


// The texture the method reads as "a" (depth, second depth or corner depth) and as "b"
// (silhouette points, or none) for map m; ValidateRequest has checked they exist.
const DepthMap& TextureA(const ViewMap& m, ShadowMethod method) {
    switch (method) {
        case ShadowMethod::kSecondDepth:
            return *m.second_depth;
        case ShadowMethod::kSilhouette:
            return m.silhouette->corners;
        case ShadowMethod::kDepth:
        case ShadowMethod::kPcf:
            break;
    }
    return *m.depth;
}

// Copies `sources` (each its own size) into `atlas` at the packed origins, each inside a
// border of `border` texels that repeats its edge texels (what clamping to the map would read,
// so the shaders' taps past an edge need no clamp); reallocates the atlas when the layout's size
// differs from `atlas_size`. Returns each map's origin (its texel (0, 0)).
Result<std::vector<Eigen::Vector2i>> CopyIntoAtlas(const GlApi& gl, int max_side, GLenum format,
                                                   const std::vector<GLuint>& sources,
                                                   const std::vector<Viewport>& sizes, int border,
                                                   GlTexture& atlas, Viewport& atlas_size) {
    auto layout = kit::PackBorderedAtlas(sizes, border, max_side);
    if (!layout) return layout.error();
    if (!atlas || atlas_size.width != layout->width || atlas_size.height != layout->height) {
        atlas = CreateTexture2D(gl, format, layout->width, layout->height);
        atlas_size = {layout->width, layout->height};
    }
    const GLuint a = atlas.id();
    const auto copy_within = [&](int sx, int sy, int dx, int dy, int w, int h) {
        gl.CopyImageSubData(a, GL_TEXTURE_2D, 0, sx, sy, 0, a, GL_TEXTURE_2D, 0, dx, dy, 0, w, h,
                            1);
    };
    for (std::size_t i = 0; i < sources.size(); ++i) {
        const Eigen::Vector2i& o = layout->origins[i];
        const int w = sizes[i].width;
        const int h = sizes[i].height;
        gl.CopyImageSubData(sources[i], GL_TEXTURE_2D, 0, 0, 0, 0, a, GL_TEXTURE_2D, 0, o.x(),
                            o.y(), 0, w, h, 1);
        for (int k = 1; k <= border; ++k) {  // edge columns, then edge rows with the corners
            copy_within(o.x(), o.y(), o.x() - k, o.y(), 1, h);
            copy_within(o.x() + w - 1, o.y(), o.x() + w - 1 + k, o.y(), 1, h);
        }
        for (int k = 1; k <= border; ++k) {
            copy_within(o.x() - border, o.y(), o.x() - border, o.y() - k, w + 2 * border, 1);
            copy_within(o.x() - border, o.y() + h - 1, o.x() - border, o.y() + h - 1 + k,
                        w + 2 * border, 1);
        }
    }
    return layout->origins;
}

void EnsureTexture(const GlApi& gl, GlTexture& texture, GLenum format, const Viewport& size,
                   const Viewport& old) {
    if (!texture || size.width != old.width || size.height != old.height) {
        texture = CreateTexture2D(gl, format, size.width, size.height);
    }
}

}  // namespace

const char* ShadowMethodName(ShadowMethod method) noexcept {
    switch (method) {
        case ShadowMethod::kDepth:
            return "depth";
        case ShadowMethod::kPcf:
            return "pcf";
        case ShadowMethod::kSecondDepth:
            return "second_depth";
        case ShadowMethod::kSilhouette:
            return "silhouette_map";
    }
    return "?";
}

Result<ViewPass> ViewPass::Create(GlContext& context, ViewVariant variant) {
    // One program per method, its test chosen at compile time (view.frag's kMethod); the bare
    // variant has no test, so one program serves every method.
    const int programs = variant == ViewVariant::kBare ? 1 : kShadowMethodCount;
    std::vector<Program> built;
    for (int method = 0; method < programs; ++method) {
        std::vector<std::string> defines = {
            "#define LIXEL_MAX_MAPS " + std::to_string(kMaxViewMaps),
            "#define LIXEL_MAX_HALF_PLANES " + std::to_string(kMaxHalfPlanes),
            "#define LIXEL_METHOD " + std::to_string(method)};
        if (variant == ViewVariant::kBare) defines.push_back("#define LIXEL_BARE_VIEW 1");
        auto program = BuildProgram(context, {"view.vert", "view.frag"}, defines);
        if (!program) return program.error();
        const GLuint id = program->id();
        context.gl().ProgramUniform1i(id, program->Uniform("lixel_atlas_a"), kAtlasUnitA);
        context.gl().ProgramUniform1i(id, program->Uniform("lixel_atlas_b"), kAtlasUnitB);
        // The bare variant reads no map: its compiler may drop the block.
        const GLuint block = context.gl().GetUniformBlockIndex(id, "LixelShadowMaps");
        if (block != GL_INVALID_INDEX) {
            context.gl().UniformBlockBinding(id, block, kShadowBlockBinding);
        }
        built.push_back(std::move(program).value());
    }
    auto prepass = BuildProgram(context, {"depth.vert"});
    if (!prepass) return prepass.error();
    GLuint fbo = 0;
    context.gl().CreateFramebuffers(1, &fbo);
    const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    context.gl().NamedFramebufferDrawBuffers(fbo, 3, buffers);
    GLuint block = 0;
    context.gl().CreateBuffers(1, &block);
    context.gl().NamedBufferData(block, static_cast<GLsizeiptr>(kit::ShadowBlockLayout::kBytes),
                                 nullptr, GL_DYNAMIC_DRAW);
    ViewPass pass(context, std::move(built), std::move(prepass.value()),
                  GlFramebuffer(context.gl(), fbo), GlBuffer(context.gl(), block),
                  variant == ViewVariant::kBare);
    if (auto ok = context.Check("view pass setup"); !ok) return ok.error();
    return pass;
}

Result<bool> ViewPass::Render(const GpuScene& scene, const ViewRequest& request,
                              ViewImages& target) {
    if (auto ok = ValidateRequest(request, context_->info().max_texture_size, !bare_); !ok) {
        return ok;
    }
    const GlApi& gl = context_->gl();
    const Vec3& origin = scene.origin();
    const Viewport old = target.viewport;
    EnsureTexture(gl, target.mask, GL_R32F, request.viewport, old);
    EnsureTexture(gl, target.preview, GL_RGBA8, request.viewport, old);
    EnsureTexture(gl, target.map_index, GL_R32I, request.viewport, old);
    EnsureTexture(gl, target.depth, GL_DEPTH_COMPONENT32F, request.viewport, old);
    target.viewport = request.viewport;
    const GLuint fbo = framebuffer_.id();
    gl.NamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, target.mask.id(), 0);
    gl.NamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT1, target.preview.id(), 0);
    gl.NamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT2, target.map_index.id(), 0);
    gl.NamedFramebufferTexture(fbo, GL_DEPTH_ATTACHMENT, target.depth.id(), 0);
    const GLenum status = gl.CheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        return Error{"view pass", "framebuffer incomplete (status " + std::to_string(status) + ")"};
    }

    const Program& shader = ProgramFor(request.method);
    const GLuint program = shader.id();
    // The maps as the kit reads them (kit/glsl/lixel_shadows.glsl): one std140 block, built
    // by the same lixel::kit code clients use.
    std::vector<kit::KitMap> maps;
    for (const ViewMap& m : request.maps) maps.push_back(kit::MakeKitMap(m.map, m.lookup, origin));
    if (!request.maps.empty()) {
        if (auto ok = FillAtlases(request, maps); !ok) return ok;
    }
    auto block = kit::BuildShadowBlock(maps, atlas_a_size_);
    if (!block) return Error{"maps", block.error().Message()};
    gl.NamedBufferSubData(shadow_block_.id(), 0, static_cast<GLsizeiptr>(block->size()),
                          block->data());
    gl.BindBufferBase(GL_UNIFORM_BUFFER, kShadowBlockBinding, shadow_block_.id());

    const Mat4f viewer = RelativeMatrix(request.viewer, origin);
    gl.ProgramUniformMatrix4fv(program, shader.Uniform("u_viewer"), 1, GL_FALSE, viewer.data());
    const Eigen::Vector4f light = RelativePoint(request.light, origin).cast<float>();
    gl.ProgramUniform4fv(program, shader.Uniform("u_light"), 1, light.data());
    auto eye = EyePoint(request.viewer);
    if (!eye) return eye.error();
    const Eigen::Vector4f eye_relative = RelativePoint(*eye, origin).cast<float>();
    gl.ProgramUniform4fv(program, shader.Uniform("u_eye"), 1, eye_relative.data());
    const ShadowOptions& o = request.options;
    gl.ProgramUniform1f(program, shader.Uniform("u_depth_bias"), o.depth_bias);
    gl.ProgramUniform1f(program, shader.Uniform("u_slope_bias"), o.slope_bias);
    gl.ProgramUniform1f(program, shader.Uniform("u_max_bias"), o.max_bias);
    gl.ProgramUniform1f(program, shader.Uniform("u_second_depth_bias"), o.second_depth_bias);
    gl.ProgramUniform1f(program, shader.Uniform("u_open_second_depth_bias"),
                        o.open_second_depth_bias);
    const GLint receiver_open = shader.Uniform("u_receiver_open");
    gl.ProgramUniform1i(program, shader.Uniform("u_pcf_radius"), o.pcf_radius);
    gl.ProgramUniform1i(program, shader.Uniform("u_virtual_samples"), o.virtual_samples ? 1 : 0);
    gl.ProgramUniform1i(program, shader.Uniform("u_tint_maps"), o.tint_maps ? 1 : 0);

    gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl.Viewport(0, 0, request.viewport.width, request.viewport.height);
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LESS);
    gl.DepthMask(GL_TRUE);
    gl.Disable(GL_CULL_FACE);  // open surfaces are seen from both sides
    gl.Disable(GL_BLEND);
    gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    const float no_surface[4] = {kNoSurface, 0.0f, 0.0f, 0.0f};
    const float background[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    const GLint no_map[4] = {kNoMap, 0, 0, 0};
    const float far = static_cast<float>(kClipDepthFar);
    gl.ClearNamedFramebufferfv(fbo, GL_COLOR, 0, no_surface);
    gl.ClearNamedFramebufferfv(fbo, GL_COLOR, 1, background);
    gl.ClearNamedFramebufferiv(fbo, GL_COLOR, 2, no_map);
    gl.ClearNamedFramebufferfv(fbo, GL_DEPTH, 0, &far);
    gl.BindVertexArray(scene.triangles());
    // Each draw placed by its model matrix in `drawing` (the pre-pass or the shading program);
    // `per_surface`: tell the shading program whether each draw's surface is open and receives.
    const GLint receives = shader.Uniform("u_receives");
    const auto draw_scene = [&](GLuint drawing, GLint model, bool per_surface) {
        for (const GpuDraw& draw : scene.draws()) {
            const GpuMeshRange& range = scene.ranges()[draw.range];
            gl.ProgramUniformMatrix4fv(drawing, model, 1, GL_FALSE, draw.model.data());
            if (per_surface) {
                gl.ProgramUniform1i(program, receiver_open, range.closed ? 0 : 1);
                gl.ProgramUniform1i(program, receives, draw.receives ? 1 : 0);
            }
            gl.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(range.index_count),
                            GL_UNSIGNED_INT,
                            reinterpret_cast<const void*>(range.first_index * sizeof(GLuint)));
        }
    };
    // Depth first, then shade only the nearest surface (GL_EQUAL; both vertex stages declare
    // gl_Position invariant): the shadow test runs once per pixel instead of once per fragment
    // of every overlapping triangle.
    const GLuint prepass = depth_prepass_.id();
    gl.ProgramUniformMatrix4fv(prepass, depth_prepass_.Uniform("u_clip"), 1, GL_FALSE,
                               viewer.data());
    gl.ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    gl.UseProgram(prepass);
    draw_scene(prepass, depth_prepass_.Uniform("u_model"), false);
    gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.DepthFunc(GL_EQUAL);
    gl.DepthMask(GL_FALSE);
    gl.UseProgram(program);
    draw_scene(program, shader.Uniform("u_model"), true);
    gl.DepthMask(GL_TRUE);
    gl.DepthFunc(GL_LESS);
    gl.BindVertexArray(0);
    gl.BindTextureUnit(kAtlasUnitA, 0);
    gl.BindTextureUnit(kAtlasUnitB, 0);
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    // The images belong to the caller: no attachment keeps them alive once it frees them.
    const GLenum attachments[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1,
                                  GL_COLOR_ATTACHMENT2, GL_DEPTH_ATTACHMENT};
    for (GLenum attachment : attachments) gl.NamedFramebufferTexture(fbo, attachment, 0, 0);
    // Atlases are kept for the next view unless large: a worker holds no more than this between
    // calls.
    constexpr std::int64_t kKeptAtlasTexels = std::int64_t{1} << 24;
    for (auto [atlas, extent] : {std::pair{&atlas_a_, &atlas_a_size_},
                                 std::pair{&atlas_b_, &atlas_b_size_}}) {
        if (static_cast<std::int64_t>(extent->width) * extent->height > kKeptAtlasTexels) {
            atlas->Reset();
            *extent = Viewport{};
        }
    }
    return context_->Check(std::string("view pass (") + ShadowMethodName(request.method) + ")");
}

Result<bool> ViewPass::FillAtlases(const ViewRequest& request, std::vector<kit::KitMap>& maps) {
    const GlApi& gl = context_->gl();
    const int max_side = context_->info().max_texture_size;
    std::vector<GLuint> a_textures;
    std::vector<Viewport> a_sizes;
    std::vector<GLuint> b_textures;
    std::vector<Viewport> b_sizes;
    std::vector<std::size_t> textured;  // the maps with texels (unshadowed ones have none)
    for (std::size_t i = 0; i < request.maps.size(); ++i) {
        const ViewMap& m = request.maps[i];
        if (m.lookup.unshadowed) continue;
        textured.push_back(i);
        const DepthMap& a = TextureA(m, request.method);
        a_textures.push_back(a.texture.id());
        a_sizes.push_back({a.map.width, a.map.height});
        if (request.method == ShadowMethod::kSilhouette) {
            b_textures.push_back(m.silhouette->points.id());
            b_sizes.push_back({m.map.width, m.map.height});
        }
    }
    if (textured.empty()) {
        // Every map unshadowed: the block still names an atlas, of one texel never read.
        EnsureTexture(gl, atlas_a_, GL_DEPTH_COMPONENT32F, {1, 1}, atlas_a_size_);
        atlas_a_size_ = {1, 1};
        gl.BindTextureUnit(kAtlasUnitA, atlas_a_.id());
        gl.BindTextureUnit(kAtlasUnitB, 0);
        return true;
    }
    auto placed_a = CopyIntoAtlas(gl, max_side, GL_DEPTH_COMPONENT32F, a_textures, a_sizes,
                                  kAtlasBorder, atlas_a_, atlas_a_size_);
    if (!placed_a) return placed_a.error();
    for (std::size_t k = 0; k < a_sizes.size(); ++k) maps[textured[k]].origin_a = (*placed_a)[k];
    gl.BindTextureUnit(kAtlasUnitA, atlas_a_.id());
    if (!b_textures.empty()) {
        // lixel_silhouette_point() tests its texel against the map itself: no border.
        auto placed_b = CopyIntoAtlas(gl, max_side, GL_RG32F, b_textures, b_sizes, 0, atlas_b_,
                                      atlas_b_size_);
        if (!placed_b) return placed_b.error();
        for (std::size_t k = 0; k < b_sizes.size(); ++k) maps[textured[k]].origin_b = (*placed_b)[k];
        gl.BindTextureUnit(kAtlasUnitB, atlas_b_.id());
    } else {
        gl.BindTextureUnit(kAtlasUnitB, 0);  // the kit reads "b" only for the silhouette map
    }
    return true;
}

}  // namespace lixel::render
