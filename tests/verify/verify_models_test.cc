// verify over every model nobody here wrote: MuJoCo's samples and the DeepMind Control
// Suite. It must not crash, and a FAIL must be a real, explained defect.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "fixture.h"
#include "plumb/verify.h"

namespace plumb {
namespace {

namespace fs = std::filesystem;

// Failures that are real findings, with the explanation (see the closing note).
const std::map<std::string, std::string> kKnownFailures = {
    // A cloth of soft equality constraints flapping in wind. state@0.5 at dt = 4, 2, 1,
    // 0.5, 0.25 ms: successive differences shrink by 2.47, 2.24, 2.11 (observed order
    // 1.02 for Euler's 1, a clean first order), so the Richardson estimate holds: at its
    // own 2 ms step the state is 7.5 (16 % of the state's excursion 47, mostly the
    // cloth's fast velocities) from the extrapolated answer; 0.125 ms would pass 1 %.
    // A real finding about the model's timestep, not a defect of the check.
    {"flag.xml:convergence", "clean first-order convergence shows dt = 2 ms is too coarse"},
};

class VerifyModelsTest : public ::testing::TestWithParam<std::string> {};

TEST_P(VerifyModelsTest, NoCrashAndNoUnexplainedFailure) {
  std::optional<Model> loaded;
  if (!testing::LoadThirdParty(GetParam(), &loaded)) {
    GTEST_SKIP() << GetParam() << " does not load on MuJoCo " << testing::CompiledMujocoVersion()
                 << ": " << testing::RefusedReason(GetParam());
  }
  Model& model = *loaded;
  VerifyReport report = Verify(model, {});
  TakeMujocoWarnings();
  ASSERT_GE(report.checks.size(), 5u);
  std::string file = fs::path(GetParam()).filename().string();
  for (const CheckRow& c : report.checks) {
    std::string key = file + ":" + c.id;
    if (c.status == CheckStatus::kFail) {
      EXPECT_TRUE(kKnownFailures.count(key)) << key << " failed: " << c.explanation;
    } else if (kKnownFailures.count(key)) {
      // the list must not rot: a known failure that went away is removed from it
      ADD_FAILURE() << key << " (" << kKnownFailures.at(key)
                    << ") no longer fails: " << c.explanation;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllModels, VerifyModelsTest,
                         ::testing::ValuesIn(testing::ThirdPartyModels()), testing::ModelTestName);

TEST(VerifyModelsListTest, FindsTheModels) {
  std::vector<std::string> models = testing::ThirdPartyModels();
  auto in_suite = [](const std::string& f) { return f.rfind(testing::kSuite, 0) == 0; };
  long suite = std::count_if(models.begin(), models.end(), in_suite);
  EXPECT_GE(static_cast<long>(models.size()) - suite, 17)
      << "MuJoCo's sample models are missing from " << testing::kSamples
      << ": install Debian's libmujoco-samples (scripts/install-deps.sh does)";
  EXPECT_GE(suite, 18) << "the DeepMind Control Suite models are missing from " << testing::kSuite
                       << ": they are part of the checkout (git status)";
}

}  // namespace
}  // namespace plumb
