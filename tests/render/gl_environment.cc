// main() of lixel_render_tests: one GL context for every test, on the main thread.
#include "gl_environment.h"

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

namespace lixel::render::testing {
namespace {

GlContext* context = nullptr;
std::unique_ptr<Renderer> renderer;

class GlEnvironment : public ::testing::Environment {
  public:
    void SetUp() override {
        auto c = ThreadContext(ContextOptions{.backend = TestBackend(), .synchronous_debug = true});
        ASSERT_TRUE(c.ok()) << c.error().Message();
        context = *c;
        std::printf("[ GL       ] %s\n", context->info().Summary().c_str());
        auto r = Renderer::Create(*context);
        ASSERT_TRUE(r.ok()) << r.error().Message();
        renderer = std::move(r.value());
    }
    void TearDown() override { renderer.reset(); }
};

}  // namespace

Backend TestBackend() {
    const char* env = std::getenv("LIXEL_TEST_GL");
    if (env == nullptr) return Backend::kEgl;
    auto parsed = ParseBackend(env, "LIXEL_TEST_GL");
    return parsed.ok() ? *parsed : Backend::kEgl;
}

GlContext& Context() { return *context; }
Renderer& TheRenderer() { return *renderer; }

}  // namespace lixel::render::testing

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    ::testing::AddGlobalTestEnvironment(new lixel::render::testing::GlEnvironment());
    return RUN_ALL_TESTS();
}
