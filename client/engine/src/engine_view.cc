// The engine client's view (engine_view.h): its own programs around the client shader kit, the
// frame's meshes and maps, one depth pre-pass and one shading pass, read back.
#include <lixel/engine/engine_view.h>
#include <lixel/kit/shadow_block.h>
#include <lixel/solver/camera.h>
#include <lixel/solver/homogeneous.h>

#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "engine_shaders.h"

namespace lixel::engine {
namespace {

constexpr GLuint kBlockBinding = 0;  // uniform buffer binding of LixelShadowMaps
constexpr GLuint kAtlasUnitA = 0;
constexpr GLuint kAtlasUnitB = 1;  // lixel_atlas_b: only the silhouette test reads it

Result<GLuint> Compile(const client::GlFunctions& gl, GLenum stage, const std::string& source,
                       const char* name) {
    const GLuint shader = gl.CreateShader(stage);
    const GLchar* text = source.c_str();
    const GLint length = static_cast<GLint>(source.size());
    gl.ShaderSource(shader, 1, &text, &length);
    gl.CompileShader(shader);
    GLint ok = GL_FALSE;
    gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        GLint size = 0;
        gl.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &size);
        std::string log(static_cast<std::size_t>(std::max(size, 1)), '\0');
        gl.GetShaderInfoLog(shader, size, nullptr, log.data());
        gl.DeleteShader(shader);
        return Error{"gl", std::string(name) + " does not compile: " + log.c_str()};
    }
    return shader;
}

Result<GLuint> Link(const client::GlFunctions& gl, const std::string& vertex,
                    const std::string* fragment, const char* name) {
    auto vs = Compile(gl, GL_VERTEX_SHADER, vertex, "engine_view.vert");
    if (!vs) return vs.error();
    GLuint fs = 0;
    if (fragment != nullptr) {
        auto compiled = Compile(gl, GL_FRAGMENT_SHADER, *fragment, name);
        if (!compiled) {
            gl.DeleteShader(*vs);
            return compiled.error();
        }
        fs = *compiled;
    }
    const GLuint program = gl.CreateProgram();
    gl.AttachShader(program, *vs);
    if (fs != 0) gl.AttachShader(program, fs);
    gl.LinkProgram(program);
    gl.DeleteShader(*vs);  // flagged; freed with the program
    if (fs != 0) gl.DeleteShader(fs);
    GLint ok = GL_FALSE;
    gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        GLint size = 0;
        gl.GetProgramiv(program, GL_INFO_LOG_LENGTH, &size);
        std::string log(static_cast<std::size_t>(std::max(size, 1)), '\0');
        gl.GetProgramInfoLog(program, size, nullptr, log.data());
        gl.DeleteProgram(program);
        return Error{"gl", std::string(name) + " does not link: " + log.c_str()};
    }
    return program;
}

// As the solver uses the light (extent_hull.cc NormalizeLight): a point with w = 1, or a unit
// direction; the view pass's u_light is this, relative to the origin.
Result<Vec4> NormalizedLight(const Vec4& light) {
    if (!light.allFinite()) return Error{"camera.light", "not finite"};
    if (light.w() != 0.0) {
        const Vec4 point = light / light.w();
        if (!point.allFinite()) return Error{"camera.light", "point too far away to represent"};
        return point;
    }
    const double length = light.head<3>().norm();
    if (!(length > 0.0)) return Error{"camera.light", "a zero direction"};
    return Vec4(light / length);
}

Eigen::Vector4f Relative(const Vec4& point, const Vec3& origin) {
    return Vec4(point.x() - point.w() * origin.x(), point.y() - point.w() * origin.y(),
                point.z() - point.w() * origin.z(), point.w())
        .cast<float>();
}

}  // namespace

const char* EngineFilterName(EngineFilter filter) noexcept {
    switch (filter) {
        case EngineFilter::kDepth:
            return "depth";
        case EngineFilter::kPcf:
            return "pcf";
        case EngineFilter::kSecondDepth:
            return "second_depth";
        case EngineFilter::kSilhouette:
            return "silhouette_map";
    }
    return "?";
}

