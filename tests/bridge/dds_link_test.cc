// Loopback DDS: a LowCmd_ written is taken whole, CRC and all, on a domain of its own.

#include "bridge/dds_link.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstring>

#include "bridge/test_domain.h"
#include "bridge/unitree_crc.h"
#include "plumb/error.h"

namespace plumb::bridge {
namespace {

// A domain id of this test process's own (tests run in parallel).

TEST(DdsLinkTest, ALowCmdCrossesLoopbackWhole) {
  DdsDomain domain(::plumb::testing::FreeDomain());
  DdsWriter<unitree_go_msg_dds__LowCmd_> writer(domain, "rt/lowcmd",
                                                &unitree_go_msg_dds__LowCmd__desc);
  DdsReader<unitree_go_msg_dds__LowCmd_> reader(domain, "rt/lowcmd",
                                                &unitree_go_msg_dds__LowCmd__desc);
  auto start = std::chrono::steady_clock::now();
  while (writer.Matched() == 0 &&
         std::chrono::steady_clock::now() - start < std::chrono::seconds(5)) {
    dds_sleepfor(DDS_MSECS(10));
  }
  ASSERT_EQ(writer.Matched(), 1);
  unitree_go_msg_dds__LowCmd_ sent;
  std::memset(&sent, 0, sizeof sent);
  sent.head[0] = 0xFE;
  sent.motor_cmd[3].mode = 1;
  sent.motor_cmd[3].q = 0.5f;
  sent.motor_cmd[3].kp = 50;
  sent.crc = UnitreeCrc(sent);
  writer.Write(sent);
  ASSERT_TRUE(reader.Wait(DDS_SECS(5)));
  unitree_go_msg_dds__LowCmd_ got;
  ASSERT_TRUE(reader.Take(&got));
  EXPECT_EQ(got.motor_cmd[3].q, 0.5f);
  EXPECT_EQ(got.crc, sent.crc);
  EXPECT_EQ(UnitreeCrc(got), got.crc);
  EXPECT_FALSE(reader.Take(&got));
}

TEST(DdsLinkTest, ABadDomainIdSaysWhyAndASecondHandleJoins) {
  EXPECT_THROW(DdsDomain(500), ValueError);
  std::uint32_t id = ::plumb::testing::FreeDomain();
  DdsDomain first(id);
  DdsDomain second(id);  // joins the first: two participants, one domain
  EXPECT_NE(first.participant(), second.participant());
  DdsWriter<unitree_go_msg_dds__LowCmd_> writer(first, "rt/lowcmd",
                                                &unitree_go_msg_dds__LowCmd__desc);
  DdsReader<unitree_go_msg_dds__LowCmd_> reader(second, "rt/lowcmd",
                                                &unitree_go_msg_dds__LowCmd__desc);
  auto start = std::chrono::steady_clock::now();
  while (writer.Matched() == 0 &&
         std::chrono::steady_clock::now() - start < std::chrono::seconds(5)) {
    dds_sleepfor(DDS_MSECS(10));
  }
  EXPECT_EQ(writer.Matched(), 1);
}

}  // namespace
}  // namespace plumb::bridge
