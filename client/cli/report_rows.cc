// View responses as report rows (report_rows.h).
#include "report_rows.h"

#include <lixel/eval/cost.h>

#include <algorithm>
#include <cstring>

namespace lixel::cli {
namespace {

eval::AliasingStats Stats(const v1::AliasingStats& s) {
    eval::AliasingStats out;
    out.pixels = static_cast<std::int64_t>(s.pixels());
    out.mean = s.mean();
    out.p95 = s.p95();
    out.over_threshold = s.over_threshold();
    return out;
}

}  // namespace

std::vector<std::pair<std::string, double>> StagesOfView(const v1::ViewResponse& view,
                                                         double round_trip_ms) {
    std::vector<std::pair<std::string, double>> stages;
    double server_ms = 0.0;
    for (const v1::StageTime& t : view.timings()) {
        const double ms = 1e3 * t.seconds();
        server_ms += ms;
        if (t.stage() == "truth" || t.stage() == "ray_scene") continue;
        stages.emplace_back(t.stage() == "maps" ? "passes" : t.stage(), ms);
    }
    stages.emplace_back("transfer", std::max(0.0, round_trip_ms - server_ms));
    return stages;
}

std::vector<std::pair<std::string, double>> MethodStages(
    const std::vector<std::pair<std::string, double>>& stages) {
    std::vector<std::pair<std::string, double>> own;
    for (const auto& s : stages) {
        const eval::CostPart part = eval::CostPartOf(s.first);
        if (part != eval::CostPart::kBaselineDepth && part != eval::CostPart::kBaselineView) {
            own.push_back(s);
        }
    }
    return own;
}

v1::Method ProtoMethod(eval::Fitting fitting) {
    switch (fitting) {
        case eval::Fitting::kPlaneOptimal: return v1::METHOD_PLANE_OPTIMAL;
        case eval::Fitting::kUniform: return v1::METHOD_UNIFORM;
        case eval::Fitting::kPsm: return v1::METHOD_PSM;
        case eval::Fitting::kLispsm: return v1::METHOD_LISPSM;
        case eval::Fitting::kCsm: return v1::METHOD_CSM;
    }
    return v1::METHOD_PLANE_OPTIMAL;
}

v1::Filter ProtoFilter(eval::ShadowTest test) {
    switch (test) {
        case eval::ShadowTest::kDepth: return v1::FILTER_DEPTH;
        case eval::ShadowTest::kPcf: return v1::FILTER_PCF;
        case eval::ShadowTest::kSecondDepth: return v1::FILTER_SECOND_DEPTH;
        case eval::ShadowTest::kSilhouette: return v1::FILTER_SILHOUETTE_MAP;
    }
    return v1::FILTER_DEPTH;
}

eval::ReportRow RowOfView(const std::string& scene, const std::string& method,
                          std::int64_t budget, const v1::ViewResponse& evaluated) {
    const v1::Evaluation& e = evaluated.evaluation();
    eval::ReportRow row;
    row.scene = scene;
    row.method = method;
    row.budget = budget;
    row.total_lixels = static_cast<std::int64_t>(evaluated.total_lixels());
    row.view_pixels = static_cast<std::int64_t>(evaluated.width()) * evaluated.height();
    row.maps = static_cast<int>(evaluated.maps());
    row.error.decided = static_cast<std::int64_t>(e.decided_pixels());
    row.error.wrong = static_cast<std::int64_t>(e.wrong_pixels());
    row.error.band_decided = static_cast<std::int64_t>(e.band_decided_pixels());
    row.error.band_wrong = static_cast<std::int64_t>(e.band_wrong_pixels());
    row.error.false_lit = static_cast<std::int64_t>(e.false_lit_pixels());
    row.error.false_shadow = static_cast<std::int64_t>(e.false_shadow_pixels());
    row.error.planes_decided = static_cast<std::int64_t>(e.planes_decided_pixels());
    row.error.planes_wrong = static_cast<std::int64_t>(e.planes_wrong_pixels());
    row.aliasing_planes = Stats(e.aliasing_planes());
    row.aliasing_elsewhere = Stats(e.aliasing_elsewhere());
    row.lixel_use = e.lixel_use();
    row.map_bytes_raw = evaluated.map_bytes_raw();
    row.map_bytes_coded = evaluated.map_bytes_coded();
    return row;
}

eval::Mask MaskOf(const v1::ViewResponse& view) {
    eval::Mask mask{static_cast<int>(view.width()), static_cast<int>(view.height()), {}};
    mask.lit.resize(view.mask().size() / sizeof(float));
    std::memcpy(mask.lit.data(), view.mask().data(), mask.lit.size() * sizeof(float));
    for (float& v : mask.lit) v = v < 0.0f ? 1.0f : v;  // no surface: nothing to shadow
    return mask;
}

eval::GroundTruth TruthOf(const v1::ViewResponse& view) {
    eval::GroundTruth truth;
    truth.width = static_cast<int>(view.width());
    truth.height = static_cast<int>(view.height());
    truth.state.resize(view.truth().size());
    for (std::size_t i = 0; i < truth.state.size(); ++i) {
        truth.state[i] = static_cast<eval::Truth>(view.truth()[i]);
    }
    return truth;
}

std::optional<eval::RgbImage> PreviewOf(const v1::ViewResponse& view) {
    const std::size_t bytes = std::size_t(3) * view.width() * view.height();
    if (view.preview().empty() || view.preview().size() != bytes) return std::nullopt;
    eval::RgbImage image(static_cast<int>(view.width()), static_cast<int>(view.height()));
    std::memcpy(image.rgb.data(), view.preview().data(), bytes);
    return image;
}

}  // namespace lixel::cli