client::KitDepth KitDepthFor(EngineFilter filter) noexcept {
    switch (filter) {
        case EngineFilter::kSecondDepth:
            return client::KitDepth::kSecondDepth;
        case EngineFilter::kSilhouette:
            return client::KitDepth::kSilhouette;
        case EngineFilter::kDepth:
        case EngineFilter::kPcf:
            break;
    }
    return client::KitDepth::kDepth;
}

Result<EngineView> EngineView::Create(client::GlLoader loader) {
    auto gl = client::GlFunctions::Load(loader);
    if (!gl) return gl.error();
    auto uploader = client::KitUploader::Create(loader);
    if (!uploader) return uploader.error();
    EngineView view(*gl, std::move(uploader).value());
    const std::string version = "#version 450 core\n";
    const std::string vertex = version + "#line 1\n" + std::string(EngineViewVert());
    auto prepass = Link(*gl, vertex, nullptr, "depth pre-pass");
    if (!prepass) return prepass.error();
    view.prepass_ = *prepass;
    for (int filter = 0; filter < kEngineFilters; ++filter) {
        const std::string fragment =
            version + "#define LIXEL_MAX_MAPS " + std::to_string(kit::kMaxMaps) +
            "\n#define LIXEL_MAX_HALF_PLANES " + std::to_string(kit::kMaxHalfPlanes) +
            "\n#define ENGINE_FILTER " + std::to_string(filter) + "\n" + std::string(KitGlsl()) +
            "\n#line 1\n" + std::string(EngineViewFrag());
        auto program =
            Link(*gl, vertex, &fragment, EngineFilterName(static_cast<EngineFilter>(filter)));
        if (!program) return program.error();
        view.programs_[filter] = *program;
        gl->ProgramUniform1i(*program, gl->GetUniformLocation(*program, "lixel_atlas_a"),
                             kAtlasUnitA);
        gl->ProgramUniform1i(*program, gl->GetUniformLocation(*program, "lixel_atlas_b"),
                             kAtlasUnitB);
        const GLuint block = gl->GetUniformBlockIndex(*program, "LixelShadowMaps");
        if (block == GL_INVALID_INDEX) return Error{"gl", "no LixelShadowMaps block"};
        gl->UniformBlockBinding(*program, block, kBlockBinding);
    }
    gl->CreateVertexArrays(1, &view.vao_);
    gl->CreateBuffers(1, &view.positions_);
    gl->CreateBuffers(1, &view.indices_);
    gl->VertexArrayVertexBuffer(view.vao_, 0, view.positions_, 0, 3 * sizeof(float));
    gl->VertexArrayElementBuffer(view.vao_, view.indices_);
    gl->EnableVertexArrayAttrib(view.vao_, 0);
    gl->VertexArrayAttribFormat(view.vao_, 0, 3, GL_FLOAT, GL_FALSE, 0);
    gl->VertexArrayAttribBinding(view.vao_, 0, 0);
    gl->CreateFramebuffers(1, &view.framebuffer_);
    const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    gl->NamedFramebufferDrawBuffers(view.framebuffer_, 2, buffers);
    if (auto ok = gl->Check("gl"); !ok) return Error{"gl", "view setup: " + ok.error().reason};
    return view;
}

EngineView::EngineView(EngineView&& other) noexcept
    : gl_(other.gl_), uploader_(std::move(other.uploader_)) {
    TakeHandles(other);
}

EngineView& EngineView::operator=(EngineView&& other) noexcept {
    if (this == &other) return *this;
    Release();
    gl_ = other.gl_;
    uploader_ = std::move(other.uploader_);
    TakeHandles(other);
    return *this;
}

