// Depth, counting, lit marking. GL state is restored to the renderer's defaults (depth test LESS
// with writes, no stencil, no depth clamp, no blending with blend function (ONE, ZERO), colour
// writes on, texture unit 0 unbound) after each call.
#include <lixel/render/map_transform.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/mesh_instance.h>
#include <lixel/volumes/gl/volume_pass.h>
#include <lixel/volumes/gl/volume_shaders.h>
#include <lixel/volumes/multiplicity.h>

#include <algorithm>
#include <optional>
#include <span>
#include <string>

namespace lixel::volumes::gl {
namespace {

// Polygon offset of the light caps: a cap lies on its own triangle, and must count as behind
// that surface (z-fail counts faces behind a pixel), or every lit surface would shadow itself.
constexpr float kCapOffsetFactor = 1.0f;
constexpr float kCapOffsetUnits = 4.0f;

// The count target (issue 16.2): R32F with additive blending of +-1 is exact for any count of
// magnitude up to 2^24 (every partial sum is an integer float represents exactly), so no
// realistic depth complexity wraps it; R16F would stop at 2^11, an 8-bit stencil wraps at 2^8.
// Integer formats cannot blend.
constexpr GLenum kCountFormat = GL_R32F;
// The texture unit the lit draw reads the count from.
constexpr GLuint kCountUnit = 0;

// Largest indexed GL_PATCHES draw llvmpipe gets right (see Create).
constexpr std::size_t kSoftwarePatchIndicesPerDraw = 1024;

Result<bool> Validate(const VolumeRequest& r, int max_texture_size) {
    if (auto ok = ValidateViewer(r.viewer, r.viewport, "viewer"); !ok) return ok;
    if (r.viewport.width > max_texture_size || r.viewport.height > max_texture_size) {
        return Error{"viewport",
                     "larger than the GL maximum texture size " + std::to_string(max_texture_size)};
    }
    if (auto l = NormalizeLight(r.light); !l) return l.error();
    return true;
}

}  // namespace

Result<VolumePass> VolumePass::Create(render::GlContext& context) {
    VolumePass pass;
    pass.context_ = &context;
    auto api = LoadVolumeGlApi(context);
    if (!api) return api.error();
    pass.api_ = *api;
    const render::ShaderLookup lookup = VolumeShaderLookup();
    auto surface =
        render::BuildProgram(context, {"volume_surface.vert", "volume_surface.frag"}, {}, lookup);
    if (!surface) return surface.error();
    auto sides = render::BuildProgram(
        context,
        {"shadow_volume.vert", "shadow_volume.tesc", "shadow_volume.tese", "shadow_volume.frag"},
        {}, lookup);
    if (!sides) return sides.error();
    auto caps = render::BuildProgram(
        context, {"volume_caps.vert", "volume_caps.geom", "shadow_volume.frag"}, {}, lookup);
    if (!caps) return caps.error();
    auto mesh =
        render::BuildProgram(context, {"volume_mesh.vert", "shadow_volume.frag"}, {}, lookup);
    if (!mesh) return mesh.error();
    pass.surface_ = std::move(surface.value());
    pass.sides_ = std::move(sides.value());
    pass.caps_ = std::move(caps.value());
    pass.mesh_ = std::move(mesh.value());
    const render::GlApi& gl = context.gl();
    GLuint fbo = 0;
    gl.CreateFramebuffers(1, &fbo);
    const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    gl.NamedFramebufferDrawBuffers(fbo, 3, buffers);
    pass.framebuffer_ = render::GlFramebuffer(gl, fbo);
    gl.CreateFramebuffers(1, &fbo);
    gl.NamedFramebufferDrawBuffer(fbo, GL_COLOR_ATTACHMENT0);
    pass.count_framebuffer_ = render::GlFramebuffer(gl, fbo);
    // PatchMultiplicities draws with rasterisation off, but still needs a complete framebuffer.
    gl.CreateFramebuffers(1, &fbo);
    pass.discard_framebuffer_ = render::GlFramebuffer(gl, fbo);
    pass.discard_target_ = render::CreateTexture2D(gl, GL_R8, 1, 1);
    gl.NamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, pass.discard_target_.id(), 0);
    // Mesa's llvmpipe (22.3) feeds the tessellation control stage the wrong vertices in indexed
    // GL_PATCHES draws of more than 1024 indices (found by the GPU-vs-CPU multiplicity test);
    // such draws are split there. Other drivers draw all patches at once.
    if (context.info().renderer.find("llvmpipe") != std::string::npos ||
        context.info().renderer.find("softpipe") != std::string::npos) {
        pass.patch_indices_per_draw_ = kSoftwarePatchIndicesPerDraw;
    }
    if (auto ok = context.Check("volume pass setup"); !ok) return ok.error();
    return pass;
}

