// The results store and merge at API level: rows in and out, resume, shards merged into one
// run, and the merges that must fail (disagreeing shards, a "complete" run with holes).

#include "plumb/store.h"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <future>
#include <thread>
#include <vector>

#include "fixture.h"
#include "io/hash.h"
#include "plumb/error.h"

namespace plumb {
using internal::HashFile;
using internal::HashModel;

namespace {

using testing::TempDir;

RolloutResult Result(long index, double metric) {
  RolloutResult r;
  r.index = index;
  r.params = {0.5 * index};
  r.metrics = {metric, NAN};
  return r;
}

RunInfo Info(long count) {
  RunInfo info;
  info.kind = "rollout";
  info.config = "seed 1; count " + std::to_string(count);
  info.command = "plumb rollout ...";
  info.parameters = {"dof_damping[hinge]"};
  info.metrics = {"qpos[hinge]@1", "period(qpos[hinge])"};
  info.count = count;
  return info;
}

// Writes a store at `path` with the results of `indices` for a run of `count`.
void WriteStore(const std::string& path, long count, const std::vector<long>& indices, bool finish,
                double offset = 0) {
  ResultsStore store(path);
  long run = store.BeginRun(Info(count));
  for (long i : indices) store.Add(run, Result(i, i + offset));
  store.Commit();
  if (finish) store.FinishRun(run);
}

TEST(StoreTest, HashesAreFnv1a64) {
  TempDir dir;
  testing::WriteFile(dir.File("empty"), "");
  testing::WriteFile(dir.File("a"), "a");
  EXPECT_EQ(HashFile(dir.File("empty")), "cbf29ce484222325");
  EXPECT_EQ(HashFile(dir.File("a")), "af63dc4c8601ec8c");
  Model model = Model::Load(testing::kPendulum);
  EXPECT_EQ(HashModel(model), HashModel(Model::Load(testing::kPendulum)));
  EXPECT_EQ(HashModel(model).size(), 16u);
}

TEST(StoreTest, RowsComeBackInIndexOrderWithNaNsAndResumeSeesThem) {
  TempDir dir;
  std::string path = dir.File("r.sqlite");
  WriteStore(path, 5, {3, 0, 1}, false);
  ResultsStore store(path, ResultsStore::Mode::kReadOnly);
  std::vector<RunInfo> runs = store.Runs();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_TRUE(runs[0].finished.empty());
  EXPECT_EQ(runs[0].metrics, Info(5).metrics);
  EXPECT_EQ(store.DoneIndices(runs[0].id), (std::vector<long>{0, 1, 3}));
  EXPECT_EQ(store.CountDone(runs[0].id), 3);
  std::vector<RolloutResult> rows = store.Results(runs[0].id);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[2].index, 3);
  EXPECT_EQ(rows[2].params, (std::vector<double>{1.5}));
  EXPECT_EQ(rows[2].metrics[0], 3);
  EXPECT_TRUE(std::isnan(rows[2].metrics[1]));
  ASSERT_TRUE(store.FindRun(Info(5).config).has_value());
  EXPECT_FALSE(store.FindRun("another config").has_value());
}

// Two writers of one store look for the same run at once, the second while the first has
// looked and not yet begun it: in a Transaction they begin it once. Looking and beginning
// outside one, both found nothing and each began a run of the same config.
TEST(StoreTest, TwoWritersLookingForARunAtOnceBeginItOnce) {
  TempDir dir;
  std::string path = dir.File("r.sqlite");
  ResultsStore first(path), second(path);
  std::promise<void> looked;
  auto claim = [&](ResultsStore& store, bool is_first) {
    long id = 0;
    store.Transaction([&] {
      std::optional<RunInfo> found = store.FindRun(Info(3).config);
      if (is_first) {
        looked.set_value();
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
      }
      id = found ? found->id : store.BeginRun(Info(3));
    });
    return id;
  };
  long second_id = 0;
  std::thread other([&] {
    looked.get_future().wait();
    second_id = claim(second, false);
  });
  long first_id = claim(first, true);
  other.join();
  EXPECT_EQ(first_id, second_id);
  EXPECT_EQ(first.Runs().size(), 1u);
}

// Several writers opening one new store at once: each switches it to SQLite's write-ahead log,
// and SQLite answers the switches that collide with SQLITE_BUSY at once, without its busy
// handler (each holds a read lock and waiting could deadlock). That made one of four plumbs
// started together on one new --db fail with "database is locked" (seen in CI, about one
// round in twelve); the store now retries the switch as every other write waits.
TEST(StoreTest, WritersOpeningOneNewStoreTogetherAllOpenIt) {
  TempDir dir;
  constexpr int kRounds = 100, kWriters = 4;
  int failed = 0;
  std::string why;
  for (int round = 0; round < kRounds; ++round) {
    std::string path = dir.File("new" + std::to_string(round) + ".sqlite");
    std::promise<void> go;
    std::shared_future<void> start = go.get_future().share();
    std::vector<std::future<std::string>> writers;
    for (int i = 0; i < kWriters; ++i) {
      writers.push_back(std::async(std::launch::async, [&path, start] {
        start.wait();
        try {
          ResultsStore store(path);
          store.Transaction([] {});
          return std::string();
        } catch (const IoError& e) {
          return std::string(e.what());
        }
      }));
    }
    go.set_value();
    for (auto& w : writers) {
      std::string error = w.get();
      if (!error.empty()) ++failed, why = error;
    }
  }
  EXPECT_EQ(failed, 0) << "of " << kRounds * kWriters << " opens; the last: " << why;
}

TEST(StoreTest, ShardsMergeIntoOneFinishedRun) {
  TempDir dir;
  WriteStore(dir.File("a.sqlite"), 4, {0, 2}, false);
  WriteStore(dir.File("b.sqlite"), 4, {1, 3}, false);
  MergeStores({dir.File("a.sqlite"), dir.File("b.sqlite")}, dir.File("all.sqlite"));
  ResultsStore all(dir.File("all.sqlite"), ResultsStore::Mode::kReadOnly);
  std::vector<RunInfo> runs = all.Runs();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_FALSE(runs[0].finished.empty());
  EXPECT_EQ(all.DoneIndices(runs[0].id), (std::vector<long>{0, 1, 2, 3}));
  // a partial merge (one shard so far) is an unfinished run that --resume completes
  MergeStores({dir.File("a.sqlite")}, dir.File("part.sqlite"));
  ResultsStore part(dir.File("part.sqlite"), ResultsStore::Mode::kReadOnly);
  EXPECT_TRUE(part.Runs()[0].finished.empty());
}

TEST(StoreTest, MergesThatWouldLieFailAndLeaveNothing) {
  TempDir dir;
  WriteStore(dir.File("a.sqlite"), 4, {0, 1}, false);
  WriteStore(dir.File("other.sqlite"), 4, {1, 2}, false, /*offset=*/0.5);
  EXPECT_THROW(MergeStores({dir.File("a.sqlite"), dir.File("other.sqlite")}, dir.File("x.sqlite")),
               ValueError);
  EXPECT_FALSE(std::filesystem::exists(dir.File("x.sqlite")));
  // a run its store calls complete, with holes: refused, naming what is missing
  WriteStore(dir.File("holes.sqlite"), 4, {0, 3}, /*finish=*/true);
  try {
    MergeStores({dir.File("holes.sqlite")}, dir.File("y.sqlite"));
    ADD_FAILURE() << "merged a run with holes";
  } catch (const ValueError& e) {
    EXPECT_NE(std::string(e.what()).find("missing: 1, 2"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir.File("y.sqlite")));
  EXPECT_THROW(MergeStores({dir.File("a.sqlite")}, dir.File("a.sqlite")), IoError);
}

// Found by fuzz_store: a row edited by hand (text where plumb writes a JSON array of numbers
// or of names) threw the JSON library's exception, which nothing above the store catches.
TEST(StoreTest, EditedRowsAreAnErrorNamingTheStoreRowAndColumnNotACrash) {
  struct Edit {
    const char* sql;
    const char* column;
  };
  for (const Edit& edit : {Edit{"UPDATE results SET metrics = 'oops'", "case 0 column 'metrics'"},
                           Edit{"UPDATE cases SET params = '[\"x\"]'", "case 0 column 'params'"},
                           Edit{"UPDATE runs SET parameters = '[1]'", "column 'parameters'"},
                           Edit{"UPDATE runs SET metrics = '{}'", "column 'metrics'"}}) {
    TempDir dir;
    std::string path = dir.File("r.sqlite");
    WriteStore(path, 2, {0, 1}, false);
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, edit.sql, nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
    try {
      ResultsStore store(path, ResultsStore::Mode::kReadOnly);
      for (const RunInfo& run : store.Runs()) store.Results(run.id);
      ADD_FAILURE() << "read an edited store: " << edit.sql;
    } catch (const IoError& e) {
      std::string message = e.what();
      EXPECT_NE(message.find(path), std::string::npos) << message;
      EXPECT_NE(message.find(edit.column), std::string::npos) << message;
    }
    EXPECT_THROW(MergeStores({path}, dir.File("merged.sqlite")), IoError);
    EXPECT_FALSE(std::filesystem::exists(dir.File("merged.sqlite")));
  }
}

// The store's format is its SQLite user_version: stores from before it (0) are read and
// written; one a newer plumb wrote (a later format) is refused naming both formats, and left
// as it was.
TEST(StoreTest, AStoreOfALaterFormatIsRefusedNamingItsFormat) {
  TempDir dir;
  std::string path = dir.File("r.sqlite");
  WriteStore(path, 2, {0, 1}, true);
  auto set_format = [&](int format) {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    std::string sql = "PRAGMA user_version = " + std::to_string(format);
    ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
  };
  set_format(0);  // as before the format was written
  EXPECT_EQ(ResultsStore(path, ResultsStore::Mode::kReadOnly).Runs().size(), 1u);
  {
    ResultsStore store(path);  // writing brings it to the current format
    EXPECT_EQ(store.Runs().size(), 1u);
  }
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    sqlite3_stmt* statement = nullptr;
    sqlite3_prepare_v2(db, "PRAGMA user_version", -1, &statement, nullptr);
    ASSERT_EQ(sqlite3_step(statement), SQLITE_ROW);
    EXPECT_EQ(sqlite3_column_int(statement, 0), kStoreFormat);
    sqlite3_finalize(statement);
    sqlite3_close(db);
  }
  set_format(kStoreFormat + 1);
  std::string before = testing::ReadFile(path);
  for (auto mode : {ResultsStore::Mode::kReadOnly, ResultsStore::Mode::kReadWrite}) {
    try {
      ResultsStore store(path, mode);
      ADD_FAILURE() << "opened a store of a later format";
    } catch (const IoError& e) {
      std::string message = e.what();
      EXPECT_NE(message.find(path), std::string::npos) << message;
      EXPECT_NE(
          message.find("format " + std::to_string(kStoreFormat + 1) + ", written by a newer plumb"),
          std::string::npos)
          << message;
      EXPECT_NE(message.find("reads formats up to " + std::to_string(kStoreFormat)),
                std::string::npos)
          << message;
    }
  }
  EXPECT_EQ(testing::ReadFile(path), before);
}

// The IoError message of opening a store at `path`, or "" when it opens.
std::string OpenError(const std::string& path, ResultsStore::Mode mode) {
  try {
    ResultsStore store(path, mode);
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

// issue 46: "unable to open database file" and "disk I/O error" said nothing of the cause
TEST(StoreTest, AStoreWhereNoneCanBeIsRefusedWithTheCause) {
  TempDir dir;
  testing::WriteFile(dir.File("file"), "");
  const std::pair<std::string, std::string> cases[] = {
      {"/dev/null", "is not a regular file (a character device)"},
      {dir.path(), "is not a regular file (a directory)"},
      {dir.File("no/such/r.db"), "the folder '" + dir.File("no/such") + "' does not exist"},
      {dir.File("file/r.db"), "'" + dir.File("file") + "' is not a folder"},
  };
  for (const auto& [path, cause] : cases) {
    for (auto mode : {ResultsStore::Mode::kReadWrite, ResultsStore::Mode::kReadOnly}) {
      std::string message = OpenError(path, mode);
      EXPECT_NE(message.find("results store '" + path + "'"), std::string::npos) << message;
      if (mode == ResultsStore::Mode::kReadWrite || path == "/dev/null") {
        EXPECT_NE(message.find(cause), std::string::npos) << message;
      }
      EXPECT_EQ(message.find("unable to open"), std::string::npos) << message;
      EXPECT_EQ(message.find("disk I/O"), std::string::npos) << message;
    }
  }
  EXPECT_FALSE(std::filesystem::exists(dir.File("no")));
  // a folder that takes no new file: read-only for a user, /sys and /proc for root (whom
  // permissions do not stop)
  std::vector<std::string> unwritable = {"/proc/plumb-store-test.db"};
  if (geteuid() != 0) {
    std::filesystem::create_directory(dir.File("ro"));
    std::filesystem::permissions(
        dir.File("ro"), std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
    unwritable.push_back(dir.File("ro/r.db"));
  } else {
    unwritable.push_back("/sys/plumb-store-test.db");
  }
  for (const std::string& path : unwritable) {
    std::string message = OpenError(path, ResultsStore::Mode::kReadWrite);
    EXPECT_NE(message.find("results store '" + path + "': its folder"), std::string::npos)
        << message;
    EXPECT_TRUE(message.find("is not writable") != std::string::npos ||
                message.find("read-only file system") != std::string::npos)
        << message;
    EXPECT_FALSE(std::filesystem::exists(path));
  }
  EXPECT_NE(OpenError(dir.File("none.db"), ResultsStore::Mode::kReadOnly).find("does not exist"),
            std::string::npos);
}

}  // namespace
}  // namespace plumb
