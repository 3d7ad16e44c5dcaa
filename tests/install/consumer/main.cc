// Runs the pendulum through an installed plumb and prints q at 0.5 s.
#include <cstdio>

#include "plumb/plumb.h"  // the umbrella: every public header compiles in a user's project

namespace {
class Last : public plumb::SampleSink {
 public:
  void Begin(const std::vector<plumb::Path>&) override {}
  void Sample(const std::vector<double>& row) override { q = row[1]; }
  double q = 0;
};
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  plumb::Model model = plumb::Model::Load(argv[1]);
  plumb::Data data(model);
  plumb::ApplyAssignments(model, data, {plumb::ParseAssignment(model, "qpos[hinge]=0.7")});
  plumb::RunSpec spec;
  spec.until = 0.5;
  spec.columns = {plumb::ResolvePath(model, "time"), plumb::ResolvePath(model, "qpos[hinge]")};
  Last sink;
  plumb::Run(model, data, spec, sink);
  std::printf("q(0.5) = %.5f\n", sink.q);
  return 0;
}
