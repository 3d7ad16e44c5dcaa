#include "plumb/audit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/mujoco_compat.h"
#include "fixture.h"
#include "plumb/error.h"
#include "plumb/repro.h"

namespace plumb {
namespace {

using testing::TempDir;
using testing::WriteFile;

// The first finding of `check` that names `element`, or nullptr.
const CheckRow* Find(const AuditReport& report, const std::string& check,
                     const std::string& element = "") {
  for (const CheckRow& f : report.findings) {
    if (f.id == check && f.About().find(element) != std::string::npos) return &f;
  }
  return nullptr;
}

std::string Failures(const AuditReport& report) {
  std::string out;
  for (const CheckRow& f : report.findings) {
    if (f.status == CheckStatus::kFail)
      out += f.id + " " + f.About() + ": " + f.measured_text + "\n";
  }
  return out;
}

class AuditTest : public testing::MujocoTest {
 protected:
  AuditReport AuditXml(const std::string& xml, AuditOptions options = {}) {
    Model model = Model::FromXmlString(xml, "planted.xml");
    AuditReport report = Audit(model, options);
    TakeMujocoWarnings();
    return report;
  }
};

// Euler integrates joint damping implicitly: a stiff servo on 1 kg at h = 0.01 s (kp h^2 / m =
// 5) is unstable without damping, and stays so with d = 40 (bound 4 + 2 h d / m = 4.8), but
// d = 100 (bound 6) makes it stable; the margins say so, and so does MuJoCo's run
TEST_F(AuditTest, TheStabilityMarginCountsJointDamping) {
  auto slider = [](int damping) {
    return "<mujoco><option timestep=\"0.01\" gravity=\"0 0 0\"/><worldbody><body>"
           "<joint name=\"s\" type=\"slide\" axis=\"1 0 0\" damping=\"" +
           std::to_string(damping) +
           "\"/><geom type=\"sphere\" size=\"0.05\" mass=\"1\"/></body></worldbody>"
           "<actuator><position name=\"p\" joint=\"s\" kp=\"50000\"/></actuator></mujoco>";
  };
  struct Case {
    int damping;
    double margin;
    bool diverges;
  } cases[] = {{0, 0.8, true}, {40, 0.96, true}, {100, 1.2, false}};
  for (const Case& c : cases) {
    const CheckRow* row = Find(AuditXml(slider(c.damping)), "actuator.stability");
    ASSERT_NE(row, nullptr) << c.damping;
    EXPECT_NEAR(row->measured.value, c.margin, 1e-9) << c.damping;
    EXPECT_EQ(row->status, c.margin < 1 ? CheckStatus::kFail : CheckStatus::kWarn);
    Model model = Model::FromXmlString(slider(c.damping));
    Data data(model);
    data->ctrl[0] = 0.1;
    bool diverged = false;
    for (int i = 0; i < 200 && !diverged; ++i) {
      mj_step(model.get(), data.get());
      diverged = data->warning[mjWARN_BADQACC].number > 0 || !(std::fabs(data->qpos[0]) < 1);
    }
    EXPECT_EQ(diverged, c.diverges) << c.damping;
  }
}

TEST_F(AuditTest, CollisionlessFreeBodyFallsForever) {
  AuditReport r = AuditXml(R"(<mujoco><worldbody>
      <geom name="floor" type="plane" size="5 5 0.1"/>
      <body name="ghost" pos="0 0 1"><freejoint/>
        <geom type="box" size="0.1 0.1 0.1" contype="0" conaffinity="0"/></body>
    </worldbody></mujoco>)");
  const CheckRow* f = Find(r, "contact.free_fall", "'ghost'");
  ASSERT_NE(f, nullptr) << Failures(r);
  EXPECT_EQ(f->section, "contact");
  EXPECT_EQ(f->status, CheckStatus::kFail);
  EXPECT_EQ(f->element.kind, "body");
  EXPECT_EQ(f->element.name, "ghost");
  EXPECT_EQ(f->element.id, 1);
}

TEST_F(AuditTest, ARobotWithoutAFloorWarnsNotFails) {
  // every Menagerie robot.xml failed contact.free_fall: it has no floor because scene.xml,
  // which includes it, adds one
  AuditReport r = AuditXml(R"(<mujoco><worldbody>
      <body name="base" pos="0 0 1"><freejoint/>
        <geom type="box" size="0.1 0.1 0.1"/></body>
    </worldbody></mujoco>)");
  const CheckRow* f = Find(r, "contact.free_fall", "'base'");
  ASSERT_NE(f, nullptr) << Failures(r);
  EXPECT_EQ(f->status, CheckStatus::kWarn);
  EXPECT_NE(f->measured_text.find("no floor"), std::string::npos) << f->measured_text;
  EXPECT_NE(f->fix.find("audit the scene"), std::string::npos) << f->fix;
}

TEST_F(AuditTest, AHeavyBodyRestingOnlyOnALightOneIsAFinding) {
  // a 50 kg box can touch only a 0.1 kg plate (bit 2), which alone touches the floor (bit 1)
  const char* xml = R"(<mujoco><worldbody>
      <geom name="floor" type="plane" size="5 5 0.1"/>
      <body name="plate" pos="0 0 0.05"><freejoint/>
        <geom type="box" size="0.3 0.3 0.02" mass="%s" contype="3" conaffinity="3"/></body>
      <body name="crate" pos="0 0 0.3"><freejoint/>
        <geom type="box" size="0.2 0.2 0.2" mass="%s" contype="2" conaffinity="2"/></body>
    </worldbody></mujoco>)";
  char text[1024];
  std::snprintf(text, sizeof(text), xml, "0.1", "50");
  AuditReport heavy = AuditXml(text);
  const CheckRow* f = Find(heavy, "contact.heavy_on_light", "'crate'");
  ASSERT_NE(f, nullptr) << Failures(heavy);
  EXPECT_EQ(f->status, CheckStatus::kWarn);
  EXPECT_NE(f->measured_text.find("body 'plate'"), std::string::npos) << f->measured_text;
  EXPECT_EQ(Find(heavy, "contact.free_fall"), nullptr);
  // the other way round is how things rest: no finding
  std::snprintf(text, sizeof(text), xml, "50", "0.1");
  EXPECT_EQ(Find(AuditXml(text), "contact.heavy_on_light"), nullptr);
}

TEST_F(AuditTest, AHeavyBodyThatCollidesWithNothingCarriedByALightOneIsAFinding) {
  // a 10 kg crate whose box lost its contype rests on a 1e-6 kg pad on a slide joint
  const char* xml = R"(<mujoco><worldbody>
      <geom name="floor" type="plane" size="5 5 0.1"/>
      <body name="crate" pos="0 0 0.5"><freejoint/>
        <geom type="box" size="0.2 0.2 0.2" mass="10" contype="%s" conaffinity="%s"/>
        <body name="pad" pos="0 0 -0.25"><joint type="slide" axis="0 0 1" limited="true" range="-0.01 0.01"/>
          <geom type="box" size="0.2 0.2 0.02" mass="1e-6"/></body></body>
    </worldbody></mujoco>)";
  char text[1024];
  std::snprintf(text, sizeof(text), xml, "0", "0");
  AuditReport r = AuditXml(text);
  const CheckRow* f = Find(r, "contact.carried", "'crate'");
  ASSERT_NE(f, nullptr) << Failures(r);
  EXPECT_EQ(f->status, CheckStatus::kWarn);
  EXPECT_NE(f->measured_text.find("body 'pad'"), std::string::npos) << f->measured_text;
  EXPECT_DOUBLE_EQ(f->measured.value, 1e7);
  // the same crate that collides itself
  std::snprintf(text, sizeof(text), xml, "1", "1");
  EXPECT_EQ(Find(AuditXml(text), "contact.carried"), nullptr);
}