void EngineView::TakeHandles(EngineView& other) noexcept {
    for (int i = 0; i < kEngineFilters; ++i) programs_[i] = std::exchange(other.programs_[i], 0);
    prepass_ = std::exchange(other.prepass_, 0);
    vao_ = std::exchange(other.vao_, 0);
    positions_ = std::exchange(other.positions_, 0);
    indices_ = std::exchange(other.indices_, 0);
    framebuffer_ = std::exchange(other.framebuffer_, 0);
    mask_ = std::exchange(other.mask_, 0);
    colour_ = std::exchange(other.colour_, 0);
    depth_ = std::exchange(other.depth_, 0);
    target_size_ = std::exchange(other.target_size_, Viewport{});
    ranges_ = std::move(other.ranges_);
    origin_ = other.origin_;
    has_meshes_ = std::exchange(other.has_meshes_, false);
    has_kit_ = std::exchange(other.has_kit_, false);
    kit_has_maps_ = std::exchange(other.kit_has_maps_, false);
    kit_origin_ = other.kit_origin_;
}

EngineView::~EngineView() { Release(); }

void EngineView::Release() noexcept {
    if (gl_.DeleteProgram == nullptr) return;  // moved-from before loading: nothing made
    for (GLuint& p : programs_) {
        if (p != 0) gl_.DeleteProgram(p);
        p = 0;
    }
    if (prepass_ != 0) gl_.DeleteProgram(prepass_);
    if (vao_ != 0) gl_.DeleteVertexArrays(1, &vao_);
    const GLuint buffers[2] = {positions_, indices_};
    for (GLuint b : buffers) {
        if (b != 0) gl_.DeleteBuffers(1, &b);
    }
    if (framebuffer_ != 0) gl_.DeleteFramebuffers(1, &framebuffer_);
    const GLuint textures[3] = {mask_, colour_, depth_};
    for (GLuint t : textures) {
        if (t != 0) gl_.DeleteTextures(1, &t);
    }
    prepass_ = vao_ = positions_ = indices_ = framebuffer_ = mask_ = colour_ = depth_ = 0;
}

Result<bool> EngineView::UploadMeshes(std::span<const Mesh> meshes, const Vec3& origin) {
    if (meshes.empty()) return Error{"meshes", "no meshes to draw"};
    if (!origin.allFinite()) return Error{"origin", "not finite"};
    std::vector<float> positions;
    std::vector<std::uint32_t> indices;
    std::vector<Range> ranges;
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        const Mesh& mesh = meshes[m];
        const std::string field = "meshes[" + std::to_string(m) + "]";
        if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) {
            return Error{field + ".indices", "not a positive multiple of 3"};
        }
        const std::size_t base = positions.size() / 3;
        if (base + mesh.positions.size() > std::numeric_limits<std::uint32_t>::max()) {
            return Error{field + ".positions", "the scene exceeds 2^32 vertices"};
        }
        // glDrawElements counts indices in a GLsizei.
        if (indices.size() + mesh.indices.size() >
            static_cast<std::size_t>(std::numeric_limits<GLsizei>::max())) {
            return Error{field + ".indices", "the scene exceeds 2^31 - 1 indices"};
        }
        for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
            const Eigen::Vector3f& p = mesh.positions[i];
            if (!p.allFinite()) {
                return Error{field + ".positions[" + std::to_string(i) + "]", "not finite"};
            }
            // In double, then float: what lixel's GpuScene uploads, so both draw the same
            // triangles (light_map.h: float world positions far from the origin lose lixels).
            const Vec3 relative = p.cast<double>() - origin;
            for (int k = 0; k < 3; ++k) positions.push_back(static_cast<float>(relative[k]));
        }
        Range range;
        range.first_index = static_cast<std::uint32_t>(indices.size());
        range.index_count = static_cast<std::uint32_t>(mesh.indices.size());
        range.closed = mesh.closed;
        for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
            if (mesh.indices[i] >= mesh.positions.size()) {
                return Error{field + ".indices[" + std::to_string(i) + "]",
                             "index " + std::to_string(mesh.indices[i]) +
                                 " >= " + std::to_string(mesh.positions.size()) + " vertices"};
            }
            indices.push_back(static_cast<std::uint32_t>(base + mesh.indices[i]));
        }
        ranges.push_back(range);
    }
    gl_.NamedBufferData(positions_, static_cast<GLsizeiptr>(positions.size() * sizeof(float)),
                        positions.data(), GL_DYNAMIC_DRAW);
    gl_.NamedBufferData(indices_, static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)),
                        indices.data(), GL_DYNAMIC_DRAW);
    ranges_ = std::move(ranges);
    origin_ = origin;
    has_meshes_ = true;
    (void)PlaceMeshes({});
    if (auto ok = gl_.Check("gl"); !ok) return Error{"gl", "mesh upload: " + ok.error().reason};
    return true;
}

