// One report run for a test suite whose tests read its rows: no volumes, one repeat, no plot or
// progress bar, written to a fresh folder in the test's temporary directory; and a fixture whose
// suite shares that run.
#pragma once

#include <gtest/gtest.h>
#include <lixel/eval/report_runner.h>

#include <filesystem>
#include <string>

namespace lixel::eval::testing {

inline Result<ReportSummary> RunQuickReport(ReportOptions options, const std::string& folder) {
    options.volumes = false;
    options.repeats = 1;
    options.plot = false;
    options.progress = false;
    const std::filesystem::path out = std::filesystem::path(::testing::TempDir()) / folder;
    std::filesystem::remove_all(out);
    options.output = out.string();
    return RunReport(options);
}

// Derived::Options() says what to run and Derived::kFolder where; the suite's tests read
// summary_ (null when the run failed, which SetUpTestSuite reports).
template <class Derived>
class SharedReport : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        auto summary = RunQuickReport(Derived::Options(), Derived::kFolder);
        ASSERT_TRUE(summary.ok()) << summary.error().Message();
        summary_ = new ReportSummary(std::move(*summary));
    }
    static void TearDownTestSuite() {
        delete summary_;
        summary_ = nullptr;
    }
    static inline ReportSummary* summary_ = nullptr;
};

}  // namespace lixel::eval::testing