TEST_F(AuditTest, EveryBodySaysWhatItCanCollideWith) {
  // visual-only geoms beside collision geoms, as in the Menagerie, are normal: no finding
  AuditReport r = AuditXml(R"(<mujoco><worldbody>
      <geom name="floor" type="plane" size="5 5 0.1"/>
      <body name="torso" pos="0 0 0.5"><freejoint/>
        <geom type="box" size="0.1 0.1 0.1" contype="0" conaffinity="0" group="2"/>
        <geom type="box" size="0.1 0.1 0.1" group="3"/>
        <body name="antenna" pos="0 0 0.2"><joint type="hinge" axis="0 1 0"/>
          <geom type="capsule" fromto="0 0 0 0 0 0.1" size="0.01" contype="0" conaffinity="0"/>
        </body></body>
    </worldbody></mujoco>)");
  const CheckRow* torso = Find(r, "contact.collides_with", "'torso'");
  ASSERT_NE(torso, nullptr);
  EXPECT_EQ(torso->status, CheckStatus::kPass);
  EXPECT_EQ(torso->measured_text, "collides with the world");
  const CheckRow* antenna = Find(r, "contact.collides_with", "'antenna'");
  ASSERT_NE(antenna, nullptr);
  EXPECT_EQ(antenna->status, CheckStatus::kPass);
  EXPECT_NE(antenna->measured_text.find("visual geoms only"), std::string::npos)
      << antenna->measured_text;
}

TEST_F(AuditTest, PenetrationIsJudgedAgainstTheSoftContactDepth) {
  // a 2 cm ball rests 3.5 mm deep with the default solref (0.02, 1): a sixth of its size, but
  // exactly the softness MuJoCo's contact model gives it; it was a WARN
  AuditReport rest = AuditXml(R"(<mujoco><worldbody>
      <geom name="floor" type="plane" size="5 5 0.1"/>
      <body name="ball" pos="0 0 0.0102"><freejoint/>
        <geom name="foot" type="sphere" size="0.01" mass="1"/></body>
    </worldbody></mujoco>)");
  const CheckRow* f = Find(rest, "contact.penetration");
  ASSERT_NE(f, nullptr) << Failures(rest);
  EXPECT_EQ(f->status, CheckStatus::kPass) << f->measured_text;
  EXPECT_NE(f->measured_text.find("mm its solref/solimp soften it by"), std::string::npos)
      << f->measured_text;
  // a hard drop at a coarse step sinks far beyond that softness: still a finding
  AuditReport drop = AuditXml(R"(<mujoco><option timestep="0.01"/><worldbody>
      <geom name="floor" type="plane" size="5 5 0.1"/>
      <body name="ball" pos="0 0 5"><freejoint/>
        <geom name="foot" type="sphere" size="0.01" mass="1"/></body>
    </worldbody></mujoco>)");
  const CheckRow* g = Find(drop, "contact.penetration");
  ASSERT_NE(g, nullptr) << Failures(drop);
  EXPECT_NE(g->status, CheckStatus::kPass) << g->measured_text;
}

TEST_F(AuditTest, FreeBodiesTouchingOnlyEachOtherStillFall) {
  // two free boxes collide with each other (bit 2) but nothing reaches the floor (bit 1)
  AuditReport r = AuditXml(R"(<mujoco><worldbody>
      <geom name="floor" type="plane" size="5 5 0.1" contype="1" conaffinity="1"/>
      <body name="a" pos="0 0 1"><freejoint/>
        <geom type="box" size="0.1 0.1 0.1" contype="2" conaffinity="2"/></body>
      <body name="b" pos="0 0 1.5"><freejoint/>
        <geom type="box" size="0.1 0.1 0.1" contype="2" conaffinity="2"/></body>
    </worldbody></mujoco>)");
  ASSERT_NE(Find(r, "contact.free_fall", "'a'"), nullptr) << Failures(r);
  ASSERT_NE(Find(r, "contact.free_fall", "'b'"), nullptr) << Failures(r);
  // a chain does hold: b rests on a, a on the floor
  AuditReport chain = AuditXml(R"(<mujoco><worldbody>
      <geom name="floor" type="plane" size="5 5 0.1" contype="1" conaffinity="1"/>
      <body name="a" pos="0 0 0.1"><freejoint/>
        <geom type="box" size="0.1 0.1 0.1" contype="3" conaffinity="3"/></body>
      <body name="b" pos="0 0 0.35"><freejoint/>
        <geom type="box" size="0.1 0.1 0.1" contype="2" conaffinity="2"/></body>
    </worldbody></mujoco>)");
  EXPECT_EQ(Find(chain, "contact.free_fall"), nullptr) << Failures(chain);
}

