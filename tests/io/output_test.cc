#include "plumb/output.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fixture.h"
#include "plumb/error.h"

namespace plumb {
namespace {

namespace fs = std::filesystem;
using testing::kPendulum;
using testing::ReadFile;
using testing::TempDir;

TEST(AtomicFileTest, NothingAppearsWithoutCommit) {
  TempDir dir;
  {
    AtomicFile file(dir.File("out.csv"));
    std::fputs("half", file.stream());
  }
  EXPECT_FALSE(fs::exists(dir.File("out.csv")));
  EXPECT_TRUE(fs::is_empty(dir.path())) << "the temporary file was left behind";
}

TEST(AtomicFileTest, CommitRenamesIntoPlace) {
  TempDir dir;
  testing::WriteFile(dir.File("out.csv"), "old contents");
  AtomicFile file(dir.File("out.csv"));
  std::fputs("new", file.stream());
  EXPECT_EQ(ReadFile(dir.File("out.csv")), "old contents");  // untouched until commit
  file.Commit();
  EXPECT_EQ(ReadFile(dir.File("out.csv")), "new");
}

TEST(AtomicFileTest, UnwritablePathsAreIoErrors) {
  EXPECT_THROW(AtomicFile("/nonexistent-dir/out.csv"), IoError);
  TempDir dir;
  EXPECT_THROW(AtomicFile{dir.path()}, IoError);  // a directory
}

class WriterTest : public testing::MujocoTest {
 protected:
  // Runs the pendulum from 0.7 rad to 0.5 s and returns what `format` wrote.
  std::string Write(SampleFormat format) {
    Model model = Model::Load(kPendulum);
    Data data(model);
    ApplyAssignments(model, data, {ParseAssignment(model, "qpos[hinge]=0.7")});
    RunSpec spec;
    spec.until = 0.5;
    spec.every = 0.1;
    spec.columns = DefaultColumns(model);
    std::FILE* out = std::tmpfile();
    std::unique_ptr<SampleSink> writer = MakeSampleWriter(format, out);
    plumb::Run(model, data, spec, *writer);
    std::rewind(out);
    std::string text;
    char buffer[4096];
    std::size_t n;
    while ((n = std::fread(buffer, 1, sizeof(buffer), out)) > 0) text.append(buffer, n);
    std::fclose(out);
    return text;
  }
};

TEST_F(WriterTest, TableShowsTheChaptersDigits) {
  std::string table = Write(SampleFormat::kTable);
  EXPECT_NE(table.find("0.65403"), std::string::npos) << table;
  EXPECT_NE(table.find("-0.89118"), std::string::npos) << table;
  EXPECT_NE(table.find("-0.16156"), std::string::npos) << table;
  EXPECT_NE(table.find("-2.40852"), std::string::npos) << table;
}

TEST_F(WriterTest, CsvHasExactHeaderAndRoundTrips) {
  std::istringstream csv(Write(SampleFormat::kCsv));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "time,qpos[hinge],qvel[hinge]");
  std::getline(csv, line);
  EXPECT_EQ(line, "0,0.69999999999999996,0");
  int rows = 1;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 6);
}

TEST_F(WriterTest, JsonLinesParse) {
  std::istringstream jsonl(Write(SampleFormat::kJsonl));
  std::string line;
  std::vector<nlohmann::json> rows;
  while (std::getline(jsonl, line)) rows.push_back(nlohmann::json::parse(line));
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_NEAR(rows[5]["qpos[hinge]"].get<double>(), -0.16156, 5e-6);
  EXPECT_EQ(rows[5]["time"].get<double>(), 250 * 0.002);
}

TEST(ShellQuoteTest, QuotesOnlyWhenNeeded) {
  EXPECT_EQ(ShellQuote("models/pendulum.xml"), "models/pendulum.xml");
  EXPECT_EQ(ShellQuote("qpos[hinge]=0.7"), "'qpos[hinge]=0.7'");
  EXPECT_EQ(ShellQuote("it's"), "'it'\\''s'");
}

TEST(ReproTest, FolderHoldsEverythingToReproduce) {
  TempDir dir;
  Model model = Model::Load(kPendulum);
  Data data(model);
  RunResult result;
  result.diverged = true;
  result.divergence = Divergence();
  result.divergence->reason = "the simulation diverged at t = 1 s";
  result.divergence->last_good = Snapshot(model.get(), data.get(), 4);
  result.divergence->bad = Snapshot(model.get(), data.get(), 5);
  result.divergence->bad.qpos[0] = NAN;
  std::string written = WriteRepro(
      model, result, {"plumb", "run", "m.xml", "--set", "qpos[hinge]=1"}, dir.File("repro"));
  EXPECT_EQ(written, dir.File("repro"));
  for (const char* name : {"model.xml", "model.mjb", "last_good.json", "bad.json", "warnings.json",
                           "command.txt", "README.txt"}) {
    EXPECT_TRUE(fs::exists(written + "/" + name)) << name;
  }
  EXPECT_NE(ReadFile(written + "/command.txt").find("plumb run m.xml --set 'qpos[hinge]=1'"),
            std::string::npos);
  nlohmann::json bad = nlohmann::json::parse(ReadFile(written + "/bad.json"));
  EXPECT_EQ(bad["step"], 5);
  EXPECT_TRUE(bad["qpos"][0].is_null());  // NaN has no JSON spelling
  // the saved model loads again
  EXPECT_EQ(Model::Load(written + "/model.xml")->nq, 1);
  // a second repro does not overwrite the first
  EXPECT_EQ(WriteRepro(model, result, {"plumb"}, dir.File("repro")), dir.File("repro") + "-2");
}

}  // namespace
}  // namespace plumb
