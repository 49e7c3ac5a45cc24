// Tests for the CLI report's reading of View responses (client/cli/report_rows.h): the stages of
// a timed call, the method's own among them, its costs, and the evaluated call's row and images.
#include <gtest/gtest.h>
#include <lixel/eval/cost.h>

#include "../../client/cli/report_rows.h"

namespace lixel::cli {
namespace {

v1::ViewResponse Timed() {
    v1::ViewResponse view;
    for (const auto& [stage, seconds] :
         {std::pair{"plan", 0.001}, std::pair{"maps", 0.004}, std::pair{"view", 0.003},
          std::pair{"readback", 0.0005}, std::pair{"baseline_depth", 0.002},
          std::pair{"baseline_view", 0.0015}, std::pair{"truth", 0.5}}) {
        v1::StageTime* t = view.add_timings();
        t->set_stage(stage);
        t->set_seconds(seconds);
    }
    return view;
}

TEST(StagesOfView, ServerStagesThenTheTransferLessEveryServerStage) {
    const auto stages = StagesOfView(Timed(), 520.0);
    ASSERT_EQ(stages.size(), 7u);  // "truth" left out, "transfer" added
    EXPECT_EQ(stages[1].first, "passes");
    EXPECT_DOUBLE_EQ(stages[1].second, 4.0);
    EXPECT_EQ(stages.back().first, "transfer");
    EXPECT_NEAR(stages.back().second, 520.0 - 512.0, 1e-9);
    // A round trip shorter than the server's stages (clock noise) is no negative transfer.
    EXPECT_EQ(StagesOfView(Timed(), 1.0).back().second, 0.0);

    const auto own = MethodStages(stages);
    ASSERT_EQ(own.size(), 5u);
    for (const auto& [stage, ms] : own) EXPECT_EQ(stage.rfind("baseline", 0), std::string::npos);

    const eval::CostRepeat cost = eval::CostOfRepeat(stages, true);
    EXPECT_DOUBLE_EQ(cost.map_ms, 5.0);  // plan + passes
    EXPECT_DOUBLE_EQ(cost.lookup_ms, 3.0);
    EXPECT_DOUBLE_EQ(cost.baseline_depth_ms, 2.0);
    EXPECT_DOUBLE_EQ(cost.baseline_view_ms, 1.5);
}

TEST(RowOfView, MetricsMaskTruthAndPreview) {
    v1::ViewResponse view;
    view.set_width(2);
    view.set_height(1);
    view.set_total_lixels(1000);
    view.set_maps(2);
    const float mask[2] = {-1.0f, 0.25f};
    view.set_mask(reinterpret_cast<const char*>(mask), sizeof mask);
    view.set_truth(std::string("\x00\x02", 2));
    view.mutable_evaluation()->set_decided_pixels(10);
    view.mutable_evaluation()->set_wrong_pixels(3);
    view.mutable_evaluation()->set_lixel_use(0.5);
    const eval::ReportRow row = RowOfView("room", "uniform + PCF", 1024, view);
    EXPECT_EQ(row.total_lixels, 1000);
    EXPECT_EQ(row.maps, 2);
    EXPECT_DOUBLE_EQ(row.error.Percent(), 30.0);
    EXPECT_FALSE(row.cost.measured());  // the caller's to fill
    const eval::Mask m = MaskOf(view);
    EXPECT_EQ(m.lit, (std::vector<float>{1.0f, 0.25f}));  // no surface counts as lit
    EXPECT_EQ(TruthOf(view).state[1], eval::Truth::kShadow);
    EXPECT_FALSE(PreviewOf(view));
    view.set_preview(std::string(6, '\x7f'));
    ASSERT_TRUE(PreviewOf(view));
    EXPECT_EQ(PreviewOf(view)->rgb[5], 0x7f);
    view.set_preview(std::string(5, '\x7f'));  // not width x height x 3
    EXPECT_FALSE(PreviewOf(view));
}

}  // namespace
}  // namespace lixel::cli
