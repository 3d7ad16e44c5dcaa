// plumb bridge --client as a user runs it: the bridge and a client (examples/pd_client, or a
// shell command that misbehaves) in one command, and the verdict it ends with.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "bridge/test_domain.h"
#include "fixture.h"

namespace plumb {
namespace {

// The chapter's pendulum as the bridge's robot: one motor on its hinge, 3 s of lockstep.
std::string PendulumConfig(std::uint32_t domain) {
  return "family = \"go\"\nmode = \"lockstep\"\ndomain = " + std::to_string(domain) +
         "\nmotors = [\"hinge\"]\nuntil = 3.0\n";
}

// `plumb bridge PENDULUM --config bridge.toml ARGS` in `dir`, with a bridge.toml of its own.
testing::CommandResult Rehearse(const testing::TempDir& dir, const std::string& args) {
  std::uint32_t domain = testing::FreeDomain();
  testing::WriteFile(dir.File("bridge.toml"), PendulumConfig(domain));
  return testing::RunPlumb("bridge '" + testing::kPendulum + "' --config bridge.toml " + args,
                           dir.path());
}

// The pd_client holding the pendulum at 0.5 rad until it is stopped.
std::string Holder() {
  return "--client \"'" + std::string(PLUMB_PD_CLIENT) +
         "' pendulum --domain {domain} --seconds 1000\"";
}

TEST(CliRehearseTest, AClientThatHoldsThePendulumPassesItsAssertions) {
  testing::TempDir dir;
  auto r = Rehearse(dir, Holder() +
                             " --assert 'final(qpos[hinge]) > 0.45' --assert "
                             "'max(tracking_error[hinge]) < 1 during [1, 3]' --all");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("final(qpos[hinge]) > 0.45"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("client.process"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("commands applied"), std::string::npos) << r.out;  // the bridge's line
}

TEST(CliRehearseTest, TheVerdictAsJsonSaysHowTheClientEnded) {
  testing::TempDir dir;
  auto r = Rehearse(dir, Holder() + " --assert 'final(qpos[hinge]) > 0.45' --format json");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["passed"], true);
  EXPECT_EQ(j["client"]["kind"], "stopped") << r.out;
  EXPECT_GT(j["view"]["commands"].get<long>(), 1000);
  EXPECT_NEAR(j["bridge"]["time"].get<double>(), 3.0, 1e-9);
}

TEST(CliRehearseTest, AnAssertionThatDoesNotHoldFailsTheRehearsal) {
  testing::TempDir dir;
  auto r = Rehearse(dir, Holder() + " --assert 'final(qpos[hinge]) > 1'");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("FAIL"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("final(qpos[hinge])"), std::string::npos) << r.out;
}

TEST(CliRehearseTest, AClientThatDiesEarlyFailsWithItsLastLines) {
  testing::TempDir dir;
  auto r = Rehearse(dir, "--client 'echo loading the policy; echo no such file >&2; exit 3'");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("exited with status 3"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("no such file"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("loading the policy"), std::string::npos) << r.out;
}

TEST(CliRehearseTest, AClientThatNeverCommandsFailsAfterItsTimeout) {
  testing::TempDir dir;
  auto r = Rehearse(dir, "--client 'sleep 30' --first-command-timeout 0.5 --grace 0.5");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("client.commands"), std::string::npos) << r.out;
}

TEST(CliRehearseTest, AClientThatIgnoresSigintIsKilledAfterItsGrace) {
  testing::TempDir dir;
  auto r = Rehearse(dir, "--client \"trap '' INT; exec '" + std::string(PLUMB_PD_CLIENT) +
                             "' pendulum --domain {domain} --seconds 1000\" --grace 0.3 "
                             "--format json");
  // pd_client keeps SIGINT ignored across exec: it has to be killed
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["client"]["kind"], "killed") << r.out;
}

TEST(CliRehearseTest, BadInputIsExit2NamingIt) {
  testing::TempDir dir;
  auto unknown = Rehearse(dir, Holder() + " --assert 'max(tracking_error[knee]) < 1'");
  EXPECT_EQ(unknown.exit_code, 2) << unknown.err;
  EXPECT_NE(unknown.err.find("hinge"), std::string::npos) << unknown.err;  // the motors
  auto lost = Rehearse(dir, Holder() + " --client-cwd no/such/folder");
  EXPECT_EQ(lost.exit_code, 2) << lost.err;
  EXPECT_NE(lost.err.find("no/such/folder"), std::string::npos) << lost.err;
  auto no_client = Rehearse(dir, "--assert 'final(qpos[hinge]) > 0'");
  EXPECT_EQ(no_client.exit_code, 2) << no_client.err;
  EXPECT_NE(no_client.err.find("--client"), std::string::npos) << no_client.err;
}

}  // namespace
}  // namespace plumb
