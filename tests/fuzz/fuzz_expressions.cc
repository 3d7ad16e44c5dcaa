// Metric expressions, distributions, randomizations and scenario assertions.

#include "fuzz_common.h"
#include "plumb/metric.h"
#include "plumb/rollout.h"
#include "plumb/scenario.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace plumb;
  std::string text = fuzz::Text(data, size);
  const Model& model = fuzz::Humanoid();
  fuzz::Expect([&] { ParseMetric(model, text); });
  fuzz::Expect([&] { ParseDistribution(text); });
  fuzz::Expect([&] { ParseRandomization(model, text); });
  fuzz::Expect([&] { ParseAssertion(model, text); });
  return 0;
}