Result<bool> EngineView::UploadKit(const client::KitFrame& frame) {
    if (auto ok = uploader_.Upload(frame); !ok) return ok;
    has_kit_ = true;
    kit_has_maps_ = !frame.maps.empty();
    kit_origin_ = frame.origin;
    return true;
}

Result<bool> EngineView::EnsureTargets(const Viewport& size) {
    if (mask_ != 0 && target_size_.width == size.width && target_size_.height == size.height) {
        return true;
    }
    const GLuint textures[3] = {mask_, colour_, depth_};
    for (GLuint t : textures) {
        if (t != 0) gl_.DeleteTextures(1, &t);
    }
    const auto make = [&](GLenum format) {
        GLuint t = 0;
        gl_.CreateTextures(GL_TEXTURE_2D, 1, &t);
        gl_.TextureStorage2D(t, 1, format, size.width, size.height);
        gl_.TextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        gl_.TextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        return t;
    };
    mask_ = make(GL_R32F);
    colour_ = make(GL_RGBA8);
    depth_ = make(GL_DEPTH_COMPONENT32F);
    target_size_ = size;
    gl_.NamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, mask_, 0);
    gl_.NamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT1, colour_, 0);
    gl_.NamedFramebufferTexture(framebuffer_, GL_DEPTH_ATTACHMENT, depth_, 0);
    const GLenum status = gl_.CheckNamedFramebufferStatus(framebuffer_, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        return Error{"gl", "framebuffer incomplete (status " + std::to_string(status) + ")"};
    }
    return true;
}

Result<bool> EngineView::CheckDraw(const EngineCamera& camera, EngineFilter filter,
                                   const EngineShadowOptions& o, Vec4& light, Vec4& eye) const {
    if (auto ok = ValidateViewer(camera.viewer, camera.viewport, "camera.viewer"); !ok) {
        return ok.error();
    }
    GLint max_side = 0;
    gl_.GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_side);
    if (camera.viewport.width > max_side || camera.viewport.height > max_side) {
        return Error{"camera.viewport",
                     "larger than GL_MAX_TEXTURE_SIZE " + std::to_string(max_side)};
    }
    auto normalized = NormalizedLight(camera.light);
    if (!normalized) return normalized.error();
    light = *normalized;
    auto eye_point = EyePoint(camera.viewer);
    if (!eye_point) return Error{"camera.viewer", eye_point.error().reason};
    eye = *eye_point;
    const std::pair<const char*, float> biases[] = {
        {"options.depth_bias", o.depth_bias},
        {"options.slope_bias", o.slope_bias},
        {"options.max_bias", o.max_bias},
        {"options.second_depth_bias", o.second_depth_bias},
        {"options.open_second_depth_bias", o.open_second_depth_bias}};
    for (const auto& [field, value] : biases) {
        if (!(value >= 0.0f && std::isfinite(value))) {
            return Error{field, std::to_string(value) + " is not a finite value >= 0"};
        }
    }
    if (o.pcf_radius < 1 || o.pcf_radius > 4) {
        return Error{"options.pcf_radius", std::to_string(o.pcf_radius) + " outside [1, 4]"};
    }
    const int index = static_cast<int>(filter);
    if (index < 0 || index >= kEngineFilters) {
        return Error{"filter", "not depth, pcf, second_depth or silhouette_map"};
    }
    if (!has_meshes_) return Error{"meshes", "none uploaded (UploadMeshes)"};
    if (!has_kit_) return Error{"kit", "no maps uploaded (UploadKit)"};
    if (filter == EngineFilter::kSilhouette && !uploader_.has_atlas_b() && kit_has_maps_) {
        return Error{"kit",
                     "the silhouette test needs the silhouette points (atlas \"b\"): upload a "
                     "KitFrameOf(..., KitDepth::kSilhouette, ...)"};
    }
    if (kit_origin_ != origin_) {
        return Error{"origin",
                     "the kit frame's origin is not the meshes': positions and maps "
                     "would be relative to different points"};
    }
    return true;
}