TEST_F(AuditTest, WithoutGravityNothingFalls) {
  // <flag gravity="disable"/> (dm_control's fish swims): no free-fall FAIL, no support row
  AuditReport r = AuditXml(R"(<mujoco><option><flag gravity="disable"/></option><worldbody>
      <body name="fish" pos="0 0 1"><freejoint/>
        <geom type="ellipsoid" size="0.1 0.05 0.05" contype="0" conaffinity="0"/></body>
    </worldbody></mujoco>)");
  EXPECT_EQ(Find(r, "contact.free_fall"), nullptr) << Failures(r);
  EXPECT_EQ(Find(r, "contact.support"), nullptr);
}

TEST_F(AuditTest, FeatherweightBodyOnAHeavyBaseIsFlagged) {
  AuditReport r = AuditXml(R"(<mujoco><worldbody>
      <body name="base" pos="0 0 1"><joint name="j1" axis="0 1 0"/>
        <geom type="box" size="0.2 0.2 0.2" mass="10"/>
        <body name="feather" pos="0.4 0 0"><joint name="j2" axis="0 1 0"/>
          <geom type="sphere" size="0.02" mass="1e-6"/></body>
      </body></worldbody></mujoco>)");
  const CheckRow* tiny = Find(r, "inertia.tiny_mass", "'feather'");
  ASSERT_NE(tiny, nullptr);
  EXPECT_EQ(tiny->section, "inertia");
  EXPECT_EQ(tiny->status, CheckStatus::kWarn);
  // the numbers beside the text: a share of the total mass against its bound
  EXPECT_NEAR(tiny->measured.value, 1e-7, 1e-12) << tiny->measured_text;
  EXPECT_EQ(tiny->measured.unit, "");
  EXPECT_EQ(tiny->reference.value, 1e-4);
  EXPECT_TRUE(tiny->threshold);
  const CheckRow* total = Find(r, "inertia.total_mass");
  ASSERT_NE(total, nullptr);
  EXPECT_NEAR(total->measured.value, 10.000001, 1e-9) << total->measured_text;
  EXPECT_EQ(total->measured.unit, "kg");
  const CheckRow* ratio = Find(r, "inertia.mass_ratio", "'feather'");
  ASSERT_NE(ratio, nullptr);
  EXPECT_EQ(ratio->status, CheckStatus::kFail);  // 1e7: beyond any conditioning
  EXPECT_NE(ratio->measured_text.find("'base'"), std::string::npos);
  EXPECT_EQ(ratio->element.name, "feather");
}

TEST_F(AuditTest, MarkerBodiesWeldedToTheirParentAreNotTinyBodies) {
  // a massless site holder welded to a 10 kg link: one weld group of 10 kg
  AuditReport r = AuditXml(R"(<mujoco><worldbody>
      <body name="link" pos="0 0 1"><joint name="j" axis="0 1 0"/>
        <geom type="box" size="0.2 0.2 0.2" mass="10"/>
        <body name="marker" pos="0.3 0 0"><site name="tip"/></body>
        <body name="label" pos="0.3 0 0"><geom type="sphere" size="0.01" mass="1e-6"/></body>
      </body></worldbody></mujoco>)");
  EXPECT_EQ(Find(r, "inertia.tiny_mass"), nullptr) << Find(r, "inertia.tiny_mass")->About();
  EXPECT_EQ(Find(r, "inertia.mass_ratio"), nullptr);
  EXPECT_EQ(Find(r, "inertia.principal"), nullptr) << Failures(r);
}

// issue 9: a 1000 kg pole with the I = 0.0094 kg*m^2 of a light one passed the audit
constexpr char kHeavyPole[] = R"(<mujoco><worldbody>
    <body name="cart"><joint name="slider" type="slide" axis="1 0 0"/>
      <geom type="box" size="0.2 0.15 0.1" mass="1"/>
      <body name="pole"><joint name="hinge" axis="0 1 0"/>
        INERTIAL<geom type="capsule" fromto="0 0 0 0 0 1" size="0.045" mass="0.1"/></body>
    </body></worldbody></mujoco>)";

std::string HeavyPole(const std::string& inertial) {
  std::string xml = kHeavyPole;
  return xml.replace(xml.find("INERTIAL"), 8, inertial);
}

TEST_F(AuditTest, InertiaImplausibleForMassAndSizeFails) {
  AuditReport r = AuditXml(
      HeavyPole(R"(<inertial pos="0 0 0.5" mass="1000" diaginertia="0.0094 0.0094 0.0001"/>)"));
  const CheckRow* f = Find(r, "inertia.shape", "'pole'");
  ASSERT_NE(f, nullptr) << Failures(r);
  EXPECT_EQ(f->status, CheckStatus::kFail);
  EXPECT_NE(f->measured_text.find("1000 kg"), std::string::npos) << f->measured_text;
  EXPECT_NE(f->fix.find("too small"), std::string::npos) << f->fix;
  // issue 49: the compiled model without its MJCF (as plumb.audit(mujoco.MjModel) gets it, on
  // every MuJoCo, 2.x included) gets the same verdict, not a SKIP
  Model compiled = Model::FromXmlString(
      HeavyPole(R"(<inertial pos="0 0 0.5" mass="1000" diaginertia="0.0094 0.0094 0.0001"/>)"));
  Model borrowed = Model::Borrow(compiled.get_mutable(), "pole");
  AuditReport without = Audit(borrowed, AuditOptions{});
  const CheckRow* same = Find(without, "inertia.shape", "'pole'");
  ASSERT_NE(same, nullptr) << Failures(without);
  EXPECT_EQ(same->status, CheckStatus::kFail);
  for (const CheckRow& row : without.findings) {
    bool inertia = row.id.rfind("inertia.", 0) == 0;
    EXPECT_FALSE(inertia && row.status == CheckStatus::kSkip) << row.id;
  }
  // the same pole as the compiler derives it, and a mass set on it, are plausible
  AuditReport nominal = AuditXml(HeavyPole(""));
  EXPECT_EQ(Find(nominal, "inertia.shape"), nullptr)
      << Find(nominal, "inertia.shape")->measured_text;
  AuditOptions heavier;
  Model model = Model::FromXmlString(HeavyPole(""), "pole.xml");
  heavier.sets = {ParseAssignment(model, "body_mass[pole]=1000")};
  AuditReport set = AuditXml(HeavyPole(""), heavier);
  EXPECT_EQ(Find(set, "inertia.shape"), nullptr) << Find(set, "inertia.shape")->measured_text;
  // a mass spread 6 times wider than the geoms allow (inertia x36) is a warning
  AuditReport wide =
      AuditXml(HeavyPole(R"(<inertial pos="0 0 0.5" mass="0.1" diaginertia="0.3 0.3 0.001"/>)"));
  const CheckRow* w = Find(wide, "inertia.shape", "'pole'");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->status, CheckStatus::kWarn);
}

