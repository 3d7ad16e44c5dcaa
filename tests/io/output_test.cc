#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <thread>

#include "core/strings.h"
#include "fixture.h"
#include "io/atomic_file.h"
#include "io/output_path.h"
#include "plumb/error.h"
#include "plumb/repro.h"
#include "plumb/sample_writer.h"

namespace plumb {
using internal::AtomicFile;
using internal::NamedPath;
using internal::RefuseOutputsOntoInputs;
using internal::SameFile;
using internal::ShellQuote;

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

// Reads everything from the FIFO `path` on a thread, as `cat path` would.
class FifoReader {
 public:
  explicit FifoReader(const std::string& path, bool close_at_once = false)
      : thread_([this, path, close_at_once] {
          std::FILE* in = std::fopen(path.c_str(), "r");
          if (!in) return;
          char buffer[4096];
          std::size_t n;
          while (!close_at_once && (n = std::fread(buffer, 1, sizeof(buffer), in)) > 0) {
            text_.append(buffer, n);
          }
          std::fclose(in);
        }) {}
  // Waits for the writer to close and returns what was read.
  std::string Text() {
    thread_.join();
    return text_;
  }
  ~FifoReader() {
    if (thread_.joinable()) thread_.join();
  }

 private:
  std::string text_;
  std::thread thread_;
};

TEST(AtomicFileTest, FifoIsWrittenThroughNotReplaced) {
  TempDir dir;
  std::string fifo = dir.File("pipe");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  FifoReader reader(fifo);
  {
    AtomicFile file(fifo);
    EXPECT_TRUE(file.direct());
    std::fputs("through the pipe\n", file.stream());
    file.Commit();
  }
  EXPECT_EQ(reader.Text(), "through the pipe\n");
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo))) << "the FIFO was replaced";
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1)
      << "a temporary file was left behind";
}

TEST(AtomicFileTest, WriteErrorOnDirectOutputIsReported) {
  // a reader that closes at once: writing more than a pipe holds fails with EPIPE, as a
  // full device fails with ENOSPC
  TempDir dir;
  std::string fifo = dir.File("pipe");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  struct sigaction ignore = {}, old = {};
  ignore.sa_handler = SIG_IGN;
  sigaction(SIGPIPE, &ignore, &old);
  FifoReader reader(fifo, /*close_at_once=*/true);
  AtomicFile file(fifo);
  reader.Text();
  std::string block(1 << 20, 'x');
  std::fwrite(block.data(), 1, block.size(), file.stream());
  try {
    file.Commit();
    ADD_FAILURE() << "a write error was not reported";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("Broken pipe"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(fifo), std::string::npos) << e.what();
  }
  sigaction(SIGPIPE, &old, nullptr);
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
}

TEST(AtomicFileTest, SymlinkStaysALinkAndItsTargetIsReplaced) {
  TempDir dir;
  fs::create_directory(dir.File("data"));
  testing::WriteFile(dir.File("data/real.csv"), "old");
  fs::permissions(dir.File("data/real.csv"), fs::perms(0640));
  fs::create_symlink("data/real.csv", dir.File("out.csv"));
  AtomicFile file(dir.File("out.csv"));
  EXPECT_FALSE(file.direct());
  std::fputs("new", file.stream());
  EXPECT_EQ(ReadFile(dir.File("out.csv")), "old");  // untouched until commit
  file.Commit();
  EXPECT_TRUE(fs::is_symlink(dir.File("out.csv"))) << "the link was replaced";
  EXPECT_EQ(fs::read_symlink(dir.File("out.csv")), "data/real.csv");
  EXPECT_EQ(ReadFile(dir.File("data/real.csv")), "new");
  EXPECT_EQ(fs::status(dir.File("data/real.csv")).permissions(), fs::perms(0640))
      << "the target lost its permissions";
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.File("data")), fs::directory_iterator()), 1);
}

TEST(AtomicFileTest, DanglingSymlinkCreatesItsTarget) {
  TempDir dir;
  fs::create_symlink("first", dir.File("out.csv"));
  fs::create_symlink(dir.File("second.csv"), dir.File("first"));  // a chain of two links
  {
    AtomicFile file(dir.File("out.csv"));
    std::fputs("made", file.stream());
    file.Commit();
  }
  EXPECT_TRUE(fs::is_symlink(dir.File("out.csv")));
  EXPECT_TRUE(fs::is_symlink(dir.File("first")));
  EXPECT_EQ(ReadFile(dir.File("second.csv")), "made");
}

TEST(AtomicFileTest, SymlinkLoopIsAnIoError) {
  TempDir dir;
  fs::create_symlink("b", dir.File("a"));
  fs::create_symlink("a", dir.File("b"));
  EXPECT_THROW(AtomicFile{dir.File("a")}, IoError);
}

