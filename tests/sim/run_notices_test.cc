#include "sim/run_notices.h"

#include <gtest/gtest.h>

#include "fixture.h"
#include "plumb/path.h"

namespace plumb {
namespace {

using RunNoticesTest = testing::MujocoTest;

// What MuJoCo warned of during a run is said on the call's channel, as the plumb command prints
// it and Python issues it: each kind once with its count, then what no summary holds.
TEST_F(RunNoticesTest, MujocosWarningsOfARunAreSaidOnce) {
  Model model = Model::FromXmlString(testing::OverfullModel(), "crowded.xml");
  Data data(model);
  RunSpec spec;
  spec.until = 0.1;
  spec.every = 0.01;
  NullSink sink;
  RunResult result = plumb::Run(model, data, spec, sink);
  ASSERT_EQ(result.warnings.size(), 1u);
  const WarningSummary& w = result.warnings[0];
  Notices notices;
  internal::AddRunWarnings(result, TakeMujocoWarnings(), &notices);
  internal::AddRunWarnings(result, {w.message + " Time = 0.0020.", "Another."}, &notices);
  std::vector<Notice> said = notices.all();
  ASSERT_EQ(said.size(), 3u);
  EXPECT_EQ(said[0].level, NoticeLevel::kWarning);
  EXPECT_EQ(said[0].Line().rfind("warning: MuJoCo " + testing::kOverfullWarning + " raised " +
                                     std::to_string(w.count) + " time(s), first in step ",
                                 0),
            0u)
      << said[0].Line();
  EXPECT_EQ(said[1].text, said[0].text);            // the summary again; its message not
  EXPECT_EQ(said[2].Line(), "warning: MuJoCo: Another.");
  internal::AddRunWarnings(result, {}, nullptr);  // no channel: nothing to do
}

}  // namespace
}  // namespace plumb
