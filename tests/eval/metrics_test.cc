// Tests for lixel::eval metrics (misclassification.h, lixel_use.h, timing.h): hand-made truths
// and masks with hand-computed answers.
#include <gtest/gtest.h>
#include <lixel/eval/lixel_use.h>
#include <lixel/eval/misclassification.h>
#include <lixel/eval/timing.h>

#include <cmath>

namespace lixel::eval {
namespace {

constexpr Truth L = Truth::kLit, S = Truth::kShadow, U = Truth::kUndecided, E = Truth::kEmpty;

// A truth from rows listed top row first (as drawn), all on object 0 where visible.
GroundTruth HandTruth(int width, const std::vector<std::vector<Truth>>& rows_top_first) {
    GroundTruth t;
    t.width = width;
    t.height = static_cast<int>(rows_top_first.size());
    const std::size_t n = static_cast<std::size_t>(t.width) * t.height;
    t.state.resize(n);
    t.position.assign(n, Vec3::Zero());
    t.normal.assign(n, Eigen::Vector3f::UnitY());
    t.object.assign(n, 0);
    t.primitive.assign(n, 0);
    t.plane.assign(n, -1);
    for (int y = 0; y < t.height; ++y) {
        for (int x = 0; x < width; ++x) {
            const std::size_t i = t.Index(x, y);
            t.state[i] = rows_top_first[t.height - 1 - y][x];
            if (t.state[i] == Truth::kEmpty) t.object[i] = -1;
        }
    }
    return t;
}

Mask HandMask(int width, const std::vector<std::vector<float>>& rows_top_first) {
    Mask m;
    m.width = width;
    m.height = static_cast<int>(rows_top_first.size());
    m.lit.resize(static_cast<std::size_t>(m.width) * m.height);
    for (int y = 0; y < m.height; ++y) {
        for (int x = 0; x < width; ++x) {
            m.lit[static_cast<std::size_t>(y) * width + x] = rows_top_first[m.height - 1 - y][x];
        }
    }
    return m;
}

// Rows as drawn (top first):   L L L S E
//                              L L U S S
//                              L L S S S
GroundTruth Case() { return HandTruth(5, {{L, L, L, S, E}, {L, L, U, S, S}, {L, L, S, S, S}}); }

// Wrong: the bottom row's (3, 0) says lit (false lit); (1, 1) at 0.4 says shadow (false shadow).
// (2, 2) at exactly 0.5 counts as lit, which is right; (2, 1) undecided and (4, 2) empty do not
// count whatever the mask says.
Mask CaseMask() { return HandMask(5, {{1, 1, 0.5f, 0, 1}, {1, 0.4f, 1, 0, 0}, {1, 1, 0, 1, 0}}); }

TEST(Misclassified, HandComputedCounts) {
    const auto r = Misclassified(Case(), CaseMask(), 1);
    ASSERT_TRUE(r.ok()) << r.error().Message();
    EXPECT_EQ(r->decided, 13);
    EXPECT_EQ(r->wrong, 2);
    EXPECT_EQ(r->false_lit, 1);
    EXPECT_EQ(r->false_shadow, 1);
    EXPECT_DOUBLE_EQ(r->Percent(), 100.0 * 2 / 13);
    // Radius 1 band: 9 decided pixels (worked out in ShadowBoundaryAndBand), both errors in it.
    EXPECT_EQ(r->band_decided, 9);
    EXPECT_EQ(r->band_wrong, 2);
    EXPECT_DOUBLE_EQ(r->BandPercent(), 100.0 * 2 / 9);
}

// Split where plane-optimal maps make their claim: the bottom row on a plane of interest holds 5
// decided pixels and the false-lit (3, 0); the other 8 decided pixels hold the false-shadow one.
TEST(Misclassified, SplitOnThePlanesOfInterestAndElsewhere) {
    GroundTruth truth = Case();
    for (int x = 0; x < truth.width; ++x) truth.plane[truth.Index(x, 0)] = 0;
    const auto r = Misclassified(truth, CaseMask(), 1);
    ASSERT_TRUE(r.ok()) << r.error().Message();
    EXPECT_EQ(r->planes_decided, 5);
    EXPECT_EQ(r->planes_wrong, 1);
    EXPECT_DOUBLE_EQ(r->PlanesPercent(), 100.0 / 5);
    EXPECT_DOUBLE_EQ(r->ElsewherePercent(), 100.0 / 8);
    // No pixel on a plane: everything is elsewhere.
    const auto none = Misclassified(Case(), CaseMask(), 1);
    ASSERT_TRUE(none.ok());
    EXPECT_EQ(none->planes_decided, 0);
    EXPECT_DOUBLE_EQ(none->PlanesPercent(), 0.0);
    EXPECT_DOUBLE_EQ(none->ElsewherePercent(), none->Percent());
}

TEST(Misclassified, BandRadiusZeroAndTwo) {
    auto r0 = Misclassified(Case(), CaseMask(), 0);
    ASSERT_TRUE(r0.ok());
    EXPECT_EQ(r0->band_decided, 4);  // the decided boundary pixels themselves
    EXPECT_EQ(r0->band_wrong, 0);
    // Every decided pixel is within 2 px of the boundary here.
    auto r2 = Misclassified(Case(), CaseMask());
    ASSERT_TRUE(r2.ok());
    EXPECT_EQ(r2->band_decided, 13);
    EXPECT_EQ(r2->band_wrong, 2);
}

TEST(Misclassified, ShadowBoundaryAndBand) {
    const GroundTruth t = Case();
    const std::vector<std::uint8_t> boundary = ShadowBoundary(t);
    // Bottom row (y = 0): L L S S S -> (1, 0) and (2, 0); undecided (2, 1); top row: (2, 2),
    // (3, 2).
    std::vector<std::uint8_t> expected(15, 0);
    for (auto [x, y] : {std::pair{1, 0}, {2, 0}, {2, 1}, {2, 2}, {3, 2}}) {
        expected[t.Index(x, y)] = 1;
    }
    EXPECT_EQ(boundary, expected);
    const std::vector<std::uint8_t> band = BoundaryBand(t, 1);
    std::vector<std::uint8_t> expected_band(15, 0);
    for (auto [x, y] :
         {std::pair{0, 0}, {1, 0}, {2, 0}, {3, 0}, {1, 1}, {3, 1}, {1, 2}, {2, 2}, {3, 2}}) {
        expected_band[t.Index(x, y)] = 1;
    }
    EXPECT_EQ(band, expected_band);
}

TEST(Misclassified, SilhouettesBetweenObjectsAreNotShadowBoundaries) {
    GroundTruth t = HandTruth(2, {{L, S}});
    t.object[1] = 1;
    EXPECT_EQ(ShadowBoundary(t), (std::vector<std::uint8_t>{0, 0}));
    t.object[1] = 0;
    EXPECT_EQ(ShadowBoundary(t), (std::vector<std::uint8_t>{1, 1}));
}

TEST(Misclassified, PerfectMaskHasNoError) {
    const GroundTruth t = Case();
    auto r = Misclassified(t, t.AsMask());
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r->wrong, 0);
    EXPECT_EQ(r->Percent(), 0.0);
}

TEST(Misclassified, RefusesMismatchedOrNonFiniteMasks) {
    Mask m = CaseMask();
    m.width = 4;
    auto r = Misclassified(Case(), m);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "mask");
    m = CaseMask();
    m.lit[7] = std::nanf("");
    r = Misclassified(Case(), m);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "mask.lit[7]");
}

