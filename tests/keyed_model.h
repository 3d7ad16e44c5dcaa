// A model with keyframes for the --keyframe tests: a slider with a motor and a mocap
// body, keyframe "home" setting every part (time, qpos, qvel, ctrl, mocap) and "away"
// only qpos.

#ifndef PLUMB_TESTS_KEYED_MODEL_H_
#define PLUMB_TESTS_KEYED_MODEL_H_

namespace plumb::testing {

inline constexpr char kKeyed[] = R"(
<mujoco model="keyed">
  <option timestep="0.01"/>
  <worldbody>
    <body name="cart">
      <joint name="slider" type="slide" axis="1 0 0"/>
      <geom type="box" size="0.1 0.1 0.1" mass="1"/>
    </body>
    <body name="target" mocap="true" pos="1 0 0">
      <geom type="sphere" size="0.05" contype="0" conaffinity="0"/>
    </body>
  </worldbody>
  <actuator><motor name="push" joint="slider" ctrlrange="-1 1" ctrllimited="true"/></actuator>
  <keyframe>
    <key name="home" qpos="0.5" qvel="0.2" ctrl="0.3" time="1" mpos="2 0 0"/>
    <key name="away" qpos="-0.5"/>
  </keyframe>
</mujoco>)";

}  // namespace plumb::testing

#endif  // PLUMB_TESTS_KEYED_MODEL_H_
