// The client kit's LixelShadowMaps block as the GL lays it out (issue 15): every member of the
// block in lixel's own view program sits at the std140 offset lixel::kit writes it to, with the
// array strides and block size the kit's table gives. A client on any GL that honours std140
// reads the kit's bytes the same way.
#include <lixel/kit/shadow_block.h>
#include <lixel/render/program.h>
#include <lixel/render/view_pass.h>

#include <string>
#include <vector>

#include "gl_environment.h"

namespace lixel::render {
namespace {

struct Member {
    const char* name;
    std::size_t offset;
    GLint array_stride;  // 0 for a non-array member
    GLint matrix_stride;  // 0 for a non-matrix member
};

TEST(KitLayout, TheGlPlacesEveryBlockMemberWhereTheKitWritesIt) {
    GlContext& context = testing::Context();
    const GlApi& gl = context.gl();
    const std::vector<std::string> defines = {
        "#define LIXEL_MAX_MAPS " + std::to_string(kit::kMaxMaps),
        "#define LIXEL_MAX_HALF_PLANES " + std::to_string(kit::kMaxHalfPlanes),
        "#define LIXEL_METHOD 2"};
    auto program = BuildProgram(context, {"view.vert", "view.frag"}, defines);
    ASSERT_TRUE(program.ok()) << program.error().Message();
    const GLuint id = program->id();
    const GLuint block = gl.GetUniformBlockIndex(id, "LixelShadowMaps");
    ASSERT_NE(block, GL_INVALID_INDEX);
    GLint size = 0;
    gl.GetActiveUniformBlockiv(id, block, GL_UNIFORM_BLOCK_DATA_SIZE, &size);
    EXPECT_EQ(static_cast<std::size_t>(size), kit::ShadowBlockLayout::kBytes);

    using L = kit::ShadowBlockLayout;
    const Member members[] = {
        {"lixel_counts", L::kCounts, 0, 0},
        {"lixel_atlas_a_texel", L::kAtlasTexel, 0, 0},
        {"lixel_map_lixel[0]", L::kLixel, 64, 16},
        {"lixel_map_plane[0]", L::kPlane, 64, 16},
        {"lixel_map_lookup[0]", L::kLookup, 16, 0},
        {"lixel_map_world_limit[0]", L::kWorldLimit, 16, 0},
        {"lixel_map_size[0]", L::kSize, 16, 0},
        {"lixel_map_origin[0]", L::kOrigin, 16, 0},
        {"lixel_half_planes[0]", L::kHalfPlanes, 16, 0},
    };
    for (const Member& m : members) {
        const char* names[1] = {m.name};
        GLuint index = GL_INVALID_INDEX;
        gl.GetUniformIndices(id, 1, names, &index);
        // A member the second-depth program does not read may be inactive: the layout still
        // holds (std140 keeps every member), but the GL reports only active ones.
        if (index == GL_INVALID_INDEX) {
            ADD_FAILURE() << m.name << " is not an active member of the view program";
            continue;
        }
        GLint offset = -1, array_stride = -1, matrix_stride = -1, in_block = -1;
        gl.GetActiveUniformsiv(id, 1, &index, GL_UNIFORM_OFFSET, &offset);
        gl.GetActiveUniformsiv(id, 1, &index, GL_UNIFORM_ARRAY_STRIDE, &array_stride);
        gl.GetActiveUniformsiv(id, 1, &index, GL_UNIFORM_MATRIX_STRIDE, &matrix_stride);
        gl.GetActiveUniformsiv(id, 1, &index, GL_UNIFORM_BLOCK_INDEX, &in_block);
        EXPECT_EQ(in_block, static_cast<GLint>(block)) << m.name;
        EXPECT_EQ(static_cast<std::size_t>(offset), m.offset) << m.name;
        EXPECT_EQ(array_stride, m.array_stride) << m.name;
        EXPECT_EQ(matrix_stride, m.matrix_stride) << m.name;
    }
    EXPECT_TRUE(context.Check("kit layout").ok());
}

}  // namespace
}  // namespace lixel::render