TEST(AtomicFileTest, SocketIsRefused) {
  TempDir dir;
  std::string path = dir.File("sock");
  int fd = socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un address = {};
  address.sun_family = AF_UNIX;
  ASSERT_LT(path.size(), sizeof(address.sun_path));
  std::strcpy(address.sun_path, path.c_str());
  ASSERT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
  try {
    AtomicFile file(path);
    ADD_FAILURE() << "a socket was accepted";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("it is a socket"), std::string::npos) << e.what();
  }
  close(fd);
  EXPECT_TRUE(fs::is_socket(fs::symlink_status(path))) << "the socket was replaced";
}

TEST(AtomicFileTest, ProcLinkIsWrittenThroughLikeDevStdout) {
  // /dev/stdout is a link to /proc/self/fd/1, which names an open file, not a path
  TempDir dir;
  int fd = ::open(dir.File("opened.csv").c_str(), O_WRONLY | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  fs::create_symlink("/proc/self/fd/" + std::to_string(fd), dir.File("stdout"));
  {
    AtomicFile file(dir.File("stdout"));
    EXPECT_TRUE(file.direct());
    std::fputs("through", file.stream());
    file.Commit();
  }
  ::close(fd);
  EXPECT_TRUE(fs::is_symlink(dir.File("stdout")));
  EXPECT_EQ(ReadFile(dir.File("opened.csv")), "through");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 2);
}

TEST(AtomicFileTest, DashIsStandardOutput) {
  AtomicFile file("-");
  EXPECT_EQ(file.stream(), stdout);
  EXPECT_TRUE(file.direct());
  file.Commit();
  EXPECT_NE(std::fputs("", stdout), EOF) << "standard output was closed";
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

// qvel = -2e6 ran two columns together and 1e308 printed 300 digits: a number that does not
// fit its column with a space before it is printed in exponent form.
TEST(TableWriterTest, HugeNumbersKeepTheirColumns) {
  Model model = Model::Load(kPendulum);
  std::vector<Path> columns = DefaultColumns(model);  // time, qpos[hinge], qvel[hinge]
  std::FILE* out = std::tmpfile();
  std::unique_ptr<SampleSink> writer = MakeSampleWriter(SampleFormat::kTable, out);
  writer->Begin(columns);
  writer->Sample({0.002, 1e308, -2e6});
  writer->Sample({0.004, -123456.789, 0.5});
  writer->Sample({0.006, NAN, INFINITY});
  writer->End();
  std::rewind(out);
  char buffer[4096];
  std::string text(buffer, std::fread(buffer, 1, sizeof(buffer), out));
  std::fclose(out);
  std::vector<std::string> lines = testing::Lines(text);
  ASSERT_EQ(lines.size(), 4u) << text;
  for (const std::string& line : lines) EXPECT_EQ(line.size(), lines[0].size()) << text;
  EXPECT_EQ(lines[1], "     0.00200  1.0000e+308  -2.0000e+06");
  EXPECT_EQ(lines[2], "     0.00400  -1.2346e+05      0.50000");
  EXPECT_EQ(lines[3], "     0.00600          nan          inf");
}

TEST_F(WriterTest, CsvHasExactHeaderAndRoundTrips) {
  std::istringstream csv(Write(SampleFormat::kCsv));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "time,qpos[hinge],qvel[hinge]");
  std::getline(csv, line);
  EXPECT_EQ(line, "0,0.7,0");  // the shortest text that reads back as the value set
  int rows = 1;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 6);
}

// Writes one CSV row of `values` and returns its text (without the newline).
std::string CsvRow(const std::vector<double>& values) {
  std::FILE* out = std::tmpfile();
  std::unique_ptr<SampleSink> writer = MakeSampleWriter(SampleFormat::kCsv, out);
  std::vector<Path> columns(values.size());
  writer->Begin(columns);
  writer->Sample(values);
  writer->End();
  std::rewind(out);
  char buffer[4096] = {};
  std::fread(buffer, 1, sizeof(buffer) - 1, out);
  std::fclose(out);
  std::string text = buffer;
  text = text.substr(text.find('\n') + 1);  // past the header
  return text.substr(0, text.find('\n'));
}

TEST(CsvNumberTest, ShortestTextThatRoundTrips) {
  EXPECT_EQ(CsvRow({0.3, 0.1 + 0.2, 1e-300, -2.5, 100, 1e21}),
            "0.3,0.30000000000000004,1e-300,-2.5,100,1e+21");
  // random doubles of every magnitude read back exactly
  std::mt19937_64 random(9);
  std::uniform_real_distribution<double> mantissa(-1, 1);
  std::uniform_int_distribution<int> exponent(-300, 300);
  for (int i = 0; i < 2000; ++i) {
    double v = std::ldexp(mantissa(random), exponent(random));
    if (i % 2) v = static_cast<double>(random()) / 3.0;  // large integers and thirds
    std::string text = CsvRow({v});
    EXPECT_EQ(std::strtod(text.c_str(), nullptr), v) << text;
    EXPECT_LE(text.size(), 24u) << text;
  }
}

