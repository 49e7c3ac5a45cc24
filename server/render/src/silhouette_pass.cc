// Silhouette map: corner depths, then edges drawn with the diagonal rule in the fragment stage.
#include <lixel/render/map_transform.h>
#include <lixel/render/silhouette_pass.h>

#include <string>

namespace lixel::render {

Result<SilhouettePass> SilhouettePass::Create(GlContext& context) {
    auto program = BuildProgram(
        context, {"silhouette_map.vert", "silhouette_map.geom", "silhouette_map.frag"});
    if (!program) return program.error();
    const GlApi& gl = context.gl();
    GLuint fbo = 0;
    gl.CreateFramebuffers(1, &fbo);
    GLuint buffer = 0;
    gl.CreateBuffers(1, &buffer);
    GLuint vao = 0;
    gl.CreateVertexArrays(1, &vao);
    gl.EnableVertexArrayAttrib(vao, 0);
    gl.VertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    gl.VertexArrayAttribBinding(vao, 0, 0);
    gl.VertexArrayElementBuffer(vao, buffer);
    if (auto ok = context.Check("silhouette pass setup"); !ok) return ok.error();
    return SilhouettePass(context, std::move(program.value()), GlFramebuffer(gl, fbo),
                          GlBuffer(gl, buffer), GlVertexArray(gl, vao));
}

Result<bool> SilhouettePass::Render(const GpuScene& scene, const LightMap& map, const Vec4& light,
                                    const SilhouetteOptions& options, DepthPass& depth,
                                    SilhouetteMap& target) {
    if (auto ok = ValidateLightMap(map, context_->info().max_texture_size - 1, "map"); !ok) {
        return ok;
    }
    if (!light.allFinite() || (light.head<3>().isZero() && light.w() == 0.0)) {
        return Error{"light", "not finite, or a zero direction"};
    }
    if (!(options.visibility_bias >= 0.0f && options.visibility_bias < 1.0f)) {
        return Error{"silhouette.visibility_bias", "outside [0, 1)"};
    }
    if (auto ok = depth.Render(scene, CornerDepthMap(map), FaceSelection::kBoth, target.corners);
        !ok) {
        return ok;
    }
    const GlApi& gl = context_->gl();
    if (!target.points || target.map.width != map.width || target.map.height != map.height) {
        target.points = CreateTexture2D(gl, GL_RG32F, map.width, map.height);
    }
    target.map = map;
    gl.NamedFramebufferTexture(framebuffer_.id(), GL_COLOR_ATTACHMENT0, target.points.id(), 0);
    gl.NamedFramebufferDrawBuffer(framebuffer_.id(), GL_COLOR_ATTACHMENT0);
    const GLenum status = gl.CheckNamedFramebufferStatus(framebuffer_.id(), GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        return Error{"silhouette pass",
                     "framebuffer incomplete (status " + std::to_string(status) + ")"};
    }
    const MapTransform transform = MakeMapTransform(map, scene.origin());
    const Eigen::Vector4f relative_light = RelativePoint(light, scene.origin()).cast<float>();
    const GLuint program = program_.id();
    gl.ProgramUniformMatrix4fv(program, program_.Uniform("u_lixel"), 1, GL_FALSE,
                               transform.lixel.data());
    gl.ProgramUniform4fv(program, program_.Uniform("u_light"), 1, relative_light.data());
    gl.ProgramUniform2f(program, program_.Uniform("u_size"), static_cast<float>(map.width),
                        static_cast<float>(map.height));
    gl.ProgramUniform1f(program, program_.Uniform("u_bias"), options.visibility_bias);
    gl.ProgramUniform1i(program, program_.Uniform("u_corner_depth"), 0);

    gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
    gl.Viewport(0, 0, map.width, map.height);
    gl.Disable(GL_DEPTH_TEST);
    gl.Disable(GL_CULL_FACE);
    gl.Disable(GL_BLEND);
    gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    const float empty[4] = {kNoSilhouettePoint, kNoSilhouettePoint, 0.0f, 0.0f};
    gl.ClearNamedFramebufferfv(framebuffer_.id(), GL_COLOR, 0, empty);
    gl.UseProgram(program);
    gl.BindTextureUnit(0, target.corners.texture.id());
    std::size_t drawn = 0;
    const GLint model = program_.Uniform("u_model");
    const GLint mirrored = program_.Uniform("u_mirrored");
    if (options.cull_to_candidates && !scene.posed()) {
        // One draw of the candidates in scene order: the primitive sequence of the per-mesh
        // draws below with the triangles that emit nothing taken out, so every texel is written
        // by the same last edge. The candidates hold the buffer's positions: a posed scene
        // draws every instance's adjacency instead.
        scene.silhouette_candidates().Select(relative_light, selected_);
        drawn = selected_.size() / 6;
        if (drawn > 0) {
            gl.NamedBufferData(candidates_.id(),
                               static_cast<GLsizeiptr>(selected_.size() * sizeof(GLuint)),
                               selected_.data(), GL_STREAM_DRAW);
            gl.VertexArrayVertexBuffer(candidate_vao_.id(), 0, scene.positions(), 0,
                                       3 * sizeof(float));
            gl.BindVertexArray(candidate_vao_.id());
            gl.DrawElements(GL_TRIANGLES_ADJACENCY, static_cast<GLsizei>(selected_.size()),
                            GL_UNSIGNED_INT, nullptr);
            // Holds no scene's buffer past the render: a deleted scene's positions are freed.
            gl.VertexArrayVertexBuffer(candidate_vao_.id(), 0, 0, 0, 3 * sizeof(float));
        }
    } else {
        gl.BindVertexArray(scene.adjacency());
        for (const GpuDraw& draw : scene.draws()) {
            if (!draw.casts) continue;
            const GpuMeshRange& range = scene.ranges()[draw.range];
            gl.ProgramUniformMatrix4fv(program, model, 1, GL_FALSE, draw.model.data());
            gl.ProgramUniform1i(program, mirrored, draw.mirrored ? 1 : 0);
            gl.DrawElements(GL_TRIANGLES_ADJACENCY, static_cast<GLsizei>(range.adjacency_count),
                            GL_UNSIGNED_INT,
                            reinterpret_cast<const void*>(range.first_adjacency * sizeof(GLuint)));
            drawn += range.adjacency_count / 6;
        }
        const Mat4f identity = Mat4f::Identity();
        gl.ProgramUniformMatrix4fv(program, model, 1, GL_FALSE, identity.data());
        gl.ProgramUniform1i(program, mirrored, 0);
    }
    gl.BindVertexArray(0);
    gl.BindTextureUnit(0, 0);
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    // The map belongs to the caller: no attachment keeps it alive once it frees it.
    gl.NamedFramebufferTexture(framebuffer_.id(), GL_COLOR_ATTACHMENT0, 0, 0);
    if (auto ok = context_->Check("silhouette pass"); !ok) return ok;
    drawn_triangles_ = drawn;
    return true;
}

}  // namespace lixel::render
