// View responses as report rows, for `lixel report` (report_command.cc): the evaluated call's
// metrics and images, and each timed call's stages with the cost baselines of lixel::eval's
// cost.h. No I/O, so tests can feed it responses.
#pragma once

#include <lixel/eval/ground_truth.h>
#include <lixel/eval/image.h>
#include <lixel/eval/methods.h>
#include <lixel/eval/report.h>
#include <lixel/v1/lixel.pb.h>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace lixel::cli {

// A timed call's stages in milliseconds, in the server's order, then "transfer": the round trip
// less every server stage. The evaluation's own stages ("truth", "ray_scene") are left out (not
// the method's cost); "maps" is renamed "passes" (the CLI's name since issue 6). The cost
// baselines stay in, under their names (eval::kBaselineDepthStage, kBaselineViewStage).
std::vector<std::pair<std::string, double>> StagesOfView(const v1::ViewResponse& view,
                                                         double round_trip_ms);

// The stages that are the method's own (not its baselines): the report's stage columns.
std::vector<std::pair<std::string, double>> MethodStages(
    const std::vector<std::pair<std::string, double>>& stages);

// The wire's method and filter for the report's fitting and shadow test.
v1::Method ProtoMethod(eval::Fitting fitting);
v1::Filter ProtoFilter(eval::ShadowTest test);

// The row of an evaluated response: error, aliasing, lixel use, lixels and maps. Stage times and
// costs are the caller's to fill from the timed calls.
eval::ReportRow RowOfView(const std::string& scene, const std::string& method,
                          std::int64_t budget, const v1::ViewResponse& evaluated);

eval::Mask MaskOf(const v1::ViewResponse& view);
eval::GroundTruth TruthOf(const v1::ViewResponse& view);
// The shaded preview when the response carries one of the right size.
std::optional<eval::RgbImage> PreviewOf(const v1::ViewResponse& view);

}  // namespace lixel::cli