void VolumePass::DrawPatches(const VolumeScene& volumes, std::optional<std::uint32_t> mesh) {
    const render::GlApi& gl = context_->gl();
    const GLuint p = sides_.id();
    gl.BindVertexArray(volumes.patches());
    std::size_t first_index = 0;
    for (const PatchGroup& group : volumes.patch_groups()) {
        const auto per_patch = static_cast<std::size_t>(group.vertices);
        const std::size_t group_index = first_index;
        first_index += group.patches * per_patch;
        if (mesh && group.mesh != *mesh) continue;
        const std::size_t chunk =
            patch_indices_per_draw_ == 0
                ? group.patches
                : std::max<std::size_t>(1, patch_indices_per_draw_ / per_patch);
        api_.PatchParameteri(GL_PATCH_VERTICES, group.vertices);
        for (std::size_t first = 0; first < group.patches; first += chunk) {
            const std::size_t n = std::min(chunk, group.patches - first);
            // gl_PrimitiveID restarts with every draw; u_patch_base keeps recorded ids global.
            gl.ProgramUniform1i(p, sides_.Uniform("u_patch_base"),
                                static_cast<GLint>(group.first_patch + first));
            const std::size_t offset = group_index + first * per_patch;
            gl.DrawElements(GL_PATCHES, static_cast<GLsizei>(n * per_patch), GL_UNSIGNED_INT,
                            reinterpret_cast<const void*>(offset * sizeof(GLuint)));
        }
    }
}

std::vector<VolumePass::CasterDraw> VolumePass::Casters(const render::GpuScene& surfaces,
                                                        const Vec4& light_world) {
    const Vec4 light = render::RelativePoint(light_world, surfaces.origin());
    std::vector<CasterDraw> casters;
    for (const render::GpuDraw& draw : surfaces.draws()) {
        if (!draw.casts) continue;
        CasterDraw caster;
        caster.mesh = draw.range;
        caster.model = draw.model;
        caster.mirrored = draw.mirrored;
        // The light carried back through the float matrix the GPU places the points with, so
        // facing and extrusion are decided on exactly the geometry drawn; the identity (a mesh
        // in place) carries it exactly.
        caster.light = ObjectSpaceLight(draw.model.cast<double>(), light).cast<float>();
        casters.push_back(caster);
    }
    return casters;
}

