// Tests for context.h: the 4.5 core context, its limits, KHR_debug errors, one per thread.
#include <lixel/render/context.h>

#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "gl_environment.h"

namespace lixel::render {
namespace {

TEST(GlContext, ReportsCoreProfileAndLimits) {
    const ContextInfo& info = testing::Context().info();
    EXPECT_FALSE(info.renderer.empty());
    EXPECT_NE(info.version.find("4.5"), std::string::npos) << info.version;
    EXPECT_NE(info.version.find("Core"), std::string::npos) << info.version;
    EXPECT_GE(info.max_texture_size, 4096);
    EXPECT_GE(info.max_patch_vertices, 32);
    EXPECT_GE(info.max_tess_gen_level, 64);
    EXPECT_GE(info.max_geometry_output_vertices, 12);  // silhouette_map.geom emits 12
    EXPECT_TRUE(info.khr_debug);
    EXPECT_NE(info.Summary().find(info.renderer), std::string::npos);
}

TEST(GlContext, GlErrorsBecomeErrorsWithTheDebugMessage) {
    GlContext& context = testing::Context();
    ASSERT_TRUE(context.Check("before").ok());
    context.gl().Enable(0x1234);  // not a capability
    auto checked = context.Check("enable");
    ASSERT_FALSE(checked.ok());
    EXPECT_EQ(checked.error().field, "enable");
    EXPECT_NE(checked.error().reason.find("GL_INVALID_ENUM"), std::string::npos)
        << checked.error().reason;
    // The debug message, not only glGetError's code: it names the call and its argument.
    EXPECT_NE(checked.error().reason.find("error "), std::string::npos) << checked.error().reason;
    EXPECT_NE(checked.error().reason.find("glEnable"), std::string::npos)
        << checked.error().reason;
    EXPECT_TRUE(context.Check("after").ok()) << "errors are reported once";
}

TEST(GlContext, DebugLogKeepsTheMostRecentMessagesOnly) {
    GlContext& context = testing::Context();
    (void)context.TakeMessages();
    constexpr int kInserted = 10'000;
    for (int i = 0; i < kInserted; ++i) {
        const std::string text = "lixel message " + std::to_string(i);
        context.gl().DebugMessageInsert(GL_DEBUG_SOURCE_APPLICATION, GL_DEBUG_TYPE_OTHER, 1,
                                        GL_DEBUG_SEVERITY_NOTIFICATION,
                                        static_cast<GLsizei>(text.size()), text.c_str());
    }
    const std::vector<std::string> messages = context.TakeMessages();
    ASSERT_EQ(messages.size(), GlContext::kDebugWindow + 1);
    EXPECT_EQ(messages.front(), std::to_string(kInserted - GlContext::kDebugWindow) +
                                    " earlier debug messages dropped");
    EXPECT_EQ(messages[1], "other 1: lixel message " +
                               std::to_string(kInserted - GlContext::kDebugWindow));
    EXPECT_EQ(messages.back(), "other 1: lixel message " + std::to_string(kInserted - 1));
    EXPECT_TRUE(context.TakeMessages().empty());
    EXPECT_TRUE(context.Check("notifications are not errors").ok());
}

TEST(GlContext, ManyErrorsAreReportedAsTheFirstFewAndACount) {
    GlContext& context = testing::Context();
    ASSERT_TRUE(context.Check("before").ok());
    constexpr int kErrors = 1'000;
    for (int i = 0; i < kErrors; ++i) context.gl().Enable(0x1234);
    auto checked = context.Check("enable");
    ASSERT_FALSE(checked.ok());
    const std::string& reason = checked.error().reason;
    std::size_t named = 0;
    for (std::size_t at = reason.find("glEnable"); at != std::string::npos;
         at = reason.find("glEnable", at + 1)) {
        ++named;
    }
    EXPECT_EQ(named, GlContext::kDebugErrors) << reason.substr(0, 400);
    EXPECT_NE(reason.find("and " + std::to_string(kErrors - GlContext::kDebugErrors) +
                          " more debug errors"),
              std::string::npos)
        << reason.substr(0, 400);
    EXPECT_TRUE(context.Check("after").ok());
    (void)context.TakeMessages();
}

TEST(GlContext, ThreadContextIsCreatedOnceAndReused) {
    auto a = ThreadContext({testing::TestBackend()});
    auto b = ThreadContext({testing::TestBackend()});
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(*a, *b);
    EXPECT_EQ(*a, &testing::Context());
    const Backend other =
        testing::TestBackend() == Backend::kEgl ? Backend::kOsmesa : Backend::kEgl;
    auto refused = ThreadContext({other});
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().field, "gl");
}

TEST(GlContext, OtherThreadsGetTheirOwnContext) {
    GlContext* here = &testing::Context();
    GlContext* there = nullptr;
    std::string error;
    std::thread worker([&] {
        auto c = ThreadContext({testing::TestBackend()});
        if (c.ok()) {
            there = *c;
        } else {
            error = c.error().Message();
        }
    });
    worker.join();
    ASSERT_TRUE(error.empty()) << error;
    EXPECT_NE(there, nullptr);
    EXPECT_NE(there, here);
    ASSERT_TRUE(here->MakeCurrent().ok());
}

TEST(GlContext, DevicePlatformIsAHardwareDeviceOrAClearRefusal) {
    if (testing::TestBackend() != Backend::kEgl) GTEST_SKIP() << "EGL only";
    std::string outcome;
    std::thread worker([&] {
        auto c = GlContext::Create({Backend::kEgl, EglPlatform::kDevice, true});
        outcome =
            c.ok() ? "device: " + (*c)->info().platform : c.error().field + ": " + c.error().reason;
    });
    worker.join();
    ASSERT_TRUE(testing::Context().MakeCurrent().ok());
    std::printf("[ GL       ] EglPlatform::kDevice -> %s\n", outcome.c_str());
    // llvmpipe is EGL_MESA_device_software and never counts as a device here.
    EXPECT_TRUE(outcome.starts_with("device: device ") || outcome.starts_with("gl.egl_platform: "))
        << outcome;
}

TEST(ParseBackend, AcceptsTheTwoNamesAndRefusesOthers) {
    EXPECT_EQ(*ParseBackend("egl"), Backend::kEgl);
    EXPECT_EQ(*ParseBackend("osmesa"), Backend::kOsmesa);
    auto bad = ParseBackend("glx", "flags.gl");
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().field, "flags.gl");
    EXPECT_NE(bad.error().reason.find("glx"), std::string::npos);
}

}  // namespace
}  // namespace lixel::render
