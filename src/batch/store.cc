#include "plumb/store.h"

#include <fmt/format.h>
#include <sqlite3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "batch/store_path.h"
#include "plumb/error.h"
#include "plumb/version.h"

namespace plumb {
using internal::CheckStorePath;

using nlohmann::json;

namespace {

std::string Now() {
  std::time_t t = std::time(nullptr);
  char buffer[32];
  std::strftime(buffer, sizeof(buffer), "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buffer;
}

json Numbers(const std::vector<double>& v) {
  json j = json::array();
  for (double x : v) j.push_back(std::isfinite(x) ? json(x) : json(nullptr));
  return j;
}

// A column plumb wrote as JSON, read back. A value that is not what plumb writes (a store
// edited by hand or damaged on disk) is an IoError naming the store, the row and the column,
// never an exception from the JSON library.
json Encoded(const std::string& text, const std::string& where) {
  json j = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!j.is_array()) {
    throw IoError(where + " is not a JSON array (" +
                  (j.is_discarded() ? std::string("not JSON") : std::string(j.type_name())) +
                  "); the store was edited or damaged: restore it from a copy or start a new "
                  "store file.");
  }
  return j;
}

// Numbers, with null for a value that was not finite.
std::vector<double> FromNumbers(const std::string& text, const std::string& where) {
  std::vector<double> out;
  for (const json& x : Encoded(text, where)) {
    if (!x.is_null() && !x.is_number()) {
      throw IoError(where + " holds " + x.type_name() +
                    " where a number belongs; the store was edited or damaged.");
    }
    out.push_back(x.is_null() ? NAN : x.get<double>());
  }
  return out;
}

std::vector<std::string> FromNames(const std::string& text, const std::string& where) {
  std::vector<std::string> out;
  for (const json& x : Encoded(text, where)) {
    if (!x.is_string()) {
      throw IoError(where + " holds " + x.type_name() +
                    " where a name belongs; the store was edited or damaged.");
    }
    out.push_back(x.get<std::string>());
  }
  return out;
}

// A prepared statement, finalized on destruction.
class Statement {
 public:
  Statement(sqlite3* db, const char* sql, const std::string& file) : file_(file) {
    if (sqlite3_prepare_v2(db, sql, -1, &s_, nullptr) != SQLITE_OK) {
      throw IoError("results store '" + file + "': " + sqlite3_errmsg(db));
    }
  }
  ~Statement() { sqlite3_finalize(s_); }
  Statement& Bind(int i, long v) { return Check(sqlite3_bind_int64(s_, i, v)); }
  Statement& Bind(int i, double v) { return Check(sqlite3_bind_double(s_, i, v)); }
  Statement& Bind(int i, const std::string& v) {
    return Check(sqlite3_bind_text(s_, i, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT));
  }
  bool Step() {
    int rc = sqlite3_step(s_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    throw IoError("results store '" + file_ + "': " + sqlite3_errmsg(sqlite3_db_handle(s_)));
  }
  // A bind that failed (out of memory, a value too big) stops the write with SQLite's reason.
  Statement& Check(int rc) {
    if (rc != SQLITE_OK) {
      throw IoError("results store '" + file_ + "': " + sqlite3_errstr(rc));
    }
    return *this;
  }
  void Reset() {
    sqlite3_reset(s_);
    sqlite3_clear_bindings(s_);
  }
  long Int(int i) { return sqlite3_column_int64(s_, i); }
  double Real(int i) { return sqlite3_column_double(s_, i); }
  std::string Text(int i) {
    const unsigned char* t = sqlite3_column_text(s_, i);
    return t ? reinterpret_cast<const char*>(t) : "";
  }

 private:
  sqlite3_stmt* s_ = nullptr;
  std::string file_;
};

}  // namespace

struct ResultsStore::Impl {
  sqlite3* db = nullptr;
  std::string file;
  std::vector<std::pair<long, RolloutResult>> queue;