void VolumePass::DrawVolumes(const VolumeScene& volumes, const GpuVolumeMesh* volume,
                             std::span<const CasterDraw> casters, CountingMode mode, float front,
                             const Eigen::Matrix4f& viewer, VolumeRenderInfo& info) {
    const render::GlApi& gl = context_->gl();
    const bool caps = mode == CountingMode::kZFail;
    if (volume != nullptr) {
        if (info.modes.empty() || info.modes[0] != mode) return;
        const GLuint p = mesh_.id();
        gl.UseProgram(p);
        gl.ProgramUniform1f(p, mesh_.Uniform("u_front"), front);
        gl.ProgramUniformMatrix4fv(p, mesh_.Uniform("u_viewer"), 1, GL_FALSE, viewer.data());
        gl.BindVertexArray(volume->vertex_array());
        gl.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(volume->side_indices()), GL_UNSIGNED_INT,
                        nullptr);
        if (caps && volume->cap_indices() > 0) {
            gl.Enable(GL_POLYGON_OFFSET_FILL);
            api_.PolygonOffset(kCapOffsetFactor, kCapOffsetUnits);
            gl.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(volume->cap_indices()),
                            GL_UNSIGNED_INT,
                            reinterpret_cast<const void*>(volume->side_indices() * sizeof(GLuint)));
            gl.Disable(GL_POLYGON_OFFSET_FILL);
            info.cap_triangles += volume->cap_indices() / 3;
        }
        return;
    }
    const GLuint sp = sides_.id();
    const GLuint cp = caps_.id();
    gl.ProgramUniformMatrix4fv(sp, sides_.Uniform("u_viewer"), 1, GL_FALSE, viewer.data());
    gl.ProgramUniform1i(sp, sides_.Uniform("u_record"), 0);
    gl.ProgramUniformMatrix4fv(cp, caps_.Uniform("u_viewer"), 1, GL_FALSE, viewer.data());
    for (std::size_t c = 0; c < casters.size(); ++c) {
        if (info.modes[c] != mode) continue;
        const CasterDraw& caster = casters[c];
        // A mirror turns every face's screen winding, so each face's contribution turns too.
        const float sign = caster.mirrored ? -front : front;
        for (const render::Program* program : {&sides_, &caps_}) {
            const GLuint id = program->id();
            gl.ProgramUniform1f(id, program->Uniform("u_front"), sign);
            gl.ProgramUniformMatrix4fv(id, program->Uniform("u_model"), 1, GL_FALSE,
                                       caster.model.data());
            gl.ProgramUniform4fv(id, program->Uniform("u_light"), 1, caster.light.data());
        }
        gl.UseProgram(sp);
        DrawPatches(volumes, caster.mesh);
        for (const PatchGroup& group : volumes.patch_groups()) {
            if (group.mesh == caster.mesh) info.patches += group.patches;
        }
        const CapRange& range = volumes.cap_ranges()[caster.mesh];
        if (!caps || range.triangles == 0) continue;
        gl.UseProgram(cp);
        gl.Enable(GL_POLYGON_OFFSET_FILL);
        api_.PolygonOffset(kCapOffsetFactor, kCapOffsetUnits);
        gl.BindVertexArray(volumes.caps());
        gl.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(3 * range.triangles), GL_UNSIGNED_INT,
                        reinterpret_cast<const void*>(3 * range.first_triangle * sizeof(GLuint)));
        gl.Disable(GL_POLYGON_OFFSET_FILL);
        info.cap_triangles += range.triangles;
    }
}

Result<VolumeRenderInfo> VolumePass::Render(const render::GpuScene& surfaces,
                                            const VolumeScene& volumes,
                                            const VolumeRequest& request,
                                            render::ViewImages& target) {
    return Draw(surfaces, volumes, nullptr, request, target);
}

Result<VolumeRenderInfo> VolumePass::Render(const render::GpuScene& surfaces,
                                            const VolumeScene& volumes, const GpuVolumeMesh& volume,
                                            const VolumeRequest& request,
                                            render::ViewImages& target) {
    return Draw(surfaces, volumes, &volume, request, target);
}

