// Depth-only rendering into a float32 depth texture; face culling chosen per mesh.
#include <lixel/render/depth_pass.h>
#include <lixel/render/map_transform.h>

#include <algorithm>
#include <string>

namespace lixel::render {

const char* FaceSelectionName(FaceSelection faces) noexcept {
    switch (faces) {
        case FaceSelection::kBoth:
            return "both";
        case FaceSelection::kLightFacing:
            return "light-facing";
        case FaceSelection::kAwayFacing:
            return "away-facing";
        case FaceSelection::kSecondDepth:
            return "second-depth";
    }
    return "?";
}

Result<bool> ValidateLightMap(const LightMap& map, int max_texture_size, const char* field) {
    const int limit = std::min(kMaxImageSide, max_texture_size);
    if (map.width < 1 || map.width > limit) {
        return Error{std::string(field) + ".width",
                     std::to_string(map.width) + " outside [1, " + std::to_string(limit) + "]"};
    }
    if (map.height < 1 || map.height > limit) {
        return Error{std::string(field) + ".height",
                     std::to_string(map.height) + " outside [1, " + std::to_string(limit) + "]"};
    }
    if (!map.matrix.allFinite()) return Error{std::string(field) + ".matrix", "not finite"};
    return true;
}

Result<DepthPass> DepthPass::Create(GlContext& context) {
    auto program = BuildProgram(context, {"depth.vert"});
    if (!program) return program.error();
    GLuint fbo = 0;
    context.gl().CreateFramebuffers(1, &fbo);
    context.gl().NamedFramebufferDrawBuffer(fbo, GL_NONE);
    context.gl().NamedFramebufferReadBuffer(fbo, GL_NONE);
    DepthPass pass(context, std::move(program.value()), GlFramebuffer(context.gl(), fbo));
    pass.clip_location_ = pass.program_.Uniform("u_clip");
    pass.model_location_ = pass.program_.Uniform("u_model");
    return pass;
}

Result<DepthMap> DepthPass::Render(const GpuScene& scene, const LightMap& map,
                                   FaceSelection faces) {
    DepthMap target;
    if (auto ok = Render(scene, map, faces, target); !ok) return ok.error();
    return target;
}

Result<bool> DepthPass::Render(const GpuScene& scene, const LightMap& map, FaceSelection faces,
                               DepthMap& target) {
    if (auto ok = ValidateLightMap(map, context_->info().max_texture_size, "map"); !ok) return ok;
    const GlApi& gl = context_->gl();
    if (!target.texture || target.map.width != map.width || target.map.height != map.height) {
        target.texture = CreateTexture2D(gl, GL_DEPTH_COMPONENT32F, map.width, map.height);
    }
    target.map = map;
    // Attached on every render and detached after it: a texture name says nothing about which
    // texture it is once the one before was deleted (drivers reuse names; NVIDIA does by
    // default), and an attachment left in place would keep a freed map's storage alive.
    gl.NamedFramebufferTexture(framebuffer_.id(), GL_DEPTH_ATTACHMENT, target.texture.id(), 0);
    const GLenum status = gl.CheckNamedFramebufferStatus(framebuffer_.id(), GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        gl.NamedFramebufferTexture(framebuffer_.id(), GL_DEPTH_ATTACHMENT, 0, 0);
        return Error{"depth pass",
                     "framebuffer incomplete (status " + std::to_string(status) + ")"};
    }
    const MapTransform transform = MakeMapTransform(map, scene.origin());
    gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
    gl.Viewport(0, 0, map.width, map.height);
    gl.Enable(GL_DEPTH_TEST);
    // depth_row.h: geometry nearer the light than the depth row's kMinNearRatio floor is kept
    // as an occluder at stored depth kStoredDepthNear rather than clipped away.
    gl.Enable(GL_DEPTH_CLAMP);
    // Reversed-Z (light_map.h): the nearest surface has the greatest stored depth.
    gl.DepthFunc(GL_GREATER);
    gl.DepthMask(GL_TRUE);
    gl.Disable(GL_BLEND);
    const float far = static_cast<float>(kStoredDepthFar);
    gl.ClearNamedFramebufferfv(framebuffer_.id(), GL_DEPTH, 0, &far);
    gl.UseProgram(program_.id());
    gl.ProgramUniformMatrix4fv(program_.id(), clip_location_, 1, GL_FALSE, transform.clip.data());
    gl.BindVertexArray(scene.triangles());
    for (const GpuDraw& draw : scene.draws()) {
        if (!draw.casts) continue;
        const GpuMeshRange& range = scene.ranges()[draw.range];
        // GL_FRONT = facing the light; a mirrored instance turns its triangles' winding.
        gl.FrontFace(!draw.mirrored                             ? transform.light_facing_winding
                     : transform.light_facing_winding == GL_CCW ? GL_CW
                                                                : GL_CCW);
        gl.ProgramUniformMatrix4fv(program_.id(), model_location_, 1, GL_FALSE, draw.model.data());
        FaceSelection mesh_faces = faces;
        if (faces == FaceSelection::kSecondDepth) {
            mesh_faces = range.closed ? FaceSelection::kAwayFacing : FaceSelection::kBoth;
            // Reversed-Z: away from the light is toward 0, a negative offset.
            if (range.closed) {
                gl.Disable(GL_POLYGON_OFFSET_FILL);
            } else {
                gl.Enable(GL_POLYGON_OFFSET_FILL);
                gl.PolygonOffset(-kOpenSecondDepthOffset, 0.0f);
            }
        }
        if (mesh_faces == FaceSelection::kBoth) {
            gl.Disable(GL_CULL_FACE);
        } else {
            gl.Enable(GL_CULL_FACE);
            gl.CullFace(mesh_faces == FaceSelection::kAwayFacing ? GL_FRONT : GL_BACK);
        }
        gl.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(range.index_count), GL_UNSIGNED_INT,
                        reinterpret_cast<const void*>(range.first_index * sizeof(GLuint)));
    }
    gl.Disable(GL_CULL_FACE);
    gl.Disable(GL_POLYGON_OFFSET_FILL);
    gl.Disable(GL_DEPTH_CLAMP);
    gl.BindVertexArray(0);
    gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl.NamedFramebufferTexture(framebuffer_.id(), GL_DEPTH_ATTACHMENT, 0, 0);
    return context_->Check(std::string("depth pass (") + FaceSelectionName(faces) + ")");
}

}  // namespace lixel::render
