// Pictures and films of runs (render.h's RenderAt, PlanFilm, RenderFilm) and the size text.

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "fixture.h"
#include "plumb/error.h"
#include "plumb/render.h"

namespace plumb {
namespace {

using FilmTest = testing::MujocoTest;

// A 32x24 renderer of `model` in `renderer`, or why there is none.
std::string Small(const Model& model, std::optional<Renderer>* renderer) {
  RenderOptions options;
  options.width = 32;
  options.height = 24;
  options.shadow_size = 256;
  try {
    renderer->emplace(model, options);
  } catch (const UnavailableError& e) {
    return e.what();
  }
  return "";
}

TEST_F(FilmTest, SizeTextNamesItsArgument) {
  EXPECT_EQ(ParseImageSize("640x480"), std::make_pair(640, 480));
  EXPECT_EQ(ParseImageSize("16X9"), std::make_pair(16, 9));
  for (const char* bad : {"640", "0x480", "640x480x3", "9000x10", "axb"}) {
    try {
      ParseImageSize(bad);
      ADD_FAILURE() << bad;
    } catch (const ArgumentError& e) {
      EXPECT_EQ(e.argument(), "size");
    }
  }
}

// Frames a whole number of steps apart: 30 fps at 2 ms is every 17 steps, 29.4 fps.
TEST_F(FilmTest, PlansFramesOnWholeSteps) {
  FilmPlan plan = PlanFilm(0.002, 1.0, 30);
  EXPECT_EQ(plan.steps, 500);
  EXPECT_EQ(plan.stride, 17);
  EXPECT_NEAR(plan.fps, 1 / 0.034, 1e-9);
  EXPECT_EQ(plan.frames, 500 / 17 + 1);
  EXPECT_EQ(PlanFilm(0.002, 1.0, 10000 / 10.0).stride, 1);
  std::vector<std::tuple<double, double, std::string>> bad = {
      {-1.0, 30.0, "until"}, {1.0, 0.0, "fps"}, {1.0, 2000.0, "fps"}};
  for (const auto& [until, fps, argument] : bad) {
    try {
      PlanFilm(0.002, until, fps);
      ADD_FAILURE() << argument;
    } catch (const ArgumentError& e) {
      EXPECT_EQ(e.argument(), argument);
    }
  }
}

TEST_F(FilmTest, RendersTheFramesThePlanSays) {
  Model model = Model::Load(testing::kPendulum);
  Data data(model);
  ApplyAssignments(model, data, {ParseAssignment(model, "qpos[hinge]=0.7")});
  std::optional<Renderer> renderer;
  std::string why = Small(model, &renderer);
  if (!why.empty()) GTEST_SKIP() << "no renderer here: " << why;
  FilmPlan plan = PlanFilm(model->opt.timestep, 0.2, 10);
  std::vector<double> times;
  std::vector<std::uint8_t> last;
  RunResult result = RenderFilm(model, data, *renderer, plan, StopToken{}, [&](const Image& f) {
    EXPECT_EQ(f.width, 32);
    times.push_back(data->time);
    last = f.rgb;
  });
  EXPECT_FALSE(result.diverged);
  ASSERT_EQ(static_cast<long>(times.size()), plan.frames);
  EXPECT_NEAR(times.back(), 0.2, 1e-12);
  Image picture;
  Data again(model);
  ApplyAssignments(model, again, {ParseAssignment(model, "qpos[hinge]=0.7")});
  result = RenderAt(model, again, *renderer, 0.2, StopToken{}, &picture);
  EXPECT_EQ(result.steps, 100);
  // the state at 0.2 s, as the film's last frame shows it (not the step before)
  EXPECT_EQ(picture.rgb, last);
  EXPECT_THROW(RenderAt(model, again, *renderer, -1, StopToken{}, &picture), ArgumentError);
}

// A run's samples drawn again give the pictures of the run itself.
TEST_F(FilmTest, SamplesDrawAsTheRunDid) {
  Model model = Model::Load(testing::kPendulum);
  Data data(model);
  ApplyAssignments(model, data, {ParseAssignment(model, "qpos[hinge]=0.7")});
  std::optional<Renderer> renderer;
  std::string why = Small(model, &renderer);
  if (!why.empty()) GTEST_SKIP() << "no renderer here: " << why;
  std::vector<std::vector<std::uint8_t>> filmed, drawn;
  std::vector<double> samples;  // time, qpos, qvel of each frame
  FilmPlan plan = PlanFilm(model->opt.timestep, 0.2, 10);
  RenderFilm(model, data, *renderer, plan, StopToken{}, [&](const Image& f) {
    filmed.push_back(f.rgb);
    samples.insert(samples.end(), {data->time, data->qpos[0], data->qvel[0]});
  });
  std::vector<Path> columns = DefaultColumns(model);
  ASSERT_EQ(columns.size(), 3u);
  Data again(model);
  RenderSamples(model, again, *renderer, columns, samples.data(), static_cast<long>(filmed.size()),
                StopToken{}, [&](const Image& f) { drawn.push_back(f.rgb); });
  EXPECT_EQ(drawn, filmed);
  std::vector<Path> time_only = {ResolvePath(model, "time")};
  EXPECT_THROW(RenderSamples(model, again, *renderer, time_only, samples.data(), 1, StopToken{},
                             [](const Image&) {}),
               ValueError);
}

}  // namespace
}  // namespace plumb