namespace {

bool UsesMode(const VolumeRenderInfo& info, CountingMode mode) {
    return std::find(info.modes.begin(), info.modes.end(), mode) != info.modes.end();
}

// A draw's object -> world matrix in world coordinates (its model matrix is relative to the
// origin on both sides): T(o) model T(-o), in double.
Mat4 WorldMatrix(const render::GpuDraw& draw, const Vec3& origin) {
    Mat4 m = draw.model.cast<double>();
    m.topRightCorner<3, 1>() += origin - m.topLeftCorner<3, 3>() * origin;
    return m;
}

// Which counting, per caster: z-pass only for casters that cannot reach the eye or the near
// rectangle (counting_mode.h). A posed draw is tested on its mesh's own coordinates against the
// light and the viewer carried there (the hull's incidences are affine invariants). A CPU-built
// volume is one caster, its occluders the posed meshes and its own finite triangles.
Result<bool> ChooseModes(const render::GpuScene& surfaces, const VolumeScene& volumes,
                         const GpuVolumeMesh* volume, std::size_t casters,
                         const VolumeRequest& request, VolumeRenderInfo& info) {
    const std::size_t count = volume != nullptr ? 1 : casters;
    if (request.counting != CountingChoice::kAuto) {
        info.modes.assign(count, request.counting == CountingChoice::kZPass ? CountingMode::kZPass
                                                                            : CountingMode::kZFail);
    } else if (!surfaces.posed()) {
        std::vector<const EdgeAdjacency*> meshes;
        for (const EdgeAdjacency& a : volumes.adjacency()) meshes.push_back(&a);
        if (volume == nullptr) {
            auto modes = ChooseCountingModes(meshes, request.light, request.viewer);
            if (!modes) return modes.error();
            info.modes = std::move(modes.value());
        } else {
            auto mode = ChooseCountingMode(meshes, request.light, request.viewer);
            if (!mode) return mode.error();
            info.modes = {*mode};
        }
    } else {
        for (const render::GpuDraw& draw : surfaces.draws()) {
            if (!draw.casts) continue;
            if (request.cancelled && request.cancelled()) {
                return Error{"request", "cancelled"};
            }
            const Mat4 m = WorldMatrix(draw, surfaces.origin());
            const EdgeAdjacency* mesh = &volumes.adjacency()[draw.range];
            auto mode = ChooseCountingMode(std::span<const EdgeAdjacency* const>(&mesh, 1),
                                           ObjectSpaceLight(m, request.light), request.viewer * m);
            if (!mode) return mode.error();
            info.modes.push_back(*mode);
        }
        if (volume != nullptr) {
            info.modes = {UsesMode(info, CountingMode::kZFail) ? CountingMode::kZFail
                                                               : CountingMode::kZPass};
        }
    }
    if (volume != nullptr && request.counting == CountingChoice::kAuto &&
        info.modes[0] == CountingMode::kZPass) {
        auto mode = ChooseCountingMode(volume->source(), request.light, request.viewer);
        if (!mode) return mode.error();
        info.modes = {*mode};
    }
    info.mode = UsesMode(info, CountingMode::kZFail) ? CountingMode::kZFail : CountingMode::kZPass;
    if (volume != nullptr && info.mode == CountingMode::kZFail && volume->cap_indices() == 0 &&
        volume->side_indices() > 0) {
        return Error{"volume.caps", "z-fail needs a volume built with Caps::kLightAndDark"};
    }
    return true;
}

}  // namespace

