// The engine client's own view of a scene, shadowed through the client shader kit from what
// Render streams: the meshes drawn relative to the KitFrame's origin, a depth pre-pass, then one
// shading pass whose fragment stage includes kit/glsl/lixel_shadows.glsl. Conventions are
// lixel's own view pass's (server/render, shaders/view.frag), so the lit mask it reads back is
// the one View returns for the same plan: [0, 1] clip depth (glClipControl ZERO_TO_ONE, lower
// left), viewer depth cleared to 1 with GL_LESS, pixel centres at +0.5, row 0 at the bottom,
// reversed-Z maps with the kit's lookup rule, the same slope-scaled bias defaults.
#pragma once

#include <lixel/client/gl_functions.h>
#include <lixel/client/kit_frame.h>
#include <lixel/client/kit_uploader.h>
#include <lixel/solver/mesh.h>
#include <lixel/solver/mesh_instance.h>
#include <lixel/solver/result.h>
#include <lixel/solver/types.h>

#include <cstdint>
#include <span>
#include <vector>

namespace lixel::engine {

// The kit's tests a client frame can run: hard shadows, PCF, second depth (paper 003) and the
// silhouette map (paper 000: the corner depth and the points Render streams for maps planned with
// the silhouette_map pass, KitDepth::kSilhouette). Values match engine_view.frag's kFilter*
// constants.
enum class EngineFilter { kDepth = 0, kPcf = 1, kSecondDepth = 2, kSilhouette = 3 };
inline constexpr int kEngineFilters = 4;

const char* EngineFilterName(EngineFilter filter) noexcept;

// Which of a map's streamed images the filter reads.
client::KitDepth KitDepthFor(EngineFilter filter) noexcept;

// The shadow tests' settings. The defaults are lixel's view pass's (render::ShadowOptions; the
// test EngineView.BiasDefaultsAreTheViewPasss holds them equal), so the engine's mask is View's.
struct EngineShadowOptions {
    // Depth, PCF and the silhouette map: lit when depth + min(depth_bias + slope_bias * reach *
    // |grad d|, max_bias) >= the stored (corner) depth; clip-depth units except slope_bias
    // (dimensionless, >= 0).
    float depth_bias = 0.0f;
    float slope_bias = 1.5f;
    float max_bias = 1.0f;
    // Second depth: a closed solid's bias (stored-depth units, 0) and an open surface's, in
    // multiples of its stored depth's rounding bound (lixel_stored_depth_rounding).
    float second_depth_bias = 0.0f;
    float open_second_depth_bias = 16.0f;
    bool virtual_samples = true;
    int pcf_radius = 1;  // [1, 4]
};

// What the viewer sees: Mv (world -> clip, [0, 1] clip depth), the image size, the light
// (w = 1 point, w = 0 direction toward it).
struct EngineCamera {
    Mat4 viewer = Mat4::Identity();
    Viewport viewport{512, 512};
    Vec4 light = Vec4(0, 10, 0, 1);
};

// A drawn frame, read back. Row 0 is the bottom row.
struct EngineImages {
    int width = 0;
    int height = 0;
    std::vector<float> mask;        // lit fraction in [0, 1]; kEngineNoSurface where none
    std::vector<std::uint8_t> rgb;  // shaded image, 3 bytes per pixel
};

// Mask value of a pixel that shows no surface (View's as well).
inline constexpr float kEngineNoSurface = -1.0f;

class EngineView {
  public:
    // Builds the programs (one per filter, plus the depth pre-pass) and the GL objects. A GL 4.5
    // core context must be current; `loader` gives its entry points. Errors: "gl" (a missing
    // entry point, a compile or link log).
    static Result<EngineView> Create(client::GlLoader loader);

    EngineView(EngineView&& other) noexcept;
    EngineView& operator=(EngineView&& other) noexcept;
    EngineView(const EngineView&) = delete;
    EngineView& operator=(const EngineView&) = delete;
    ~EngineView();

