#include "core/file_kind.h"

#include <gtest/gtest.h>

#include "fixture.h"
#include "plumb/error.h"
#include "plumb/model.h"

namespace plumb {
using internal::FileKind;
using internal::SniffFileKind;

namespace {

using testing::TempDir;
using testing::WriteFile;

TEST(FileKindTest, NamesWhatAFileIs) {
  EXPECT_EQ(SniffFileKind(""), FileKind::kEmpty);
  EXPECT_EQ(SniffFileKind(" \n\t"), FileKind::kEmpty);
  EXPECT_EQ(SniffFileKind(std::string("\x7f"
                                      "ELF\x02\x01\x00\x00",
                                      8)),
            FileKind::kBinary);
  EXPECT_EQ(SniffFileKind("{\n  \"plumb_snapshot\": 1,\n}"), FileKind::kSnapshot);
  EXPECT_EQ(SniffFileKind("[1, 2]"), FileKind::kJson);
  EXPECT_EQ(SniffFileKind("<mujoco model=\"x\"/>"), FileKind::kMjcf);
  EXPECT_EQ(SniffFileKind("<?xml version=\"1.0\"?>\n<!-- a <robot> -->\n<mujoco/>"),
            FileKind::kMjcf);
  EXPECT_EQ(SniffFileKind("<robot name=\"r\"><!-- <mujoco> --></robot>"), FileKind::kXml);
  EXPECT_EQ(SniffFileKind("hello"), FileKind::kText);
}

// Loads `text` written to a file and returns the LoadError's message ("" if it loaded).
std::string LoadMessage(const std::string& name, const std::string& text) {
  TempDir dir;
  WriteFile(dir.File(name), text);
  try {
    Model::Load(dir.File(name));
  } catch (const LoadError& e) {
    return e.what();
  }
  return "";
}

TEST(FileKindTest, EmptyOrBinaryModelIsNamedNotParsed) {
  EXPECT_NE(LoadMessage("empty.xml", "").find("is empty (0 bytes)"), std::string::npos);
  std::string binary = LoadMessage("model.xml", std::string("\x00\x01\x02xml", 6));
  EXPECT_NE(binary.find("is a binary file, but neither an MJCF model (XML) nor a compiled model"),
            std::string::npos)
      << binary;
  EXPECT_NE(binary.find(".mjb"), std::string::npos) << binary;
  std::string snapshot = LoadMessage("a.json", "{\"plumb_snapshot\": 1}");
  EXPECT_NE(snapshot.find("is a plumb snapshot (JSON), not a model"), std::string::npos)
      << snapshot;
  EXPECT_NE(snapshot.find("plumb diff"), std::string::npos) << snapshot;
  EXPECT_EQ(LoadMessage("ok.xml", "<mujoco><worldbody/></mujoco>"), "");
}

// The content decides the format, not the name: MJCF named .mjb got "Model missing header ID",
// MuJoCo's binary-format message; a compiled model named .bin is loaded.
TEST(FileKindTest, TheContentDecidesBetweenMjcfAndACompiledModel) {
  EXPECT_EQ(LoadMessage("model.mjb", "<mujoco><worldbody><geom size='1'/></worldbody></mujoco>"),
            "");
  TempDir dir;
  Model model = Model::FromXmlString("<mujoco><worldbody><geom size='1'/></worldbody></mujoco>");
  model.SaveBinary(dir.File("model.bin"));
  EXPECT_EQ(Model::Load(dir.File("model.bin"))->ngeom, 1);
  // a damaged compiled model still gets the binary-format message
  std::string damaged = LoadMessage("broken.mjb", std::string("\x00\x01\x02mjb", 6));
  EXPECT_NE(damaged.find("cannot load binary model"), std::string::npos) << damaged;
}

}  // namespace
}  // namespace plumb