Result<bool> EngineView::PlaceMeshes(std::span<const MeshInstance> instances) {
    std::vector<Placed> placed;
    if (instances.empty()) {
        for (std::size_t r = 0; r < ranges_.size(); ++r) {
            placed.push_back({static_cast<std::uint32_t>(r), Eigen::Matrix4f::Identity(), true});
        }
    }
    for (std::size_t i = 0; i < instances.size(); ++i) {
        const MeshInstance& instance = instances[i];
        const std::string field = "instances[" + std::to_string(i) + "]";
        if (instance.mesh >= ranges_.size()) {
            return Error{field + ".mesh", "mesh " + std::to_string(instance.mesh) + " >= " +
                                              std::to_string(ranges_.size()) + " uploaded"};
        }
        if (auto ok = CheckInstanceMatrix(instance.object_to_world, field + ".object_to_world");
            !ok) {
            return ok.error();
        }
        placed.push_back({instance.mesh,
                          RelativeObjectToWorld(instance.object_to_world, origin_).cast<float>(),
                          instance.receives});
    }
    placed_ = std::move(placed);
    return true;
}

void EngineView::SetUniforms(GLuint program, const EngineCamera& camera, const Vec4& light,
                             const Vec4& eye, const EngineShadowOptions& o) {
    const auto uniform = [&](const char* name) { return gl_.GetUniformLocation(program, name); };
    const Eigen::Matrix4f viewer = (camera.viewer * Translation(origin_)).cast<float>();
    gl_.ProgramUniformMatrix4fv(program, uniform("u_viewer"), 1, GL_FALSE, viewer.data());
    gl_.ProgramUniformMatrix4fv(prepass_, gl_.GetUniformLocation(prepass_, "u_viewer"), 1, GL_FALSE,
                                viewer.data());
    const Eigen::Vector4f light_relative = Relative(light, origin_);
    gl_.ProgramUniform4fv(program, uniform("u_light"), 1, light_relative.data());
    const Eigen::Vector4f eye_relative = Relative(eye, origin_);
    gl_.ProgramUniform4fv(program, uniform("u_eye"), 1, eye_relative.data());
    gl_.ProgramUniform1f(program, uniform("u_depth_bias"), o.depth_bias);
    gl_.ProgramUniform1f(program, uniform("u_slope_bias"), o.slope_bias);
    gl_.ProgramUniform1f(program, uniform("u_max_bias"), o.max_bias);
    gl_.ProgramUniform1f(program, uniform("u_second_depth_bias"), o.second_depth_bias);
    gl_.ProgramUniform1f(program, uniform("u_open_second_depth_bias"), o.open_second_depth_bias);
    gl_.ProgramUniform1i(program, uniform("u_pcf_radius"), o.pcf_radius);
    gl_.ProgramUniform1i(program, uniform("u_virtual_samples"), o.virtual_samples ? 1 : 0);
}