Result<bool> VolumePass::AttachTargets(const Viewport& size, render::ViewImages& target) {
    const render::GlApi& gl = context_->gl();
    const bool resize =
        size.width != target.viewport.width || size.height != target.viewport.height;
    if (!target.mask || resize)
        target.mask = render::CreateTexture2D(gl, GL_R32F, size.width, size.height);
    if (!target.preview || resize) {
        target.preview = render::CreateTexture2D(gl, GL_RGBA8, size.width, size.height);
    }
    if (!target.map_index || resize) {
        target.map_index = render::CreateTexture2D(gl, GL_R32I, size.width, size.height);
    }
    if (!target.depth || resize || target.depth.id() != own_depth_) {
        target.depth = render::CreateTexture2D(gl, GL_DEPTH32F_STENCIL8, size.width, size.height);
        own_depth_ = target.depth.id();
    }
    if (!count_ || size.width != count_size_.width || size.height != count_size_.height) {
        count_ = render::CreateTexture2D(gl, kCountFormat, size.width, size.height);
        count_size_ = size;
    }
    target.viewport = size;
    const GLuint fbo = framebuffer_.id();
    gl.NamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, target.mask.id(), 0);
    gl.NamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT1, target.preview.id(), 0);
    gl.NamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT2, target.map_index.id(), 0);
    gl.NamedFramebufferTexture(fbo, GL_DEPTH_STENCIL_ATTACHMENT, target.depth.id(), 0);
    const GLuint count_fbo = count_framebuffer_.id();
    gl.NamedFramebufferTexture(count_fbo, GL_COLOR_ATTACHMENT0, count_.id(), 0);
    gl.NamedFramebufferTexture(count_fbo, GL_DEPTH_STENCIL_ATTACHMENT, target.depth.id(), 0);
    for (const GLuint f : {fbo, count_fbo}) {
        const GLenum status = gl.CheckNamedFramebufferStatus(f, GL_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE) {
            return Error{"volume pass",
                         "framebuffer incomplete (status " + std::to_string(status) + ")"};
        }
    }
    const float no_surface[4] = {render::kNoSurface, 0.0f, 0.0f, 0.0f};
    const float background[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    const GLint no_map[4] = {render::kNoMap, 0, 0, 0};
    gl.ClearNamedFramebufferfv(fbo, GL_COLOR, 0, no_surface);
    gl.ClearNamedFramebufferfv(fbo, GL_COLOR, 1, background);
    gl.ClearNamedFramebufferiv(fbo, GL_COLOR, 2, no_map);
    api_.ClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, static_cast<float>(kClipDepthFar), 0);
    gl.ClearNamedFramebufferfv(count_fbo, GL_COLOR, 0, zero);
    return true;
}

void VolumePass::DrawSurfaces(const render::GpuScene& surfaces) {
    const render::GlApi& gl = context_->gl();
    const GLuint p = surface_.id();
    gl.UseProgram(p);
    gl.BindVertexArray(surfaces.triangles());
    for (const render::GpuDraw& draw : surfaces.draws()) {
        const render::GpuMeshRange& range = surfaces.ranges()[draw.range];
        gl.ProgramUniformMatrix4fv(p, surface_.Uniform("u_model"), 1, GL_FALSE, draw.model.data());
        gl.ProgramUniform1i(p, surface_.Uniform("u_receives"), draw.receives ? 1 : 0);
        gl.ProgramUniform1i(p, surface_.Uniform("u_casts"), draw.casts ? 1 : 0);
        gl.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(range.index_count), GL_UNSIGNED_INT,
                        reinterpret_cast<const void*>(range.first_index * sizeof(GLuint)));
    }
}

// Into the count target: each fragment adds +1 or -1 (shadow_volume.frag), in float, exact for
// any count below 2^24 where an 8-bit stencil would wrap at 256 (issue 16.2). Z-pass casters
// count the fragments in front of the surface (depth LESS) with the near plane clipping, so the
// count starts at the near rectangle, which their proof covers; z-fail casters count those
// behind it (GEQUAL: exactly where LESS fails), front faces -1, with caps and depth clamp, which
// keeps the dark caps and the sides' far ends, at infinity, from being clipped. Each caster's
// count is exact for its own volumes, so the sum is too.
void VolumePass::CountVolumes(const VolumeScene& volumes, const GpuVolumeMesh* volume,
                              std::span<const CasterDraw> casters, const Eigen::Matrix4f& viewer,
                              VolumeRenderInfo& info) {
    const render::GlApi& gl = context_->gl();
    gl.BindFramebuffer(GL_FRAMEBUFFER, count_framebuffer_.id());
    gl.ColorMask(GL_TRUE, GL_FALSE, GL_FALSE, GL_FALSE);
    gl.DepthMask(GL_FALSE);
    gl.Enable(GL_BLEND);
    api_.BlendEquation(GL_FUNC_ADD);
    api_.BlendFunc(GL_ONE, GL_ONE);
    gl.FrontFace(GL_CCW);
    for (const CountingMode mode : {CountingMode::kZPass, CountingMode::kZFail}) {
        if (!UsesMode(info, mode)) continue;
        const bool zfail = mode == CountingMode::kZFail;
        const float sign = zfail ? -1.0f : 1.0f;  // added by front faces; back faces add -sign
        if (zfail) {
            gl.Enable(GL_DEPTH_CLAMP);
        } else {
            gl.Disable(GL_DEPTH_CLAMP);
        }
        gl.DepthFunc(zfail ? GL_GEQUAL : GL_LESS);
        DrawVolumes(volumes, volume, casters, mode, sign, viewer, info);
    }
    gl.Disable(GL_DEPTH_CLAMP);
    gl.Disable(GL_BLEND);
}