  void Exec(const char* sql) {
    char* error = nullptr;
    if (sqlite3_exec(db, sql, nullptr, nullptr, &error) != SQLITE_OK) {
      std::string message = error ? error : "unknown error";
      sqlite3_free(error);
      throw IoError("results store '" + file + "': " + message);
    }
  }
};

namespace {

// How long a write waits for another process's write to the same store.
constexpr int kBusyTimeoutMs = 10000;

// Opens `path` with SQLite's `flags`. @throws IoError naming the file.
sqlite3* OpenDatabase(const std::string& path, int flags) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, flags, nullptr) != SQLITE_OK) {
    std::string message = db ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    throw IoError("cannot open results store '" + path + "': " + message);
  }
  sqlite3_busy_timeout(db, kBusyTimeoutMs);
  return db;
}

// True when a read-only connection cannot read `db` until a writable one has rolled back the
// journal, or recovered the write-ahead log, of a writer that was killed mid-transaction.
bool NeedsRecovery(sqlite3* db) {
  if (sqlite3_exec(db, "SELECT count(*) FROM sqlite_master", nullptr, nullptr, nullptr) ==
      SQLITE_OK) {
    return false;
  }
  int why = sqlite3_extended_errcode(db);
  return why == SQLITE_READONLY_ROLLBACK || why == SQLITE_READONLY_RECOVERY;
}

// Puts `db` in write-ahead-log mode (a no-op once it is). SQLite answers a switch that meets
// another connection's read with SQLITE_BUSY at once, without its busy handler (the switch holds
// a read lock of its own and waiting could deadlock), so several plumbs opening one new store
// together retry here, for as long as the busy timeout. @throws IoError naming the file.
void SwitchToWriteAheadLog(sqlite3* db, const std::string& path) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point give_up = Clock::now() + std::chrono::milliseconds(kBusyTimeoutMs);
  auto pause = std::chrono::milliseconds(1);
  while (true) {
    int rc = sqlite3_exec(db, "PRAGMA journal_mode=WAL", nullptr, nullptr, nullptr);
    if (rc == SQLITE_OK) return;
    if ((rc & 0xff) != SQLITE_BUSY || Clock::now() >= give_up) {
      throw IoError("results store '" + path + "': " + sqlite3_errmsg(db) +
                    (rc == SQLITE_BUSY ? " (another process held it for " +
                                             std::to_string(kBusyTimeoutMs / 1000) + " s)"
                                       : ""));
    }
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::milliseconds(50));
  }
}

}  // namespace

namespace {

// SQLite's own recovery of a store a writer left mid-write: on the first read of a writable
// connection, which writes nothing else; `*db` is closed first and is read-only again after.
void RecoverForReading(sqlite3** db, const std::string& path) {
  sqlite3_close(*db);
  *db = nullptr;
  sqlite3* writable = nullptr;
  try {
    writable = OpenDatabase(path, SQLITE_OPEN_READWRITE);
  } catch (const IoError& e) {
    throw IoError(std::string(e.what()) +
                  " (a plumb writing it was killed mid-write, and SQLite can finish its "
                  "recovery only where the file is writable)");
  }
  sqlite3_exec(writable, "SELECT count(*) FROM sqlite_master", nullptr, nullptr, nullptr);
  sqlite3_close(writable);
  *db = OpenDatabase(path, SQLITE_OPEN_READONLY);
}

// Throws IoError unless SQLite's quick_check finds the store `db` (at `path`) sound.
void RequireUndamaged(sqlite3* db, const std::string& path) {
  Statement check(db, "PRAGMA quick_check", path);
  std::string verdict = check.Step() ? check.Text(0) : "no answer";
  if (verdict != "ok") {
    throw IoError("results store '" + path + "' is damaged (SQLite quick_check: " + verdict +
                  "); restore it from a copy or start a new store file.");
  }
}

// The tables and the ids in one transaction: a store killed while it is made holds all of
// them or none (one table alone used to make it "not a plumb results store").
std::string CreateTablesSql() {
  return fmt::format(
      "BEGIN IMMEDIATE;"
      "CREATE TABLE IF NOT EXISTS runs(id INTEGER PRIMARY KEY, kind TEXT, "
      "config TEXT, command TEXT, model_file TEXT, model_hash TEXT, "
      "plumb_version TEXT, mujoco_version TEXT, started TEXT, finished TEXT, "
      "parameters TEXT, metrics TEXT, count INTEGER);"
      "CREATE TABLE IF NOT EXISTS cases(run INTEGER, idx INTEGER, params TEXT, "
      "PRIMARY KEY(run, idx));"
      "CREATE TABLE IF NOT EXISTS results(run INTEGER, idx INTEGER, metrics TEXT, "
      "diverged INTEGER, diverged_time REAL, problem TEXT, warnings TEXT, "
      "PRIMARY KEY(run, idx));"
      "PRAGMA application_id = {}; PRAGMA user_version = {}; COMMIT;",
      kStoreApplicationId, kStoreFormat);
}

}  // namespace