// issue 49: every inertia is judged now, the derived ones too; one derived from geoms of unlike
// densities (dm_control's pendulum: a massless rod, its 1 kg in the sphere at the tip) fits
// that sphere alone, not the uniform fill of all three (x0.17), and raises nothing
TEST_F(AuditTest, AnInertiaDerivedFromGeomsOfUnlikeDensitiesIsNotFlagged) {
  constexpr char kTipMass[] = R"(<mujoco><worldbody><body name="pole" pos="0 0 .6">
      <joint name="hinge" axis="0 1 0" damping="0.1"/>
      <geom type="cylinder" fromto="0 -.03 0 0 .03 0" size="0.021" mass="0"/>
      <geom type="capsule" fromto="0 0 0 0 0 0.5" size="0.02" mass="0"/>
      <geom type="sphere" pos="0 0 0.5" size="0.05" mass="1"/></body></worldbody></mujoco>)";
  const CheckRow* row = Find(AuditXml(kTipMass), "inertia.shape");
  EXPECT_EQ(row, nullptr) << row->measured_text;
  // a tenth of the sphere's moments written at the rod's middle is no solid of this body, nor
  // of the rod alone (whose centroid that is)
  AuditReport moved = AuditXml(std::string(kTipMass).replace(
      std::string(kTipMass).find("<geom"), 0,
      R"(<inertial pos="0 0 0.25" mass="1" diaginertia="0.0001 0.0001 0.0001"/>)"));
  EXPECT_NE(Find(moved, "inertia.shape", "'pole'"), nullptr) << Failures(moved);
}

TEST_F(AuditTest, MotorWithoutLimitsIsFlagged) {
  AuditReport r = AuditXml(R"(<mujoco><worldbody>
      <body name="arm" pos="0 0 1"><joint name="shoulder" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.03" mass="1"/></body>
    </worldbody><actuator><motor name="strong" joint="shoulder" gear="50"/></actuator></mujoco>)");
  const CheckRow* f = Find(r, "actuator.limits", "'strong'");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->section, "actuator");
  EXPECT_EQ(f->status, CheckStatus::kWarn);
  EXPECT_NE(f->measured_text.find("gear 50"), std::string::npos) << f->measured_text;
  EXPECT_EQ(f->element.name, "strong");
}

TEST_F(AuditTest, ActuatorTooWeakToHoldItsArm) {
  // a 2 kg, 1 m arm held horizontal needs 2 * 9.81 * 0.5 = 9.81 N*m; the motor gives 1
  AuditReport r = AuditXml(R"(<mujoco><worldbody>
      <body name="arm" pos="0 0 1"><joint name="shoulder" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 1 0 0" size="0.03" mass="2"/></body>
    </worldbody><actuator>
      <motor name="weak" joint="shoulder" gear="1" ctrllimited="true" ctrlrange="-1 1"/>
    </actuator></mujoco>)");
  const CheckRow* f = Find(r, "actuator.holding", "'weak'");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->status, CheckStatus::kWarn);
  EXPECT_NE(f->measured_text.find("9.81"), std::string::npos) << f->measured_text;
  // as numbers: what the motor delivers on gravity's side (1 N*m) against the need
  EXPECT_NEAR(std::fabs(f->reference.value), 9.81, 0.01) << f->reference_text;
  EXPECT_EQ(std::fabs(f->measured.value), 1.0) << f->measured_text;
  EXPECT_EQ(f->measured.unit, "N*m");
  EXPECT_EQ(f->reference.unit, "N*m");
  EXPECT_EQ(f->element.kind, "actuator");
  EXPECT_EQ(f->element.name, "weak");
  EXPECT_EQ(Find(r, "actuator.limits", "'weak'"), nullptr);  // its ctrl is limited
}

TEST_F(AuditTest, HoldingRespectsTheSignOfTheTorque) {
  // gravity pulls the arm down (needs -9.81 N*m about +y... or +9.81: whichever sign, a
  // motor that pushes only the other way cannot hold it, one that pushes this way can)
  auto audit = [&](const char* range) {
    return AuditXml(std::string(R"(<mujoco><worldbody>
      <body name="arm" pos="0 0 1"><joint name="shoulder" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 1 0 0" size="0.03" mass="2"/></body>
    </worldbody><actuator>
      <motor name="m" joint="shoulder" gear="1" ctrllimited="true" ctrlrange=")") +
                    range + R"("/></actuator></mujoco>)");
  };
  AuditReport up = audit("0 100"), down = audit("-100 0");
  const CheckRow* a = Find(up, "actuator.holding", "'m'");
  const CheckRow* b = Find(down, "actuator.holding", "'m'");
  ASSERT_NE(a, nullptr);
  ASSERT_NE(b, nullptr);
  // exactly one of the two one-sided motors holds the arm
  EXPECT_NE(a->status, b->status) << a->measured_text << " | " << b->measured_text;
}

TEST_F(AuditTest, MusclesAreBoundedByTheirPeakForce) {
  // a muscle's control is implicitly 0..1 and its force at most its peak force
  AuditReport r = AuditXml(R"(<mujoco><worldbody>
      <body name="arm" pos="0 0 1"><joint name="elbow" axis="0 1 0" limited="true" range="-60 60"/>
        <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.03" mass="1"/></body>
    </worldbody><actuator><muscle name="biceps" joint="elbow"/></actuator></mujoco>)");
  EXPECT_EQ(Find(r, "actuator.limits", "'biceps'"), nullptr)
      << Find(r, "actuator.limits")->measured_text;
  const CheckRow* step = Find(r, "actuator.step_response", "'biceps'");
  ASSERT_NE(step, nullptr);
  EXPECT_NE(step->measured_text.find("no setpoint (muscle)"), std::string::npos)
      << step->measured_text;
}