TEST(CsvNumberTest, OneFormatterForEveryCommand) {
  // run, sweep, rollout and results each had their own number and field formatting
  EXPECT_EQ(CsvNumber(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(CsvNumber(0.3), "0.3");
  EXPECT_EQ(CsvNumber(NAN), "");  // not measured
  std::string line = "x";
  AppendCsvNumber(&line, -2.5);
  EXPECT_EQ(line, "x-2.5");
  EXPECT_EQ(CsvField("qpos[hinge]"), "qpos[hinge]");
  EXPECT_EQ(CsvField("geom_friction[a,b]"), "\"geom_friction[a,b]\"");
  EXPECT_EQ(CsvField("say \"hi\""), "\"say \"\"hi\"\"\"");
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
  result.divergence->last_good = Snapshot(model, data, 4);
  result.divergence->bad = Snapshot(model, data, 5);
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

TEST(OutputPathTest, SameFileUnderEveryName) {
  TempDir dir;
  testing::WriteFile(dir.File("in.xml"), "<mujoco/>");
  fs::create_symlink("in.xml", dir.File("link.xml"));
  fs::create_hard_link(dir.File("in.xml"), dir.File("hard.xml"));
  testing::WriteFile(dir.File("copy.xml"), "<mujoco/>");
  fs::create_directory(dir.File("sub"));
  const std::string in = dir.File("in.xml");
  EXPECT_TRUE(SameFile(in, in));
  EXPECT_TRUE(SameFile(in, dir.File("./in.xml")));
  EXPECT_TRUE(SameFile(in, dir.File("sub/../in.xml")));
  EXPECT_TRUE(SameFile(in, dir.File("link.xml")));
  EXPECT_TRUE(SameFile(in, dir.File("hard.xml")));
  EXPECT_FALSE(SameFile(in, dir.File("copy.xml")));  // the same bytes are not the same file
  EXPECT_FALSE(SameFile(in, dir.File("new.xml")));   // not there yet
  EXPECT_FALSE(SameFile(dir.File("new.xml"), dir.File("new.xml")));
  EXPECT_FALSE(SameFile(in, ""));
}

TEST(OutputPathTest, AnOutputOntoAnInputIsRefusedNamingBoth) {
  TempDir dir;
  testing::WriteFile(dir.File("in.xml"), "<mujoco/>");
  fs::create_symlink("in.xml", dir.File("link.xml"));
  const std::vector<NamedPath> inputs = {{"the pose file", ""}, {"the model", dir.File("in.xml")}};
  try {
    RefuseOutputsOntoInputs({{"out", dir.File("new.csv")}, {"output", dir.File("link.xml")}},
                            inputs);
    ADD_FAILURE() << "not refused";
  } catch (const ArgumentError& e) {
    EXPECT_EQ(e.argument(), "output");
    EXPECT_EQ(e.value(), "'" + dir.File("link.xml") + "'");
    EXPECT_EQ(e.problem(), "the model '" + dir.File("in.xml") +
                               "' is the same file (under another name), and the output would "
                               "destroy its input; write it elsewhere.");
  }
  try {
    RefuseOutputsOntoInputs({{"output", dir.File("./in.xml")}}, inputs);
    ADD_FAILURE() << "not refused";
  } catch (const ArgumentError& e) {
    EXPECT_EQ(e.problem().find("the same file (under"), std::string::npos) << e.what();
  }
  // a folder output (a repro folder) that is an input folder
  fs::create_directory(dir.File("d"));
  EXPECT_THROW(RefuseOutputsOntoInputs({{"repro", dir.File("d")}}, {{"the data", dir.File("d/.")}}),
               ArgumentError);
}

TEST(OutputPathTest, OutputsThatReplaceNoInputAreAccepted) {
  TempDir dir;
  testing::WriteFile(dir.File("in.xml"), "<mujoco/>");
  testing::WriteFile(dir.File("copy.xml"), "<mujoco/>");
  ASSERT_EQ(mkfifo(dir.File("pipe").c_str(), 0600), 0);
  const std::vector<NamedPath> inputs = {{"the model", dir.File("in.xml")},
                                         {"the pose file", dir.File("pipe")},
                                         {"the tty", "/dev/null"}};
  EXPECT_NO_THROW(RefuseOutputsOntoInputs({{"output", dir.File("copy.xml")},
                                           {"output", dir.File("new.xml")},
                                           {"output", ""},
                                           {"output", "-"},
                                           // written directly, never replaced
                                           {"output", dir.File("pipe")},
                                           {"output", "/dev/null"}},
                                          inputs));
  EXPECT_EQ(ReadFile(dir.File("in.xml")), "<mujoco/>");
}

}  // namespace
}  // namespace plumb
