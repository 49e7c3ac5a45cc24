// main() of lixel_volumes_gl_tests: one GL context (EGL, or OSMesa with LIXEL_TEST_GL=osmesa)
// and one VolumePass for every test, on the main thread.
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>

#include "gl_environment.h"

namespace lixel::volumes::gl::testing {
namespace {

render::GlContext* context = nullptr;
std::optional<VolumePass> pass;

class GlEnvironment : public ::testing::Environment {
  public:
    void SetUp() override {
        render::Backend backend = render::Backend::kEgl;
        if (const char* env = std::getenv("LIXEL_TEST_GL")) {
            auto parsed = render::ParseBackend(env, "LIXEL_TEST_GL");
            ASSERT_TRUE(parsed.ok()) << parsed.error().Message();
            backend = *parsed;
        }
        auto c = render::ThreadContext(
            render::ContextOptions{.backend = backend, .synchronous_debug = true});
        ASSERT_TRUE(c.ok()) << c.error().Message();
        context = *c;
        std::printf("[ GL       ] %s\n", context->info().Summary().c_str());
        auto p = VolumePass::Create(*context);
        ASSERT_TRUE(p.ok()) << p.error().Message();
        pass.emplace(std::move(p.value()));
    }
    void TearDown() override { pass.reset(); }
};

}  // namespace

render::GlContext& Context() { return *context; }
VolumePass& Pass() { return *pass; }

}  // namespace lixel::volumes::gl::testing

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    ::testing::AddGlobalTestEnvironment(new lixel::volumes::gl::testing::GlEnvironment());
    return RUN_ALL_TESTS();
}