TEST_F(AuditTest, StepResponsesFitTheActuatorKind) {
  AuditReport r = AuditXml(R"(<mujoco><option gravity="0 0 0"/><worldbody>
      <body name="a" pos="0 0 1"><joint name="ja" axis="0 1 0" damping="1"/>
        <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.03" mass="1"/></body>
      <body name="b" pos="1 0 1"><joint name="jb" axis="0 1 0" damping="1"/>
        <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.03" mass="1"/></body>
    </worldbody><actuator>
      <position name="servo" joint="ja" kp="20" ctrllimited="true" ctrlrange="-1 1"/>
      <motor name="motor" joint="jb" ctrllimited="true" ctrlrange="-1 1"/>
    </actuator></mujoco>)");
  const CheckRow* servo = Find(r, "actuator.step_response", "'servo'");
  const CheckRow* motor = Find(r, "actuator.step_response", "'motor'");
  ASSERT_NE(servo, nullptr);
  ASSERT_NE(motor, nullptr);
  EXPECT_NE(servo->measured_text.find("position servo: rise "), std::string::npos)
      << servo->measured_text;
  EXPECT_NE(servo->measured_text.find("steady-state error"), std::string::npos)
      << servo->measured_text;
  EXPECT_NE(motor->measured_text.find("no setpoint (motor)"), std::string::npos)
      << motor->measured_text;
}

TEST_F(AuditTest, DivergingStepResponseIsAFinding) {
  // a servo this stiff on a light link explodes at this timestep, with gravity off too
  AuditReport r = AuditXml(R"(<mujoco><option timestep="0.01"/><worldbody>
      <geom name="floor" type="plane" size="5 5 0.1"/>
      <body name="a" pos="0 0 1"><joint name="ja" type="slide" axis="1 0 0"/>
        <geom type="sphere" size="0.05" mass="0.01"/></body>
    </worldbody><actuator>
      <position name="stiff" joint="ja" kp="1e6" ctrllimited="true" ctrlrange="-1 1"/>
    </actuator></mujoco>)");
  const CheckRow* f = Find(r, "actuator.step_response", "'stiff'");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->status, CheckStatus::kFail) << f->measured_text;
  EXPECT_EQ(f->measured_text, "diverged");
  EXPECT_NE(f->fix.find("smaller timestep"), std::string::npos) << f->fix;
}

TEST_F(AuditTest, SetStateDefinesTheReferencePose) {
  // the arm hangs at qpos0 (no gravity torque); --set qpos=1.57 puts it horizontal,
  // where the weak motor cannot hold it, even though the model has a home keyframe
  Model model = Model::FromXmlString(R"(<mujoco><worldbody>
      <body name="arm" pos="0 0 1"><joint name="shoulder" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -1" size="0.03" mass="2"/></body>
    </worldbody><actuator>
      <motor name="weak" joint="shoulder" gear="1" ctrllimited="true" ctrlrange="-1 1"/>
    </actuator><keyframe><key name="home" qpos="0"/></keyframe></mujoco>)",
                                     "arm.xml");
  AuditReport hanging = Audit(model, {});
  AuditOptions options;
  options.sets = {ParseAssignment(model, "qpos[shoulder]=1.57")};
  AuditReport horizontal = Audit(model, options);
  TakeMujocoWarnings();
  ASSERT_NE(Find(hanging, "actuator.holding", "'weak'"), nullptr);
  EXPECT_EQ(Find(hanging, "actuator.holding", "'weak'")->status, CheckStatus::kPass);
  EXPECT_EQ(Find(horizontal, "actuator.holding", "'weak'")->status, CheckStatus::kWarn);
}

TEST_F(AuditTest, RadiansWrittenWhereMjcfExpectsDegreesAreFlagged) {
  // MJCF angles default to degrees: range="-1.5 1.5" is +-1.5 degrees, not radians
  AuditReport r = AuditXml(R"(<mujoco><compiler autolimits="true"/><worldbody>
      <body name="arm" pos="0 0 1"><joint name="shoulder" axis="0 1 0" range="-1.5 1.5"/>
        <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.03" mass="1"/></body>
    </worldbody><actuator>
      <position name="servo" joint="shoulder" kp="50" ctrlrange="-1.5 1.5"/>
    </actuator></mujoco>)");
  const CheckRow* range = Find(r, "structure.joint_range", "'shoulder'");
  ASSERT_NE(range, nullptr);
  EXPECT_EQ(range->status, CheckStatus::kWarn);
  EXPECT_NE(range->fix.find("angle=\"radian\""), std::string::npos) << range->fix;
  const CheckRow* target = Find(r, "actuator.target_range", "'servo'");
  ASSERT_NE(target, nullptr);
  EXPECT_EQ(target->section, "actuator");
}

TEST_F(AuditTest, DivergingTimestepIsCaughtWithARepro) {
  TempDir dir;
  AuditOptions options;
  std::vector<std::string> kept;
  options.keep_diverged = [&](const Model& work, const RunResult& run, const std::string& what) {
    kept.push_back(what);
    EXPECT_TRUE(run.diverged);
    return WriteRepro(work, run, {"plumb", "audit"}, dir.File("repro"), what);
  };
  AuditReport r = AuditXml(R"(<mujoco><option timestep="0.01" gravity="0 0 0"/><worldbody>
      <body name="mass"><joint name="spring" type="slide" axis="1 0 0" stiffness="1e6" ref="0.01"/>
        <geom type="sphere" size="0.05" mass="1"/></body></worldbody></mujoco>)",
                           options);
  const CheckRow* f = Find(r, "behaviour.passive_settle");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->status, CheckStatus::kFail);
  EXPECT_EQ(f->measured_text, "diverged");
  EXPECT_NE(f->fix.find("joint 'spring'"), std::string::npos) << f->fix;
  EXPECT_NE(f->fix.find("smaller timestep"), std::string::npos) << f->fix;
  ASSERT_FALSE(r.repro_folders.empty());
  EXPECT_TRUE(std::filesystem::exists(r.repro_folders[0] + "/model.mjb"));
  ASSERT_FALSE(kept.empty());
  EXPECT_NE(kept[0].find("the audit run that diverged"), std::string::npos) << kept[0];
  EXPECT_NE(f->fix.find("Repro folder: " + r.repro_folders[0]), std::string::npos) << f->fix;
}