// Overdraw: every volume fragment, depth test off, nothing written.
void VolumePass::MeasureOverdraw(const VolumeScene& volumes, const GpuVolumeMesh* volume,
                                 std::span<const CasterDraw> casters, const Eigen::Matrix4f& viewer,
                                 const Viewport& size, VolumeRenderInfo& info) {
    const render::GlApi& gl = context_->gl();
    gl.Disable(GL_DEPTH_TEST);
    gl.Enable(GL_DEPTH_CLAMP);
    gl.ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    GLuint query = 0;
    api_.CreateQueries(GL_SAMPLES_PASSED, 1, &query);
    api_.BeginQuery(GL_SAMPLES_PASSED, query);
    VolumeRenderInfo ignored;
    ignored.modes = info.modes;
    for (const CountingMode mode : {CountingMode::kZPass, CountingMode::kZFail}) {
        if (UsesMode(info, mode)) {
            DrawVolumes(volumes, volume, casters, mode, 1.0f, viewer, ignored);
        }
    }
    api_.EndQuery(GL_SAMPLES_PASSED);
    GLuint64 samples = 0;
    api_.GetQueryObjectui64v(query, GL_QUERY_RESULT, &samples);
    api_.DeleteQueries(1, &query);
    info.volume_fragments = samples;
    info.overdraw = static_cast<double>(samples) /
                    (static_cast<double>(size.width) * static_cast<double>(size.height));
    gl.Disable(GL_DEPTH_CLAMP);
    gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

Result<VolumeRenderInfo> VolumePass::Draw(const render::GpuScene& surfaces,
                                          const VolumeScene& volumes, const GpuVolumeMesh* volume,
                                          const VolumeRequest& request,
                                          render::ViewImages& target) {
    if (auto ok = Validate(request, context_->info().max_texture_size); !ok) return ok.error();
    if (surfaces.origin() != volumes.origin()) {
        return Error{"origin", "surfaces and volumes were uploaded with different origins"};
    }
    // Everything that can fail before any GL state changes.
    auto eye = EyePoint(request.viewer);
    if (!eye) return eye.error();
    VolumeRenderInfo info;
    const std::vector<CasterDraw> casters = Casters(surfaces, *NormalizeLight(request.light));
    if (auto ok = ChooseModes(surfaces, volumes, volume, casters.size(), request, info); !ok) {
        return ok.error();
    }
    const render::GlApi& gl = context_->gl();
    const Viewport& size = request.viewport;
    if (auto ok = AttachTargets(size, target); !ok) return ok.error();
    const Vec3& origin = volumes.origin();
    const Eigen::Matrix4f viewer = render::RelativeMatrix(request.viewer, origin);
    const Vec4 light_world = *NormalizeLight(request.light);
    const Eigen::Vector4f light = render::RelativePoint(light_world, origin).cast<float>();

    gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
    gl.Viewport(0, 0, size.width, size.height);
    // 1. Depth of the visible surfaces; every surface pixel starts as shadowed (mask 0).
    const GLuint sp = surface_.id();
    gl.ProgramUniformMatrix4fv(sp, surface_.Uniform("u_viewer"), 1, GL_FALSE, viewer.data());
    gl.ProgramUniform4fv(sp, surface_.Uniform("u_light"), 1, light.data());
    const Eigen::Vector4f eye_relative = render::RelativePoint(*eye, origin).cast<float>();
    gl.ProgramUniform4fv(sp, surface_.Uniform("u_eye"), 1, eye_relative.data());
    gl.ProgramUniform1f(sp, surface_.Uniform("u_lit"), 0.0f);
    gl.ProgramUniform1i(sp, surface_.Uniform("u_count"), kCountUnit);
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LESS);
    gl.DepthMask(GL_TRUE);
    gl.Disable(GL_CULL_FACE);
    gl.Disable(GL_BLEND);
    gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    DrawSurfaces(surfaces);

    // 2. The volumes' count per pixel.
    CountVolumes(volumes, volume, casters, viewer, info);

    // 3. Lit where the count is zero: the same surfaces, same depth (invariant), mask 1.
    gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
    gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl.DepthFunc(GL_EQUAL);
    gl.BindTextureUnit(kCountUnit, count_.id());
    gl.ProgramUniform1f(sp, surface_.Uniform("u_lit"), 1.0f);
    DrawSurfaces(surfaces);
    gl.BindTextureUnit(kCountUnit, 0);

    if (request.measure_overdraw) MeasureOverdraw(volumes, volume, casters, viewer, size, info);

    gl.Disable(GL_STENCIL_TEST);
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LESS);
    gl.DepthMask(GL_TRUE);
    api_.BlendFunc(GL_ONE, GL_ZERO);
    gl.BindVertexArray(0);
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    if (auto ok = context_->Check(std::string("volume pass (") + CountingModeName(info.mode) + ")");
        !ok) {
        return ok.error();
    }
    return info;
}