TEST(LixelUse, HandComputedShare) {
    // An orthographic map of the floor: lixel (x, y) = world (x, z), 4 x 4 lixels.
    LightMap map;
    map.matrix << 1, 0, 0, 0,  //
        0, 0, 1, 0,            //
        0, 1, 0, 0,            //
        0, 0, 0, 1;
    map.width = 4;
    map.height = 4;
    LightMap second = map;
    second.width = second.height = 2;
    GroundTruth t = HandTruth(5, {{L, S, L, L, E}});
    t.position[0] = Vec3(0.5, 0, 0.5);  // map 0, lixel (0, 0)
    t.position[1] = Vec3(0.7, 0, 0.2);  // map 0, lixel (0, 0) again
    t.position[2] = Vec3(2.5, 0, 3.5);  // map 0, lixel (2, 3)
    t.position[3] = Vec3(9.0, 0, 0.0);  // map 0, out of its bounds: reads nothing
    const std::vector<LightMap> maps = {map, second};
    auto select = [](const Vec4& x) { return x.x() > 2.0 && x.x() < 3.0 ? 1 : 0; };
    const LixelUse use = ComputeLixelUse(t, maps, select);
    // Position 2 goes to map 1 (2 x 2), where lixel (2, 3) is out of bounds.
    EXPECT_EQ(use.allocated, 16 + 4);
    EXPECT_EQ(use.read, 1);
    EXPECT_EQ(use.read_per_map, (std::vector<std::int64_t>{1, 0}));
    EXPECT_DOUBLE_EQ(use.Share(), 1.0 / 20.0);

    const LixelUse one =
        ComputeLixelUse(t, std::vector<LightMap>{map}, [](const Vec4&) { return 0; });
    EXPECT_EQ(one.read, 2);
    EXPECT_DOUBLE_EQ(one.Share(), 2.0 / 16.0);
}

TEST(Timing, MedianOfRepeats) {
    EXPECT_EQ(Median({}), 0.0);
    EXPECT_EQ(Median({3.0}), 3.0);
    EXPECT_EQ(Median({5.0, 1.0, 4.0}), 4.0);
    EXPECT_EQ(Median({4.0, 1.0, 3.0, 100.0}), 3.5);
    StageTimes times;
    times.Add("solve", 1.0);
    times.Add("pass depth", 10.0);
    times.Add("solve", 3.0);
    times.Add("solve", 2.0);
    times.Add("pass depth", 12.0);
    EXPECT_EQ(times.MedianMs("solve"), 2.0);
    EXPECT_EQ(times.MedianMs("pass depth"), 11.0);
    EXPECT_EQ(times.MedianMs("view"), 0.0);
    EXPECT_EQ(times.Repeats("solve"), 3);
    EXPECT_EQ(times.TotalMs(), 13.0);
    const auto medians = times.Medians();
    ASSERT_EQ(medians.size(), 2u);
    EXPECT_EQ(medians[0].first, "solve");  // first-seen order
    EXPECT_EQ(medians[1].first, "pass depth");
}

TEST(Timing, ScopedStageRecordsElapsedTime) {
    StageTimes times;
    { ScopedStage stage(times, "plan"); }
    EXPECT_EQ(times.Repeats("plan"), 1);
    EXPECT_GE(times.MedianMs("plan"), 0.0);
}

}  // namespace
}  // namespace lixel::eval