// The audit writes nothing: without keep_diverged a diverged run is reported, and no
// folder appears.
TEST_F(AuditTest, ADivergedRunIsReportedWithoutWritingAnything) {
  TempDir dir;
  auto before = std::filesystem::current_path();
  std::filesystem::current_path(dir.path());
  AuditReport r = AuditXml(R"(<mujoco><option timestep="0.01" gravity="0 0 0"/><worldbody>
      <body name="mass"><joint name="spring" type="slide" axis="1 0 0" stiffness="1e6" ref="0.01"/>
        <geom type="sphere" size="0.05" mass="1"/></body></worldbody></mujoco>)",
                           {});
  std::filesystem::current_path(before);
  const CheckRow* f = Find(r, "behaviour.passive_settle");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->measured_text, "diverged");
  EXPECT_TRUE(r.repro_folders.empty());
  EXPECT_EQ(f->fix.find("Repro folder"), std::string::npos) << f->fix;
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST_F(AuditTest, HumanoidHasNoFailure) {
  AuditReport r = Audit(Model::Load(testing::kHumanoid), {});
  TakeMujocoWarnings();
  EXPECT_EQ(r.Count(CheckStatus::kFail), 0) << Failures(r);
  for (const char* layer :
       {"structure", "inertia", "actuator", "contact", "behaviour", "warnings"}) {
    bool seen = false;
    for (const CheckRow& f : r.findings) seen = seen || f.section == layer;
    EXPECT_TRUE(seen) << layer;
  }
  const CheckRow* nq = Find(r, "structure.nq_nv", "'root'");
  ASSERT_NE(nq, nullptr);
  EXPECT_NE(nq->measured_text.find("nq 28 != nv 27"), std::string::npos);
}

TEST_F(AuditTest, BoxComesToRestOnItsWeight) {
  AuditReport r = AuditXml(R"(<mujoco><worldbody>
      <geom name="floor" type="plane" size="5 5 0.1"/>
      <body name="box" pos="0 0 0.2"><freejoint/><geom type="box" size="0.1 0.1 0.1" mass="3"/></body>
    </worldbody></mujoco>)");
  const CheckRow* support = Find(r, "contact.support");
  ASSERT_NE(support, nullptr);
  EXPECT_EQ(support->status, CheckStatus::kPass) << support->measured_text;
  EXPECT_NEAR(support->measured.value, 1.0, 0.1) << support->measured_text;
  EXPECT_FALSE(support->reference.known());  // inside 0.9 .. 1.1: no bound crossed
  EXPECT_EQ(Find(r, "contact.slip")->status, CheckStatus::kPass);
  EXPECT_EQ(Find(r, "contact.slip")->measured.unit, "m/s");
  EXPECT_EQ(r.Count(CheckStatus::kFail), 0) << Failures(r);
}

constexpr char kArm[] = R"(<mujoco><worldbody>
    <body name="upper" pos="0 0 1"><joint name="shoulder" axis="0 1 0" damping="1"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.03" mass="1"/></body>
  </worldbody>
  <actuator><position name="servo" joint="shoulder" kp="50" ctrllimited="true" ctrlrange="-1 1"/></actuator>
  <keyframe><key name="home" qpos="0.3"/></keyframe>
</mujoco>)";

TEST_F(AuditTest, ScenarioAssertionsPassAndFailWhenTheyShould) {
  TempDir dir;
  Model model = Model::FromXmlString(kArm, "arm.xml");
  WriteFile(dir.File("lift.toml"), R"(
name = "lift"
duration = 3.0
keyframe = "home"
assertions = ["qpos[shoulder] > 0.5 during [2, 3]",
              "maxabs(qvel[*]) < 50",
              "qpos[shoulder] < 0.5 during [2, 3]"]
[[controls]]
actuator = "servo"
type = "step"
before = 0.3
value = 0.8
at = 0.5
)");
  AuditOptions options;
  options.scenario = LoadScenario(model, dir.File("lift.toml"));
  AuditReport r = Audit(model, options);
  std::vector<const CheckRow*> rows;
  for (const CheckRow& f : r.findings) {
    if (f.id == "behaviour.assertion") rows.push_back(&f);
  }
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0]->status, CheckStatus::kPass) << rows[0]->measured_text;
  EXPECT_EQ(rows[1]->status, CheckStatus::kPass) << rows[1]->measured_text;
  EXPECT_EQ(rows[2]->status, CheckStatus::kFail);
  EXPECT_NE(rows[2]->measured_text.find("at t = 2"), std::string::npos) << rows[2]->measured_text;
}

TEST_F(AuditTest, JsonScenarioWithRampAndSine) {
  TempDir dir;
  Model model = Model::FromXmlString(kArm, "arm.xml");
  WriteFile(dir.File("s.json"), R"({"name": "wave", "duration": 2,
    "initial": {"qpos[shoulder]": 0.1},
    "controls": [{"actuator": "servo", "type": "sine", "offset": 0, "amplitude": 0.2,
                  "frequency": 1}],
    "assertions": ["maxabs(qpos[shoulder]) < 0.5", "final(time) >= 2"]})");
  Scenario sc = LoadScenario(model, dir.File("s.json"));
  EXPECT_EQ(sc.controls[0].At(0.25), 0.2);
  EXPECT_EQ(sc.initial.size(), 1u);
  AuditOptions options;
  options.scenario = sc;
  AuditReport r = Audit(model, options);
  TakeMujocoWarnings();
  for (const CheckRow& f : r.findings) {
    if (f.id == "behaviour.assertion") {
      EXPECT_EQ(f.status, CheckStatus::kPass) << f.About();
    }
  }
}