void EngineView::DrawMeshes(GLuint program, const Viewport& viewport) {
    const GLint receiver_open = gl_.GetUniformLocation(program, "u_receiver_open");
    // DESIGN §3: z/w in [0, 1], lower-left origin; pixel centres at +0.5 (GL's default). The
    // caller's clip convention is put back after the draw.
    GLint clip_origin = GL_LOWER_LEFT, clip_depth = GL_NEGATIVE_ONE_TO_ONE;
    gl_.GetIntegerv(GL_CLIP_ORIGIN, &clip_origin);
    gl_.GetIntegerv(GL_CLIP_DEPTH_MODE, &clip_depth);
    gl_.ClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    uploader_.Bind(kBlockBinding, kAtlasUnitA, kAtlasUnitB);
    gl_.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    gl_.Viewport(0, 0, viewport.width, viewport.height);
    gl_.Enable(GL_DEPTH_TEST);
    gl_.DepthFunc(GL_LESS);
    gl_.DepthMask(GL_TRUE);
    gl_.Disable(GL_CULL_FACE);  // open surfaces are seen from both sides
    gl_.Disable(GL_BLEND);
    const float no_surface[4] = {kEngineNoSurface, 0.0f, 0.0f, 0.0f};
    const float background[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    const float far = 1.0f;  // kClipDepthFar
    gl_.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl_.ClearNamedFramebufferfv(framebuffer_, GL_COLOR, 0, no_surface);
    gl_.ClearNamedFramebufferfv(framebuffer_, GL_COLOR, 1, background);
    gl_.ClearNamedFramebufferfv(framebuffer_, GL_DEPTH, 0, &far);
    gl_.BindVertexArray(vao_);
    const GLint receives = gl_.GetUniformLocation(program, "u_receives");
    const auto draw = [&](GLuint drawing, bool per_surface) {
        const GLint model = gl_.GetUniformLocation(drawing, "u_model");
        for (const Placed& p : placed_) {
            const Range& r = ranges_[p.range];
            gl_.ProgramUniformMatrix4fv(drawing, model, 1, GL_FALSE, p.model.data());
            if (per_surface) {
                gl_.ProgramUniform1i(program, receiver_open, r.closed ? 0 : 1);
                gl_.ProgramUniform1i(program, receives, p.receives ? 1 : 0);
            }
            gl_.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(r.index_count), GL_UNSIGNED_INT,
                             reinterpret_cast<const void*>(std::uintptr_t{r.first_index} *
                                                           sizeof(std::uint32_t)));
        }
    };
    // Depth first, then shade the nearest surface only (GL_EQUAL; gl_Position is invariant).
    gl_.ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    gl_.UseProgram(prepass_);
    draw(prepass_, false);
    gl_.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl_.DepthFunc(GL_EQUAL);
    gl_.DepthMask(GL_FALSE);
    gl_.UseProgram(program);
    draw(program, true);
    gl_.DepthMask(GL_TRUE);
    gl_.DepthFunc(GL_LESS);
    gl_.UseProgram(0);
    gl_.BindVertexArray(0);
    gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl_.ClipControl(static_cast<GLenum>(clip_origin), static_cast<GLenum>(clip_depth));
}

EngineImages EngineView::ReadImages(const Viewport& viewport) {
    EngineImages images;
    images.width = viewport.width;
    images.height = viewport.height;
    const std::size_t pixels = static_cast<std::size_t>(images.width) * images.height;
    images.mask.resize(pixels);
    std::vector<std::uint8_t> rgba(pixels * 4);
    {
        // Tightly packed rows into client memory; the caller's pack state after.
        const client::PixelStoreScope tight(gl_, client::PixelStoreScope::kPack);
        gl_.GetTextureImage(mask_, 0, GL_RED, GL_FLOAT,
                            static_cast<GLsizei>(pixels * sizeof(float)), images.mask.data());
        gl_.GetTextureImage(colour_, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                            static_cast<GLsizei>(rgba.size()), rgba.data());
    }
    images.rgb.resize(pixels * 3);
    for (std::size_t i = 0; i < pixels; ++i) {
        for (int c = 0; c < 3; ++c) images.rgb[3 * i + c] = rgba[4 * i + c];
    }
    return images;
}

Result<EngineImages> EngineView::Draw(const EngineCamera& camera, EngineFilter filter,
                                      const EngineShadowOptions& o) {
    Vec4 light, eye;
    if (auto ok = CheckDraw(camera, filter, o, light, eye); !ok) return ok.error();
    if (auto ok = EnsureTargets(camera.viewport); !ok) return ok.error();
    const GLuint program = programs_[static_cast<int>(filter)];
    SetUniforms(program, camera, light, eye, o);
    DrawMeshes(program, camera.viewport);
    EngineImages images = ReadImages(camera.viewport);
    if (auto ok = gl_.Check("gl"); !ok) return Error{"gl", "draw: " + ok.error().reason};
    return images;
}

}  // namespace lixel::engine
