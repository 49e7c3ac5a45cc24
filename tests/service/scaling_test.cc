// Tests for scaling past one machine (DESIGN §8): three instances on loopback behind one
// round_robin channel; calls spread over them and survive the loss of one.
#include <set>

#include "service_fixture.h"

namespace lixel {
namespace {

using testing::Connect;
using testing::SmallScene;
using testing::SmallServerOptions;
using testing::StartServer;
using testing::Target;

TEST(Scaling, CallsSpreadOverThreeInstancesAndSurviveTheLossOfOne) {
    std::vector<std::unique_ptr<service::Server>> servers;
    std::string target = "ipv4:";
    for (const char* name : {"east", "west", "north"}) {
        servers.push_back(StartServer(SmallServerOptions(name)));
        if (target.size() > 5) target += ",";
        target += Target(*servers.back());
    }
    auto client = Connect(target);
    ASSERT_TRUE(client->WaitForReady(10.0).ok());
    auto uploaded = client->UploadScene(SmallScene());
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();

    v1::PlanRequest plan;
    plan.set_scene_id(uploaded->scene_id());
    plan.set_lixel_budget(128 * 128);
    std::set<std::string> answered;
    for (int i = 0; i < 30; ++i) {
        auto p = client->Plan(plan);  // instances without the scene get it re-uploaded
        ASSERT_TRUE(p.ok()) << p.error().Message();
        answered.insert(p->instance());
    }
    EXPECT_EQ(answered, (std::set<std::string>{"east", "west", "north"}));

    servers[1]->Shutdown();  // "west" goes away
    std::set<std::string> after;
    for (int i = 0; i < 30; ++i) {
        auto p = client->Plan(plan);
        ASSERT_TRUE(p.ok()) << i << ": " << p.error().Message();
        after.insert(p->instance());
    }
    EXPECT_EQ(after, (std::set<std::string>{"east", "north"}));
}

}  // namespace
}  // namespace lixel