TEST_F(AuditTest, BadScenariosNameTheFileAndEntry) {
  TempDir dir;
  Model model = Model::FromXmlString(kArm, "arm.xml");
  WriteFile(dir.File("a.json"), R"({"controls": [{"actuator": "srvo"}]})");
  try {
    LoadScenario(model, dir.File("a.json"));
    FAIL();
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("a.json"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("did you mean: servo"), std::string::npos) << e.what();
  }
  WriteFile(dir.File("b.toml"), "duration = \n");
  EXPECT_THROW(LoadScenario(model, dir.File("b.toml")), ValueError);
  // a TOML syntax error names its line and column (toml++ keeps positions)
  WriteFile(dir.File("e.toml"), "name = \"x\"\nduration = 1.0\nassertions = [\n");
  try {
    LoadScenario(model, dir.File("e.toml"));
    FAIL();
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("e.toml' is not valid TOML: line 3, column"),
              std::string::npos)
        << e.what();
  }
  WriteFile(dir.File("c.json"), R"({"assertions": ["qpos[shoulder] ~ 1"]})");
  EXPECT_THROW(LoadScenario(model, dir.File("c.json")), ValueError);
  WriteFile(dir.File("d.json"), R"({"durations": 1})");
  EXPECT_THROW(LoadScenario(model, dir.File("d.json")), ValueError);
  EXPECT_THROW(LoadScenario(model, dir.File("missing.json")), IoError);
}

TEST_F(AuditTest, RampAndConstantControlsDriveTheScenario) {
  TempDir dir;
  Model model = Model::FromXmlString(kArm, "arm.xml");
  WriteFile(dir.File("r.toml"), R"(
duration = 3.0
assertions = ["final(qpos[shoulder]) > 0.5", "final(qpos[shoulder]) < 0.7"]
[[controls]]
actuator = "servo"
type = "ramp"
from = 0.0
to = 0.6
start = 0.5
end = 1.5
)");
  Scenario ramp = LoadScenario(model, dir.File("r.toml"));
  ASSERT_EQ(ramp.controls.size(), 1u);
  EXPECT_EQ(ramp.controls[0].At(0.2), 0.0);
  EXPECT_DOUBLE_EQ(ramp.controls[0].At(1.0), 0.3);
  EXPECT_EQ(ramp.controls[0].At(2.0), 0.6);
  AuditOptions options;
  options.scenario = ramp;
  AuditReport r = Audit(model, options);
  TakeMujocoWarnings();
  for (const CheckRow& f : r.findings) {
    if (f.id == "behaviour.assertion") {
      EXPECT_EQ(f.status, CheckStatus::kPass) << f.measured_text;
    }
  }
  // a constant control holds the servo at -0.4 instead: the same assertions fail
  WriteFile(dir.File("c.json"), R"({"duration": 3,
    "controls": [{"actuator": "servo", "type": "constant", "value": -0.4}],
    "assertions": ["final(qpos[shoulder]) > 0.5", "final(qpos[shoulder]) < -0.3"]})");
  options.scenario = LoadScenario(model, dir.File("c.json"));
  EXPECT_EQ(options.scenario->controls[0].At(2.5), -0.4);
  AuditReport c = Audit(model, options);
  TakeMujocoWarnings();
  std::vector<CheckStatus> statuses;
  for (const CheckRow& f : c.findings) {
    if (f.id == "behaviour.assertion") statuses.push_back(f.status);
  }
  EXPECT_EQ(statuses, (std::vector<CheckStatus>{CheckStatus::kFail, CheckStatus::kPass}));
}

TEST_F(AuditTest, FinalChecksEveryPath) {
  // two links: only the first is driven up; final(qpos[*]) > 0.5 must fail on the second
  Model model = Model::FromXmlString(R"(<mujoco><option gravity="0 0 0"/><worldbody>
      <body name="a" pos="0 0 1"><joint name="ja" axis="0 1 0" damping="1"/>
        <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.03" mass="1"/></body>
      <body name="b" pos="1 0 1"><joint name="jb" axis="0 1 0" damping="1"/>
        <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.03" mass="1"/></body>
    </worldbody><actuator>
      <position name="sa" joint="ja" kp="20" ctrllimited="true" ctrlrange="-1 1"/>
      <position name="sb" joint="jb" kp="20" ctrllimited="true" ctrlrange="-1 1"/>
    </actuator></mujoco>)",
                                     "two.xml");
  TempDir dir;
  // jb is listed last, so a check of only the last path would see it; ja first must fail
  WriteFile(dir.File("f.json"), R"({"duration": 2,
    "controls": [{"actuator": "sa", "value": 0.0}, {"actuator": "sb", "value": 0.8}],
    "assertions": ["final(qpos[*]) > 0.5"]})");
  AuditOptions options;
  options.scenario = LoadScenario(model, dir.File("f.json"));
  AuditReport r = Audit(model, options);
  TakeMujocoWarnings();
  const CheckRow* f = Find(r, "behaviour.assertion");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->status, CheckStatus::kFail) << f->measured_text;
  EXPECT_NE(f->measured_text.find("qpos[ja]"), std::string::npos) << f->measured_text;
}

