// The results store's encoded rows: a store whose run, case and result rows hold the fuzzer's
// text (one field a line: the run's parameters, metrics, count and finished time, then a
// case's index, params, metrics, problem and warnings) is read back and merged. A store
// edited by hand or damaged on disk must give an Error naming it, never a crash.

#include <sqlite3.h>

#include <filesystem>
#include <sstream>
#include <vector>

#include "fuzz_common.h"
#include "plumb/store.h"

namespace {

void Exec(sqlite3* db, const char* sql, const std::vector<std::string>& values) {
  sqlite3_stmt* s = nullptr;
  if (sqlite3_prepare_v2(db, sql, -1, &s, nullptr) != SQLITE_OK) __builtin_trap();
  for (std::size_t i = 0; i < values.size(); ++i) {
    sqlite3_bind_text(s, static_cast<int>(i + 1), values[i].c_str(),
                      static_cast<int>(values[i].size()), SQLITE_TRANSIENT);
  }
  if (sqlite3_step(s) != SQLITE_DONE) __builtin_trap();
  sqlite3_finalize(s);
}

void Remove(const std::string& path) {
  std::error_code ignored;
  for (const char* suffix :
       {"", "-wal", "-shm", ".tmp-merge", ".tmp-merge-wal", ".tmp-merge-shm"}) {
    std::filesystem::remove(path + suffix, ignored);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace plumb;
  std::vector<std::string> field;
  std::istringstream lines(fuzz::Text(data, size));
  for (std::string line; field.size() < 9 && std::getline(lines, line);) field.push_back(line);
  field.resize(9);
  // in memory where there is a tmpfs: a store is made and merged for every input
  static const std::string folder = std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
  std::string base = folder + "/plumb-fuzz-store-" + std::to_string(getpid());
  std::string input = base + ".sqlite", output = base + "-merged.sqlite";
  Remove(input);
  Remove(output);
  { ResultsStore create(input); }
  sqlite3* db = nullptr;
  if (sqlite3_open(input.c_str(), &db) != SQLITE_OK) __builtin_trap();
  Exec(db,
       "INSERT INTO runs(id, kind, config, command, parameters, metrics, count, finished) "
       "VALUES(1, 'rollout', 'config', 'plumb rollout', ?, ?, ?, ?)",
       {field[0], field[1], field[2], field[3]});
  Exec(db, "INSERT INTO cases(run, idx, params) VALUES(1, ?, ?)", {field[4], field[5]});
  Exec(db,
       "INSERT INTO results(run, idx, metrics, diverged, diverged_time, problem, warnings) "
       "VALUES(1, ?, ?, 0, 0, ?, ?)",
       {field[4], field[6], field[7], field[8]});
  sqlite3_close(db);
  fuzz::Expect([&] {
    ResultsStore store(input, ResultsStore::Mode::kReadOnly);
    for (const RunInfo& run : store.Runs()) {
      store.DoneIndices(run.id);
      store.Results(run.id);
    }
  });
  fuzz::Expect([&] { MergeStores({input}, output); });
  Remove(input);
  Remove(output);
  return 0;
}