ResultsStore::ResultsStore(const std::string& path, Mode mode) : impl_(std::make_unique<Impl>()) {
  impl_->file = path;
  bool read_only = mode == Mode::kReadOnly;
  CheckStorePath(path, !read_only);  // the real cause, not SQLite's "unable to open database"
  impl_->db = OpenDatabase(
      path, read_only ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  try {
    if (read_only && NeedsRecovery(impl_->db)) RecoverForReading(&impl_->db, path);
    auto integer = [&](const char* sql) {
      Statement s(impl_->db, sql, path);
      return s.Step() ? s.Int(0) : 0L;
    };
    long tables = integer("SELECT count(*) FROM sqlite_master WHERE type = 'table'");
    long ours = integer(
        "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name IN "
        "('runs', 'cases', 'results')");
    long id = integer("PRAGMA application_id");
    bool fresh = tables == 0;
    // stores written before the id existed have id 0 and exactly our tables
    bool plumb = id == kStoreApplicationId || (id == 0 && ours == 3 && tables == 3);
    if (!fresh && !plumb) {
      throw IoError("'" + path + "' is an SQLite file but not a plumb results store (" +
                    (id != 0 ? fmt::format("application_id {:#x}", id)
                             : std::to_string(tables) + " unrelated table(s)") +
                    "); give plumb a file of its own.");
    }
    long format = integer("PRAGMA user_version");
    if (format > kStoreFormat) {
      throw IoError(fmt::format(
          "results store '{}' has format {}, written by a newer plumb; this plumb (version {}) "
          "reads formats up to {}. Open it with that newer plumb, or start a new store file.",
          path, format, PLUMB_VERSION, kStoreFormat));
    }
    if (read_only) {
      if (fresh) throw IoError("'" + path + "' is empty, not a plumb results store.");
      return;
    }
    if (!fresh) RequireUndamaged(impl_->db, path);
    SwitchToWriteAheadLog(impl_->db, path);
    impl_->Exec("PRAGMA synchronous=NORMAL");
    if (id != kStoreApplicationId || ours != 3 || format < kStoreFormat) {
      impl_->Exec(CreateTablesSql().c_str());  // all tables and ids, or none
    }
  } catch (const Error&) {
    sqlite3_close(impl_->db);
    impl_->db = nullptr;
    throw;
  }
}

ResultsStore::~ResultsStore() {
  if (!impl_->db) return;
  // a destructor cannot throw: a commit that fails here is said on stderr, never dropped in
  // silence (callers commit explicitly first, where a failure is an error they report)
  std::size_t pending = impl_->queue.size();
  try {
    Commit();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "plumb: error: %zu result(s) could not be written to '%s': %s\n", pending,
                 impl_->file.c_str(), e.what());
  }
  sqlite3_close(impl_->db);
}

std::optional<RunInfo> ResultsStore::FindRun(const std::string& config) {
  for (RunInfo& r : Runs()) {
    if (r.config == config) return r;
  }
  return std::nullopt;
}

long ResultsStore::BeginRun(const RunInfo& info) {
  Statement s(impl_->db,
              "INSERT INTO runs(kind, config, command, model_file, model_hash, plumb_version, "
              "mujoco_version, started, finished, parameters, metrics, count) "
              "VALUES(?,?,?,?,?,?,?,?,?,?,?,?)",
              impl_->file);
  s.Bind(1, info.kind).Bind(2, info.config).Bind(3, info.command).Bind(4, info.model_file);
  s.Bind(5, info.model_hash).Bind(6, info.plumb_version).Bind(7, info.mujoco_version);
  s.Bind(8, info.started.empty() ? Now() : info.started).Bind(9, info.finished);
  s.Bind(10, json(info.parameters).dump()).Bind(11, json(info.metrics).dump()).Bind(12, info.count);
  s.Step();
  return sqlite3_last_insert_rowid(impl_->db);
}