// The message of the ValueError LoadScenario throws for `text` in `name`.
std::string ScenarioError(const Model& model, const TempDir& dir, const std::string& name,
                          const std::string& text) {
  WriteFile(dir.File(name), text);
  try {
    LoadScenario(model, dir.File(name));
  } catch (const ValueError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST_F(AuditTest, ScenarioErrorsGiveTheLineOrPointer) {
  TempDir dir;
  Model model = Model::FromXmlString(kArm, "arm.xml");
  std::string toml = ScenarioError(model, dir, "bad.toml", R"(name = "x"
duration = 1.0

[[controls]]
actuator = "servo"
type = "step"
valu = 0.5
)");
  EXPECT_NE(toml.find("bad.toml:7:1 (controls[0].valu)"), std::string::npos) << toml;
  EXPECT_NE(toml.find("did you mean: value"), std::string::npos) << toml;
  std::string window = ScenarioError(model, dir, "w.toml", R"(duration = 1.0
assertions = [
  "maxabs(qvel[*]) < 50",
  "qpos[shoulder] > 0 during [0.5, 3]",
]
)");
  EXPECT_NE(window.find("w.toml:4:3 (assertions[1])"), std::string::npos) << window;
  EXPECT_NE(window.find("raise duration"), std::string::npos) << window;
  std::string key = ScenarioError(model, dir, "k.json", R"({"keyframe": 0})");
  EXPECT_NE(key.find("k.json at /keyframe"), std::string::npos) << key;
  EXPECT_NE(key.find("by name"), std::string::npos) << key;
  std::string type = ScenarioError(model, dir, "t.json",
                                   R"({"controls": [{"actuator": "servo", "value": "high"}]})");
  EXPECT_NE(type.find("t.json at /controls/0/value"), std::string::npos) << type;
  EXPECT_NE(type.find("must be a number"), std::string::npos) << type;
  std::string shape = ScenarioError(model, dir, "s.json", R"({"controls": {"actuator": 1}})");
  EXPECT_NE(shape.find("s.json at /controls"), std::string::npos) << shape;
  std::string name = ScenarioError(model, dir, "n.json", R"({"name": 3})");
  EXPECT_NE(name.find("n.json at /name"), std::string::npos) << name;
}

TEST_F(AuditTest, AssertionsParse) {
  Model model = Model::FromXmlString(kArm, "arm.xml");
  Assertion a = ParseAssertion(model, "xpos[upper][2] >= 0.5 during [0.5, 1]");
  EXPECT_EQ(a.op, Comparison::kGreaterEqual);
  EXPECT_EQ(a.bound, 0.5);
  EXPECT_EQ(a.from, 0.5);
  EXPECT_EQ(a.to, 1);
  Assertion b = ParseAssertion(model, "maxabs(qvel[*]) < 50");
  EXPECT_EQ(b.reduce, Reduction::kMaxAbs);
  EXPECT_EQ(b.paths.size(), 1u);
  EXPECT_LT(b.to, 0);
  EXPECT_THROW(ParseAssertion(model, "qvel[*] < fast"), ValueError);
  EXPECT_THROW(ParseAssertion(model, "qvel[elbow] < 1"), PathError);
}

// Found by tests/hostile/hostile_models.py: a NaN the compiler let through was no finding.
TEST_F(AuditTest, ANaNParameterIsAStructureFailureNamingItsPath) {
  AuditReport r = AuditXml(testing::kNonFiniteXml);
  const CheckRow* f = Find(r, "structure.finite");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->status, CheckStatus::kFail);
  EXPECT_NE(f->About().find("dof_damping[hinge] = nan"), std::string::npos) << f->About();
  EXPECT_NE(f->About().find("geom_rgba[rod][1] = inf"), std::string::npos) << f->About();
  EXPECT_GT(r.Count(CheckStatus::kFail), 0);
  AuditReport clean = Audit(Model::Load(testing::kPendulum), {});
  ASSERT_NE(Find(clean, "structure.finite"), nullptr);
  EXPECT_EQ(Find(clean, "structure.finite")->status, CheckStatus::kPass);
}

TEST_F(AuditTest, StopsWhenItsCallerAsks) {
  Model model = Model::Load(testing::kPendulum);
  AuditOptions options;
  StopSource stop;
  stop.RequestStop();
  options.stop = stop.token();
  EXPECT_THROW(Audit(model, options), Interrupted);
}

// MuJoCo 3.12+: a pid takes two controls; the dcmotor beside it is judged the same whichever
// comes first (its step once went into the pid's second control: "no response")
TEST_F(AuditTest, APidBesideADcMotorDoesNotShiftItsControls) {
  if (!(mjVERSION_HEADER >= 3012000)) GTEST_SKIP() << "pid actuators came with MuJoCo 3.12";
  const char* xml = R"(<mujoco><worldbody>
      <body><joint name="a" axis="0 1 0" damping="0.1"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/>
        <body pos="0.3 0 0"><joint name="b" axis="0 1 0" damping="0.1"/>
          <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/></body></body></worldbody>
    <actuator>%s%s</actuator></mujoco>)";
  const char* pid = R"(<pid name="p" joint="a" kp="10" kv="1" ctrlrange="-1 1"/>)";
  const char* motor =
      R"(<dcmotor name="m" joint="b" motorconst="0.05" resistance="1" ctrlrange="-12 12"/>)";
  char text[2048];
  std::string verdicts[2], steps[2];
  for (int order = 0; order < 2; ++order) {
    std::snprintf(text, sizeof(text), xml, order ? motor : pid, order ? pid : motor);
    AuditReport r = AuditXml(text);
    const CheckRow* step = Find(r, "actuator.step_response", "'m'");
    ASSERT_NE(step, nullptr) << Failures(r);
    EXPECT_EQ(step->status, CheckStatus::kPass) << step->measured_text;
    steps[order] = step->measured_text;
    const CheckRow* limits = Find(r, "actuator.limits", "'m'");
    verdicts[order] = limits ? limits->measured_text : "bounded";
  }
  EXPECT_EQ(steps[0], steps[1]);
  EXPECT_NE(steps[0].find("force 0 -> "), std::string::npos) << steps[0];
  EXPECT_EQ(verdicts[0], verdicts[1]);
  EXPECT_EQ(verdicts[0].find("ctrl unlimited"), std::string::npos) << verdicts[0];
}

// A free box resting on a table that hangs on a joint (at its limit) is supported: the table's
// contacts count, not only those of bodies welded to the world
TEST_F(AuditTest, AnObjectOnJointedLinksIsSupported) {
  AuditReport r = AuditXml(R"(<mujoco><worldbody>
      <body name="table" pos="0 0 0.5"><joint name="lift" type="slide" axis="0 0 1"
          limited="true" range="-0.001 0.001" damping="10"/>
        <geom type="box" size="0.5 0.5 0.05" mass="5"/></body>
      <body name="box" pos="0 0 0.6"><freejoint/><geom type="box" size="0.05 0.05 0.05" mass="1"/></body>
    </worldbody></mujoco>)");
  const CheckRow* support = Find(r, "contact.support");
  ASSERT_NE(support, nullptr) << Failures(r);
  EXPECT_EQ(support->status, CheckStatus::kPass) << support->measured_text;
  EXPECT_NEAR(support->measured.value, 1, 0.05);
}

}  // namespace
}  // namespace plumb