Result<std::vector<int>> VolumePass::PatchMultiplicities(const VolumeScene& volumes,
                                                         const Vec4& light) {
    auto l = NormalizeLight(light);
    if (!l) return l.error();
    const render::GlApi& gl = context_->gl();
    const std::size_t count = volumes.patch_count();
    std::vector<int> out(count, 0);
    if (count == 0) return out;
    GLuint buffer = 0;
    gl.CreateBuffers(1, &buffer);
    const render::GlBuffer storage(gl, buffer);
    gl.NamedBufferStorage(buffer, static_cast<GLsizeiptr>(count * sizeof(int)), out.data(), 0);
    api_.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffer);
    const Eigen::Vector4f relative = render::RelativePoint(*l, volumes.origin()).cast<float>();
    const Eigen::Matrix4f identity = Eigen::Matrix4f::Identity();
    const GLuint p = sides_.id();
    gl.UseProgram(p);
    gl.ProgramUniformMatrix4fv(p, sides_.Uniform("u_viewer"), 1, GL_FALSE, identity.data());
    gl.ProgramUniformMatrix4fv(p, sides_.Uniform("u_model"), 1, GL_FALSE, identity.data());
    gl.ProgramUniform4fv(p, sides_.Uniform("u_light"), 1, relative.data());
    gl.ProgramUniform1i(p, sides_.Uniform("u_record"), 1);
    gl.BindFramebuffer(GL_FRAMEBUFFER, discard_framebuffer_.id());
    gl.Enable(GL_RASTERIZER_DISCARD);
    DrawPatches(volumes, std::nullopt);
    gl.Disable(GL_RASTERIZER_DISCARD);
    gl.ProgramUniform1i(p, sides_.Uniform("u_record"), 0);
    gl.BindVertexArray(0);
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    api_.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // shader writes before the read-back
    api_.GetNamedBufferSubData(buffer, 0, static_cast<GLsizeiptr>(count * sizeof(int)), out.data());
    api_.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
    if (auto ok = context_->Check("patch multiplicities"); !ok) return ok.error();
    return out;
}

}  // namespace lixel::volumes::gl
