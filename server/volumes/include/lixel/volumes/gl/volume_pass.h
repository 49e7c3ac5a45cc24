// The shadow-volume view (DESIGN §5-6, paper 001): the viewer's depth, then every volume
// counted per pixel into a float count target (each caster z-pass, or z-fail with caps), then
// the pixels whose count is zero marked lit. The result is the view pass's interface
// (render::ViewImages): a lit-fraction mask of exactly 0 or 1, a preview, no maps.
#pragma once

#include <lixel/render/context.h>
#include <lixel/render/gl_objects.h>
#include <lixel/render/gpu_scene.h>
#include <lixel/render/program.h>
#include <lixel/render/view_pass.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>
#include <lixel/volumes/counting_mode.h>
#include <lixel/volumes/gl/volume_gl_api.h>
#include <lixel/volumes/gl/volume_scene.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace lixel::volumes::gl {

enum class CountingChoice {
    kAuto,   // per caster: z-pass where ChooseCountingModes proves it safe, else z-fail
    kZPass,  // forced (wrong where a volume holds part of the near rectangle; tests, timing)
    kZFail,  // forced
};

struct VolumeRequest {
    Mat4 viewer = Mat4::Identity();  // Mv, world -> clip, [0, 1] clip depth
    Viewport viewport;               // pixels
    Vec4 light = Vec4::Zero();       // w = 1 point, w = 0 direction toward the light
    CountingChoice counting = CountingChoice::kAuto;
    // Also count the volume fragments rasterised (overdraw O, paper 000 Table 1): one more
    // draw of the volumes with the depth test off, under a GL_SAMPLES_PASSED query.
    bool measure_overdraw = false;
    // Polled between a posed scene's casters while their counting modes are chosen (a CPU test
    // of every triangle): true ends the pass with Error{"request", "cancelled"}.
    std::function<bool()> cancelled;
};

struct VolumeRenderInfo {
    // kZFail when any caster was counted z-fail, kZPass when all were z-pass.
    CountingMode mode = CountingMode::kZFail;
    // Per caster: each casting draw of the surfaces' pose (each mesh of the VolumeScene, in
    // order, when the scene is not posed), or the one GpuVolumeMesh.
    std::vector<CountingMode> modes;
    std::size_t patches = 0;             // edge patches drawn (robust silhouettes)
    std::size_t cap_triangles = 0;       // triangles drawn for caps (z-fail)
    std::uint64_t volume_fragments = 0;  // with measure_overdraw
    double overdraw = 0.0;               // volume_fragments / pixels
};

class VolumePass {
  public:
    // Builds the programs; `context` must outlive the pass and be current.
    static Result<VolumePass> Create(render::GlContext& context);

    // Robust silhouette volumes of `volumes` (multiplicity in the tessellation control shader,
    // extrusion in the evaluation shader, caps in a geometry shader). `surfaces` is the same
    // scene uploaded by render::UploadScene with the same origin, posed as the frame places its
    // meshes (render::GpuScene::Pose): each draw that casts extrudes its mesh's patches in its
    // object space, against the light carried there (ObjectSpaceLight of its model matrix), and
    // draws them through its model matrix; a mirrored draw's faces count with the opposite
    // sign; a draw that does not receive is lit where it faces the light. `target.depth`
    // becomes a GL_DEPTH32F_STENCIL8 texture. Errors: "viewer", "viewport", "light", "origin"
    // (scenes uploaded with different origins), or the GL debug message.
    Result<VolumeRenderInfo> Render(const render::GpuScene& surfaces, const VolumeScene& volumes,
                                    const VolumeRequest& request, render::ViewImages& target);

    // A volume built on the CPU (smooth silhouettes: ExtrudeSceneVolume of the surfaces' pose),
    // drawn as triangles. z-fail needs the volume built with Caps::kLightAndDark
    // ("volume.caps" otherwise).
    Result<VolumeRenderInfo> Render(const render::GpuScene& surfaces, const VolumeScene& volumes,
                                    const GpuVolumeMesh& volume, const VolumeRequest& request,
                                    render::ViewImages& target);

    // Each patch's multiplicity as the tessellation control shader computes it (same order as
    // volumes.patch_edges()), read back from a storage buffer; for tests against the CPU.
    Result<std::vector<int>> PatchMultiplicities(const VolumeScene& volumes, const Vec4& light);

  private:
    // A draw of the surfaces' pose that casts: its mesh, model matrix (object -> world, relative
    // to the origin) and the light in its object space, relative to the origin.
    struct CasterDraw {
        std::uint32_t mesh = 0;
        Eigen::Matrix4f model = Eigen::Matrix4f::Identity();
        Eigen::Vector4f light = Eigen::Vector4f::Zero();
        bool mirrored = false;
    };
    static std::vector<CasterDraw> Casters(const render::GpuScene& surfaces,
                                           const Vec4& light_world);
    VolumePass() = default;
    Result<VolumeRenderInfo> Draw(const render::GpuScene& surfaces, const VolumeScene& volumes,
                                  const GpuVolumeMesh* volume, const VolumeRequest& request,
                                  render::ViewImages& target);
    // The target's textures (made or resized to `size`) and the count target, attached and
    // cleared.
    Result<bool> AttachTargets(const Viewport& size, render::ViewImages& target);
    void DrawSurfaces(const render::GpuScene& surfaces);
    // Every caster's volumes into the count target, each with its counting mode.
    void CountVolumes(const VolumeScene& volumes, const GpuVolumeMesh* volume,
                      std::span<const CasterDraw> casters, const Eigen::Matrix4f& viewer,
                      VolumeRenderInfo& info);
    // info.volume_fragments and info.overdraw: the volumes' fragments per pixel of `size`.
    void MeasureOverdraw(const VolumeScene& volumes, const GpuVolumeMesh* volume,
                         std::span<const CasterDraw> casters, const Eigen::Matrix4f& viewer,
                         const Viewport& size, VolumeRenderInfo& info);
    // The patch groups of `mesh` (of every mesh without one).
    void DrawPatches(const VolumeScene& volumes, std::optional<std::uint32_t> mesh);
    // The volumes of the casters counted with `mode` (info.modes: per caster draw, or one for
    // `volume`), with caps for z-fail; `front` is what a front face adds (a mirrored draw's
    // faces add the opposite).
    void DrawVolumes(const VolumeScene& volumes, const GpuVolumeMesh* volume,
                     std::span<const CasterDraw> casters, CountingMode mode, float front,
                     const Eigen::Matrix4f& viewer, VolumeRenderInfo& info);

    render::GlContext* context_ = nullptr;
    VolumeGlApi api_;
    render::Program surface_;
    render::Program sides_;
    render::Program caps_;
    render::Program mesh_;
    render::GlFramebuffer framebuffer_;
    // The per-pixel volume count (volume_pass.cc, kCountFormat) and its framebuffer, which
    // shares the target's depth.
    render::GlFramebuffer count_framebuffer_;
    render::GlTexture count_;
    Viewport count_size_;
    render::GlFramebuffer discard_framebuffer_;
    render::GlTexture discard_target_;
    GLuint own_depth_ = 0;  // the depth-stencil texture this pass last put in a ViewImages
    // Indices per GL_PATCHES draw; 0 draws every patch in one call (see volume_pass.cc).
    std::size_t patch_indices_per_draw_ = 0;
};

}  // namespace lixel::volumes::gl
