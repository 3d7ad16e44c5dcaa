// Paths and values: ResolvePath, ExpandPath, ScalarPaths, ParseAssignment and WriteValues on
// the pendulum and the humanoid.

#include "fuzz_common.h"
#include "plumb/path.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace plumb;
  std::string text = fuzz::Text(data, size);
  for (const Model* model : {&fuzz::Pendulum(), &fuzz::Humanoid()}) {
    fuzz::Expect([&] {
      for (const Path& p : ExpandPath(*model, text)) ScalarPaths(p);
    });
    fuzz::Expect([&] { ResolvePath(*model, text); });
    fuzz::Expect([&] {
      Assignment a = ParseAssignment(*model, text);
      Model work = model->Clone();
      Data d(work);
      ApplyAssignments(work, d, {a});
    });
  }
  return 0;
}
