// Tests for lixel::eval's frame-sequence figures (sequence.h): flicker and reallocations on
// hand-made frames with hand-counted answers, against a per-pixel recount on seeded random
// frames, and the summaries and writers.
#include <gtest/gtest.h>
#include <lixel/eval/sequence.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

namespace lixel::eval {
namespace {

constexpr Truth L = Truth::kLit, S = Truth::kShadow, U = Truth::kUndecided, E = Truth::kEmpty;

GroundTruth Row(const std::vector<Truth>& states) {
    GroundTruth t;
    t.width = static_cast<int>(states.size());
    t.height = 1;
    t.state = states;
    return t;
}

Mask MaskRow(const std::vector<float>& lit) { return Mask{static_cast<int>(lit.size()), 1, lit}; }

TEST(Flicker, CountsOnlyAnswersThatChangeWhereTheTruthHoldsStill) {
    // Pixel by pixel: 0 steady lit, answer flips (flicker); 1 steady shadow, answer holds;
    // 2 truth changes lit -> shadow (not steady, whatever the answer does); 3 undecided before;
    // 4 no surface before; 5 steady lit, 0.49 -> 0.5 crosses the lit threshold (flicker);
    // 6 steady shadow, 0.2 -> 0.3 stays shadowed.
    const GroundTruth before = Row({L, S, L, U, E, L, S});
    const GroundTruth after = Row({L, S, S, U, L, L, S});
    const Mask a = MaskRow({1, 0, 1, 0, 1, 0.49f, 0.2f});
    const Mask b = MaskRow({0, 0, 0, 1, 0, 0.5f, 0.3f});
    auto f = CountFlicker(before, a, after, b);
    ASSERT_TRUE(f.ok()) << f.error().Message();
    EXPECT_EQ(f->steady, 4);
    EXPECT_EQ(f->flickering, 2);
    EXPECT_DOUBLE_EQ(f->Percent(), 50.0);
}

TEST(Flicker, AgreesWithAPerPixelRecountOnRandomFrames) {
    std::mt19937 rng(12351);
    std::uniform_int_distribution<int> state(0, 3);
    std::uniform_real_distribution<float> lit(0.0f, 1.0f);
    const Truth states[4] = {E, L, S, U};
    for (int trial = 0; trial < 50; ++trial) {
        const int n = 1 + trial * 7;
        std::vector<Truth> t0(n), t1(n);
        std::vector<float> m0(n), m1(n);
        std::int64_t steady = 0, flickering = 0;
        for (int i = 0; i < n; ++i) {
            t0[i] = states[state(rng)];
            // Half the pixels keep their truth, as consecutive frames mostly do.
            t1[i] = lit(rng) < 0.5f ? t0[i] : states[state(rng)];
            m0[i] = lit(rng);
            m1[i] = lit(rng) < 0.7f ? m0[i] : lit(rng);
            if ((t0[i] == L || t0[i] == S) && t1[i] == t0[i]) {
                ++steady;
                if ((m0[i] >= 0.5f) != (m1[i] >= 0.5f)) ++flickering;
            }
        }
        auto f = CountFlicker(Row(t0), MaskRow(m0), Row(t1), MaskRow(m1));
        ASSERT_TRUE(f.ok());
        EXPECT_EQ(f->steady, steady) << "trial " << trial;
        EXPECT_EQ(f->flickering, flickering) << "trial " << trial;
        // The same frames the other way round flicker alike.
        auto back = CountFlicker(Row(t1), MaskRow(m1), Row(t0), MaskRow(m0));
        ASSERT_TRUE(back.ok());
        EXPECT_EQ(back->flickering, flickering);
    }
}

TEST(Flicker, IdenticalFramesNeverFlickerAndNothingSteadyIsZeroPercent) {
    const GroundTruth t = Row({L, S, L, S});
    const Mask m = MaskRow({1, 0, 0, 1});  // wrong twice, but the same both times
    auto f = CountFlicker(t, m, t, m);
    ASSERT_TRUE(f.ok());
    EXPECT_EQ(f->steady, 4);
    EXPECT_EQ(f->flickering, 0);
    auto none = CountFlicker(Row({U, E}), MaskRow({1, 1}), Row({U, E}), MaskRow({0, 0}));
    ASSERT_TRUE(none.ok());
    EXPECT_EQ(none->steady, 0);
    EXPECT_EQ(none->Percent(), 0.0);
}

TEST(Flicker, RefusesFramesOfOtherSizesAndNonFiniteMasksByName) {
    const GroundTruth t = Row({L, S});
    const Mask m = MaskRow({1, 0});
    auto sizes = CountFlicker(t, m, Row({L, S, L}), MaskRow({1, 0, 1}));
    ASSERT_FALSE(sizes.ok());
    EXPECT_EQ(sizes.error().field, "after_truth");
    auto mask = CountFlicker(t, MaskRow({1}), t, m);
    ASSERT_FALSE(mask.ok());
    EXPECT_EQ(mask.error().field, "before_mask");
    auto nan = CountFlicker(t, m, t, MaskRow({1, std::nanf("")}));
    ASSERT_FALSE(nan.ok());
    EXPECT_EQ(nan.error().field, "after_mask.lit[1]");
}

TEST(Reallocations, CountsMapsThatAppearOrChangeSizeByName) {
    const std::vector<MapAllocation> before = {{"floor", 300, 200}, {"wall", 100, 100},
                                               {"fallback", 128, 128}};
    EXPECT_EQ(CountReallocations(before, before), 0);
    // The wall grows, the fallback is dropped (freed: no allocation), a cube face appears.
    const std::vector<MapAllocation> after = {{"floor", 300, 200}, {"wall", 100, 101},
                                              {"cube +x", 64, 64}};
    EXPECT_EQ(CountReallocations(before, after), 2);
    // Swapped sides are another texture.
    EXPECT_EQ(CountReallocations({{"floor", 300, 200}}, {{"floor", 200, 300}}), 1);
    EXPECT_EQ(CountReallocations({}, before), 3);
    EXPECT_EQ(MapSizesText(after), "floor 300x200, wall 100x101, cube +x 64x64");
}

SequenceFrameRow Frame(const std::string& method, bool coherent, int frame, int reallocations,
                       std::int64_t steady, std::int64_t flickering, double wrong_share) {
    SequenceFrameRow r;
    r.scene = "floor_wall";
    r.method = method;
    r.coherent = coherent;
    r.frame = frame;
    r.budget = 4096;
    r.error.decided = 1000;
    r.error.wrong = static_cast<std::int64_t>(wrong_share * 1000);
    r.reallocations = reallocations;
    r.flicker = {steady, flickering};
    r.maps = {{"floor", 40 + reallocations, 30}};
    r.total_lixels = 1200;
    r.cost = {true, 2.0 * (frame + 1), 3.0, 1.0, 1.0};
    return r;
}

TEST(SequenceSummary, SumsFlickerAndReallocationsAfterTheFirstFramePerMethod) {
    // Out of order on purpose: the summary sorts frames.
    const std::vector<SequenceFrameRow> rows = {
        Frame("plane-optimal + depth", false, 1, 1, 100, 10, 0.02),
        Frame("plane-optimal + depth", false, 0, 2, 0, 0, 0.01),
        Frame("plane-optimal + depth", true, 0, 2, 0, 0, 0.01),
        Frame("plane-optimal + depth", false, 2, 0, 300, 5, 0.03),
        Frame("plane-optimal + depth", true, 1, 0, 100, 1, 0.01),
    };
    const auto s = SummariseSequences(rows);
    ASSERT_EQ(s.size(), 2u);
    EXPECT_FALSE(s[0].coherent);
    EXPECT_EQ(s[0].frames, 3);
    EXPECT_EQ(s[0].reallocations, 1);  // frame 0's two allocations are not counted
    EXPECT_EQ(s[0].frames_with_reallocation, 1);
    EXPECT_EQ(s[0].flicker.steady, 400);
    EXPECT_EQ(s[0].flicker.flickering, 15);
    EXPECT_NEAR(s[0].misclassified_mean, 2.0, 1e-12);
    EXPECT_EQ(s[0].distinct_sizes, 3);  // floor 42x30, 41x30, 40x30
    EXPECT_DOUBLE_EQ(s[0].cost.map_ratio.median, 4.0);  // 2, 4, 6 ms over a 1 ms baseline
    EXPECT_DOUBLE_EQ(s[0].cost.lookup_ratio.max, 3.0);
    EXPECT_TRUE(s[1].coherent);
    EXPECT_EQ(s[1].reallocations, 0);
    EXPECT_EQ(s[1].flicker.flickering, 1);
}

TEST(SequenceWriters, CsvHasALinePerFrameAndMarkdownALinePerMethod) {
    const std::vector<SequenceFrameRow> rows = {
        Frame("csm + depth", false, 0, 4, 0, 0, 0.1), Frame("csm + depth", false, 1, 0, 50, 5, 0.1)};
    const auto dir = std::filesystem::temp_directory_path() / "lixel_sequence_test";
    std::filesystem::create_directories(dir);
    ASSERT_TRUE(WriteSequenceCsv((dir / "s.csv").string(), rows).ok());
    ASSERT_TRUE(WriteSequenceMarkdown((dir / "s.md").string(), SummariseSequences(rows),
                                      {"a note"}).ok());
    std::ifstream csv(dir / "s.csv");
    std::string line;
    int lines = 0;
    while (std::getline(csv, line)) ++lines;
    EXPECT_EQ(lines, 3);  // header + 2 frames
    std::stringstream md;
    md << std::ifstream(dir / "s.md").rdbuf();
    EXPECT_NE(md.str().find("| floor_wall | csm + depth | no | 4096 | 2 |"), std::string::npos)
        << md.str();
    EXPECT_NE(md.str().find("| 10.000 | 5 / 50 | 0 |"), std::string::npos) << md.str();
    EXPECT_NE(md.str().find("- a note"), std::string::npos);
    auto bad = WriteSequenceCsv((dir / "missing" / "s.csv").string(), rows);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().field.find("missing"), std::string::npos);
}

}  // namespace
}  // namespace lixel::eval