void ResultsStore::AppendCommand(long run, const std::string& command) {
  Statement s(impl_->db,
              "UPDATE runs SET command = command || char(10) || ? WHERE id = ? AND "
              "instr(char(10) || command || char(10), char(10) || ? || char(10)) = 0",
              impl_->file);
  s.Bind(1, command).Bind(2, run).Bind(3, command).Step();
}

void ResultsStore::Transaction(const std::function<void()>& work) {
  Commit();
  impl_->Exec("BEGIN IMMEDIATE");
  try {
    work();
    impl_->Exec("COMMIT");
  } catch (...) {
    sqlite3_exec(impl_->db, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

void ResultsStore::FinishRun(long run) {
  Commit();
  Statement s(impl_->db, "UPDATE runs SET finished = ? WHERE id = ?", impl_->file);
  s.Bind(1, Now()).Bind(2, run).Step();
}

std::vector<RunInfo> ResultsStore::Runs() {
  Statement s(impl_->db,
              "SELECT id, kind, config, command, model_file, model_hash, plumb_version, "
              "mujoco_version, started, finished, parameters, metrics, count FROM runs ORDER BY id",
              impl_->file);
  std::vector<RunInfo> runs;
  while (s.Step()) {
    RunInfo r;
    r.id = s.Int(0);
    r.kind = s.Text(1);
    r.config = s.Text(2);
    r.command = s.Text(3);
    r.model_file = s.Text(4);
    r.model_hash = s.Text(5);
    r.plumb_version = s.Text(6);
    r.mujoco_version = s.Text(7);
    r.started = s.Text(8);
    r.finished = s.Text(9);
    std::string where = fmt::format("results store '{}': run {}", impl_->file, r.id);
    r.parameters = FromNames(s.Text(10), where + " column 'parameters'");
    r.metrics = FromNames(s.Text(11), where + " column 'metrics'");
    r.count = s.Int(12);
    runs.push_back(r);
  }
  return runs;
}

std::vector<long> ResultsStore::DoneIndices(long run) {
  Commit();
  Statement s(impl_->db, "SELECT idx FROM results WHERE run = ? ORDER BY idx", impl_->file);
  s.Bind(1, run);
  std::vector<long> done;
  while (s.Step()) done.push_back(s.Int(0));
  return done;
}

long ResultsStore::CountDone(long run) {
  Commit();
  Statement s(impl_->db, "SELECT count(*) FROM results WHERE run = ?", impl_->file);
  s.Bind(1, run);
  return s.Step() ? s.Int(0) : 0;
}

void ResultsStore::Add(long run, const RolloutResult& result) {
  impl_->queue.emplace_back(run, result);
  if (impl_->queue.size() >= batch) Commit();
}

void ResultsStore::Commit() {
  if (impl_->queue.empty()) return;
  impl_->Exec("BEGIN IMMEDIATE");
  try {
    Statement c(impl_->db, "INSERT OR REPLACE INTO cases(run, idx, params) VALUES(?,?,?)",
                impl_->file);
    Statement r(impl_->db,
                "INSERT OR REPLACE INTO results(run, idx, metrics, diverged, diverged_time, "
                "problem, warnings) VALUES(?,?,?,?,?,?,?)",
                impl_->file);
    for (const auto& [run, x] : impl_->queue) {
      c.Bind(1, run).Bind(2, x.index).Bind(3, Numbers(x.params).dump());
      c.Step();
      c.Reset();
      r.Bind(1, run).Bind(2, x.index).Bind(3, Numbers(x.metrics).dump());
      r.Bind(4, static_cast<long>(x.diverged)).Bind(5, x.diverged_time).Bind(6, x.problem);
      r.Bind(7, x.warnings);
      r.Step();
      r.Reset();
    }
    impl_->Exec("COMMIT");
  } catch (...) {
    sqlite3_exec(impl_->db, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
  impl_->queue.clear();
}

std::vector<RolloutResult> ResultsStore::Results(long run) {
  std::vector<RolloutResult> out;
  ForEachResult(run, [&](const RolloutResult& r) { out.push_back(r); });
  return out;
}

void ResultsStore::ForEachResult(long run, const std::function<void(const RolloutResult&)>& visit) {
  Commit();
  Statement s(impl_->db,
              "SELECT r.idx, c.params, r.metrics, r.diverged, r.diverged_time, r.problem, "
              "r.warnings "
              "FROM results r JOIN cases c ON c.run = r.run AND c.idx = r.idx "
              "WHERE r.run = ? ORDER BY r.idx",
              impl_->file);
  s.Bind(1, run);
  while (s.Step()) {
    RolloutResult x;
    x.index = s.Int(0);
    std::string where =
        fmt::format("results store '{}': run {} case {}", impl_->file, run, x.index);
    x.params = FromNumbers(s.Text(1), where + " column 'params'");
    x.metrics = FromNumbers(s.Text(2), where + " column 'metrics'");
    x.diverged = s.Int(3) != 0;
    x.diverged_time = s.Real(4);
    x.problem = s.Text(5);
    x.warnings = s.Text(6);
    visit(x);
  }
}

namespace {

// A run an input says is finished must hold every index: a hole there means the store was
// edited or damaged, and a merge would pass the hole on as a complete run.
void RequireCompleteIfFinished(ResultsStore& in, const RunInfo& run, const std::string& input) {
  if (run.finished.empty() || in.CountDone(run.id) == run.count) return;
  std::vector<long> done = in.DoneIndices(run.id);
  std::vector<std::string> missing;
  std::size_t k = 0;
  for (long i = 0; i < run.count && missing.size() < 6; ++i) {
    while (k < done.size() && done[k] < i) ++k;
    if (k < done.size() && done[k] == i) continue;
    missing.push_back(std::to_string(i));
  }
  throw ValueError(fmt::format(
      "merge: '{}' says run {} is complete, but it holds {} of its {} rollouts (missing: {}{}); "
      "the store was edited or damaged. Resume the run on that store before merging.",
      input, run.id, done.size(), run.count, fmt::join(missing, ", "),
      static_cast<long>(done.size()) + static_cast<long>(missing.size()) < run.count ? ", ..."
                                                                                     : ""));
}

}  // namespace

void MergeStores(const std::vector<std::string>& inputs, const std::string& output) {
  if (std::filesystem::exists(output)) {
    throw IoError("merge: '" + output + "' exists already; give a new file name.");
  }
  std::string temp = output + ".tmp-merge";
  auto remove_temp = [&] {
    std::error_code ignored;
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(temp + suffix, ignored);
  };
  remove_temp();
  try {
    ResultsStore out(temp);
    std::map<std::string, long> by_config;
    std::map<std::pair<long, long>, RolloutResult> seen;
    for (const std::string& input : inputs) {
      if (!std::filesystem::exists(input)) throw IoError("merge: no such store '" + input + "'.");
      ResultsStore in(input, ResultsStore::Mode::kReadOnly);
      for (const RunInfo& run : in.Runs()) {
        RequireCompleteIfFinished(in, run, input);
        auto [it, fresh] = by_config.emplace(run.config, 0);
        if (fresh) {
          RunInfo copy = run;
          copy.finished.clear();
          it->second = out.BeginRun(copy);
        } else {
          // every shard's command line stays on record
          std::istringstream commands(run.command);
          for (std::string line; std::getline(commands, line);) {
            out.AppendCommand(it->second, line);
          }
        }
        long target = it->second;
        for (const RolloutResult& r : in.Results(run.id)) {
          auto [at, inserted] = seen.emplace(std::make_pair(target, r.index), r);
          if (!inserted) {
            bool same = at->second.params.size() == r.params.size() &&
                        Numbers(at->second.params) == Numbers(r.params) &&
                        Numbers(at->second.metrics) == Numbers(r.metrics);
            if (!same) {
              throw ValueError("merge: rollout " + std::to_string(r.index) +
                               " differs between inputs ('" + input +
                               "'); they are not shards "
                               "of the same run.");
            }
            continue;
          }
          out.Add(target, r);
        }
      }
    }
    out.Commit();
    // a merged run is finished when it holds every index
    for (const RunInfo& run : out.Runs()) {
      if (out.CountDone(run.id) == run.count) out.FinishRun(run.id);
    }
  } catch (...) {
    remove_temp();  // a failed merge leaves nothing behind
    throw;
  }
  std::filesystem::rename(temp, output);
  std::filesystem::remove(temp + "-wal");
  std::filesystem::remove(temp + "-shm");
}

}  // namespace plumb