    // The frame's meshes, positions relative to `origin` (subtracted in double, then float, as
    // lixel's passes upload theirs), into the view's two buffers, whose storage is given anew
    // each call (the frame's scene may differ from the last). Errors name the mesh
    // ("meshes[1].indices[7]").
    // The meshes are drawn each once, in place, until PlaceMeshes places them.
    Result<bool> UploadMeshes(std::span<const Mesh> meshes, const Vec3& origin);

    // Places the uploaded meshes for the next draws (mesh_instance.h), uploading nothing but
    // matrices: each instance's mesh < the meshes uploaded ("instances[i].mesh"), its matrix
    // usable (CheckInstanceMatrix, "instances[i].object_to_world"). Empty: each mesh once, in
    // place. The model matrices are lixel's (RelativeObjectToWorld against the same origin), so
    // a frame drawn here places every vertex as the server's passes did.
    Result<bool> PlaceMeshes(std::span<const MeshInstance> instances);

    // The frame's maps (KitUploader::Upload); its origin must be the meshes' ("origin").
    Result<bool> UploadKit(const client::KitFrame& frame);

    // Draws the uploaded meshes with the uploaded maps and reads the mask and the colour back.
    // The caller's clip convention (glClipControl) and pack state are as they were afterwards;
    // the depth test is left on, blending and face culling off, the kit's uniform buffer at
    // binding 0 and its atlases on texture units 0 and 1. Errors: "camera.viewer", "camera.viewport", "camera.light", "options.pcf_radius",
    // "options.*_bias", "meshes" (none uploaded), "kit" (none uploaded, or kSilhouette on a frame
    // without silhouette points), "filter", "gl".
    Result<EngineImages> Draw(const EngineCamera& camera, EngineFilter filter,
                              const EngineShadowOptions& options = {});

    // Waits until the GL has run every command so far (glFinish): for timing an upload.
    void Finish() const { gl_.Finish(); }

    const client::KitUploader& uploader() const noexcept { return uploader_; }
    const Vec3& origin() const noexcept { return origin_; }

  private:
    struct Range {
        std::uint32_t first_index = 0;
        std::uint32_t index_count = 0;
        bool closed = false;
    };
    struct Placed {
        std::uint32_t range = 0;
        Eigen::Matrix4f model = Eigen::Matrix4f::Identity();  // relative object -> world
        bool receives = true;
    };
    EngineView(const client::GlFunctions& gl, client::KitUploader uploader)
        : gl_(gl), uploader_(std::move(uploader)) {}
    void Release() noexcept;
    void TakeHandles(EngineView& other) noexcept;
    Result<bool> EnsureTargets(const Viewport& size);
    // Draw's steps: its arguments and state checked (the light normalised, the eye found), the
    // filter's program set up, the meshes
    // drawn (depth pre-pass, then the nearest surface shaded) and the targets read back.
    Result<bool> CheckDraw(const EngineCamera& camera, EngineFilter filter,
                           const EngineShadowOptions& o, Vec4& light, Vec4& eye) const;
    void SetUniforms(GLuint program, const EngineCamera& camera, const Vec4& light,
                     const Vec4& eye, const EngineShadowOptions& o);
    void DrawMeshes(GLuint program, const Viewport& viewport);
    EngineImages ReadImages(const Viewport& viewport);

    client::GlFunctions gl_;
    client::KitUploader uploader_;
    GLuint programs_[kEngineFilters] = {0, 0, 0, 0};  // by EngineFilter
    GLuint prepass_ = 0;
    GLuint vao_ = 0;
    GLuint positions_ = 0;
    GLuint indices_ = 0;
    GLuint framebuffer_ = 0;
    GLuint mask_ = 0;    // GL_R32F
    GLuint colour_ = 0;  // GL_RGBA8
    GLuint depth_ = 0;   // GL_DEPTH_COMPONENT32F
    Viewport target_size_;
    std::vector<Range> ranges_;
    std::vector<Placed> placed_;  // what DrawMeshes draws
    Vec3 origin_ = Vec3::Zero();
    bool has_meshes_ = false;
    bool has_kit_ = false;
    bool kit_has_maps_ = false;  // the uploaded frame's; a frame without maps needs no atlas "b"
    Vec3 kit_origin_ = Vec3::Zero();
};

}  // namespace lixel::engine
