// Model and Data ownership, loading with complete diagnostics, MuJoCo handlers.

#include "plumb/model.h"

#include <dlfcn.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>

#include "core/derived.h"
#include "core/file_kind.h"
#include "core/input_file.h"
#include "core/mujoco_compat.h"
#include "core/schema_error.h"
#include "core/strings.h"
#include "plumb/error.h"

namespace plumb {
using internal::CheckModelText;
using internal::CompleteDerived;
using internal::FileKind;
using internal::InputKind;
using internal::Join;
using internal::ReadInputFile;
using internal::SchemaErrorPlace;
using internal::SniffFileKind;

namespace {

namespace fs = std::filesystem;

// MuJoCo's XML loader and mj_saveLastXML share global state ("the last XML parsed").
std::mutex& LoaderMutex() {
  static std::mutex mutex;
  return mutex;
}

// Identifies the most recent successful XML parse, so SaveXml knows whether MuJoCo's
// global "last XML" still belongs to the model being saved.
std::uint64_t g_last_xml_load_id = 0;
std::uint64_t g_next_xml_load_id = 1;

// Warnings are kept per thread, so parallel workers never see each other's messages.
constexpr std::size_t kMaxKeptWarnings = 1000;
thread_local std::vector<std::string> t_warnings;

std::string Trimmed(const char* text) {
  std::string s(text);
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ' || s.back() == '\r')) s.pop_back();
  return s;
}

void OnMujocoError(const char* msg) {
  // mju_error must not return into MuJoCo (2.x would carry on with bad memory), and
  // must not exit(): unwind to the plumb call that entered MuJoCo. libmujoco is built
  // with unwind tables, which tests/core/model_test.cc exercises (also under ASan).
  throw MujocoError("MuJoCo error: " + Trimmed(msg));
}

void OnMujocoWarning(const char* msg) {
  if (t_warnings.size() < kMaxKeptWarnings) t_warnings.push_back(Trimmed(msg));
}

// MujocoHandlerMode::kAroundCalls: plumb's handler chains to the one it replaced, and takes a
// message only on a thread inside a MujocoCallScope.
MujocoHandlerMode g_mode = MujocoHandlerMode::kProcess;
thread_local int t_call_depth = 0;

#if PLUMB_MUJOCO_HAS_LOG_HANDLER
std::mutex g_scope_mutex;
int g_scopes_alive = 0;  // guarded by g_scope_mutex
// the handler plumb's replaced: written under g_scope_mutex, read by any thread's message
std::atomic<mjfLogHandler> g_previous_log_handler{nullptr};

void OnMujocoLog(const mjLogMessage* message) {
  bool ours = t_call_depth > 0 &&
              (message->level == mjLOG_ERROR || message->level == mjLOG_WARNING);
  if (!ours) {
    g_previous_log_handler.load()(message);
    return;
  }
  std::string text = message->subject;
  if (message->body != nullptr && *message->body != '\0') text += std::string("\n") + message->body;
  if (message->level == mjLOG_ERROR) {
    OnMujocoError(text.c_str());  // throws
  } else {
    OnMujocoWarning(text.c_str());
  }
}
#endif

bool EndsWith(const std::string& s, std::string_view suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Inserts <compiler autolimits="true"/> right after the <mujoco ...> tag, or returns ""
// when there is no such tag.
std::string WithAutolimits(const std::string& xml) {
  std::size_t open = xml.find("<mujoco");
  if (open == std::string::npos) return "";
  std::size_t close = xml.find('>', open);
  if (close == std::string::npos || xml[close - 1] == '/') return "";
  return xml.substr(0, close + 1) + "<compiler autolimits=\"true\"/>" + xml.substr(close + 1);
}

// Compiles `xml` from a temporary file in `dir` (so relative includes and assets
// resolve as for the original). Returns nullptr on any failure. Caller holds the lock.
mjModel* CompileFromTempFile(const std::string& xml, const fs::path& dir, char* error,
                             int error_size) {
  std::string pattern = (dir / ".plumb-XXXXXX.xml").string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  int fd = mkstemps(name.data(), 4);
  if (fd < 0) return nullptr;
  bool written = ::write(fd, xml.data(), xml.size()) == static_cast<ssize_t>(xml.size());
  ::close(fd);
  mjModel* m = nullptr;
  if (written) {
    try {
      m = mj_loadXML(name.data(), nullptr, error, error_size);
    } catch (const MujocoError&) {
      m = nullptr;
    }
  }
  std::remove(name.data());
  return m;
}

// On MuJoCo 2.x, `range` without `limited` is an error unless autolimits is on; MuJoCo
// 3 turned autolimits on by default, so 3.x-era models fail here. Detects that case
// by compiling again with autolimits, without matching on error text.
std::string AutolimitsHint(const std::string& xml, const fs::path& dir) {
  if constexpr (compat::kMujoco3) return "";
  std::string patched = WithAutolimits(xml);
  if (patched.empty()) return "";
  char error[1024] = {0};
  mjModel* m = CompileFromTempFile(patched, dir, error, sizeof(error));
  if (!m) m = CompileFromTempFile(patched, fs::temp_directory_path(), error, sizeof(error));
  if (!m) return "";
  mj_deleteModel(m);
  return "hint: this model compiles once <compiler autolimits=\"true\"/> is added. MuJoCo " +
         MujocoVersion() +
         " requires limited=\"true\" next to every range (joints, actuator ctrlrange/"
         "forcerange, tendons) unless autolimits is on; MuJoCo 3 turns autolimits on by "
         "default, so models written for 3.x often fail here. To load on both, add "
         "<compiler autolimits=\"true\"/> inside <mujoco>, or write limited=\"true\" "
         "wherever a range is given.";
}

// Schema elements that one MuJoCo release removed or renamed, so models written for another
// fail with "unrecognized attribute": what changed, and which build loads the model as is.
struct SchemaChange {
  const char* element;    // as MuJoCo's error names it ("Element 'contact'")
  const char* attribute;  // "unrecognized attribute: 'internal'"
  int removed_in;         // the release that removed it: major*10^6 + minor*10^3 + patch
  const char* what;
};
constexpr SchemaChange kSchemaChanges[] = {
    {"contact", "internal", 4000000,
     "MuJoCo 4.0 removed the internal attribute of a flex's <contact> (flexcomp and flex), "
     "which 3.x models such as MuJoCo 3.12's own flex samples set; MuJoCo 3.11.0 loads the "
     "model as it is (build plumb with make build MUJOCO=3.11.0), and here it loads once the "
     "attribute is deleted"},
    {"flag", "passive", 3003006,
     "MuJoCo 3.3.6 replaced <option><flag passive> with the spring and damper flags: write "
     "spring=\"disable\" damper=\"disable\" instead"},
    {"option", "collision", 3000000,
     "MuJoCo 3.0 removed <option collision>: delete collision=\"all\"; for "
     "collision=\"dynamic\" delete the <pair> elements; for \"predefined\" set contype and "
     "conaffinity to 0 by default"},
};

// What changed between releases, when `error` is a schema violation that one caused.
std::string SchemaChangeHint(const std::string& error) {
  for (const SchemaChange& c : kSchemaChanges) {
    if (!compat::CompiledAtLeast(c.removed_in)) continue;
    if (error.find("unrecognized attribute: '" + std::string(c.attribute) + "'") ==
            std::string::npos ||
        error.find("Element '" + std::string(c.element) + "'") == std::string::npos) {
      continue;
    }
    return std::string("hint: ") + c.what + ".";
  }
  return "";
}

// The hint for a model MuJoCo refused: a release's schema change, or 2.x's autolimits.
std::string LoadHint(const std::string& error, const std::string& xml, const fs::path& dir) {
  std::string hint = SchemaChangeHint(error);
  return hint.empty() ? AutolimitsHint(xml, dir) : hint;
}

}  // namespace

void InstallMujocoHandlers() {
  if (!compat::LoadedMujocoIsCompiledOne()) {
    throw Error("the MuJoCo library loaded (" + MujocoVersion() + ", " + MujocoLibraryPath() +
                ") is not the one plumb was built with (" + CompiledMujocoVersion() +
                "): MuJoCo changes its binary interface between releases. Rebuild plumb "
                "against the MuJoCo it runs with (make build MUJOCO=" +
                MujocoVersion() +
                ", or -DMUJOCO_ROOT=<release folder>), or run it with the library it was "
                "built with.");
  }
  if (g_mode == MujocoHandlerMode::kAroundCalls) return;  // MujocoCallScope installs them
  static std::once_flag once;
  std::call_once(once, [] {
    compat::SetMujocoHandlers(&OnMujocoError, &OnMujocoWarning);
    std::string plugins = MujocoPluginPath();
    if (!plugins.empty()) compat::LoadPluginLibraries(plugins);
  });
}

void SetMujocoHandlerMode(MujocoHandlerMode mode) {
#if !PLUMB_MUJOCO_HAS_LOG_HANDLER
  if (mode == MujocoHandlerMode::kAroundCalls) {
    throw UnavailableError("plumb cannot install its MuJoCo handlers around its own calls on "
                           "MuJoCo " + CompiledMujocoVersion() +
                           ": that needs mju_setLogHandler (MuJoCo 3.11 or later)");
  }
#endif
  g_mode = mode;
}

MujocoCallScope::MujocoCallScope() {
  if (t_call_depth++ > 0 || g_mode != MujocoHandlerMode::kAroundCalls) return;
#if PLUMB_MUJOCO_HAS_LOG_HANDLER
  std::lock_guard<std::mutex> lock(g_scope_mutex);
  if (g_scopes_alive++ == 0) g_previous_log_handler = mju_setLogHandler(&OnMujocoLog);
#endif
}

MujocoCallScope::~MujocoCallScope() {
  if (--t_call_depth > 0 || g_mode != MujocoHandlerMode::kAroundCalls) return;
#if PLUMB_MUJOCO_HAS_LOG_HANDLER
  std::lock_guard<std::mutex> lock(g_scope_mutex);
  if (--g_scopes_alive == 0) mju_setLogHandler(g_previous_log_handler.load());
#endif
}

std::string CompiledMujocoVersion() { return compat::CompiledVersionText(); }

std::string MujocoLibraryPath() {
  Dl_info info;
  if (dladdr(reinterpret_cast<void*>(&mj_version), &info) == 0 || !info.dli_fname) return "";
  std::error_code ec;
  fs::path path = fs::canonical(info.dli_fname, ec);
  return ec ? std::string(info.dli_fname) : path.string();
}

std::string MujocoPluginPath() {
  if (!compat::kMujoco3) return "";  // 2.x has no plugins
  if (const char* env = std::getenv("PLUMB_MUJOCO_PLUGIN_PATH"); env && *env) {
    std::error_code ec;
    if (!fs::is_directory(env, ec)) {  // MuJoCo would skip it without a word
      throw ValueError(std::string("PLUMB_MUJOCO_PLUGIN_PATH='") + env +
                       "' is not a folder (" + (ec ? ec.message() : "it is a file") +
                       "): set it to the folder of MuJoCo's plugin libraries, or unset it to "
                       "use the one beside the MuJoCo library.");
    }
    return env;
  }
  std::string library = MujocoLibraryPath();
  if (library.empty()) return "";
  fs::path dir = fs::path(library).parent_path();
  // a release folder's layout, a folder of its own beside the library, and the mujoco-core
  // wheel's (site-packages/mujoco/plugin, which plumb's wheel runs with)
  for (const fs::path& candidate :
       {dir / ".." / "bin" / "mujoco_plugin", dir / "mujoco_plugin", dir / "plugin"}) {
    std::error_code ec;
    if (fs::is_directory(candidate, ec)) return fs::canonical(candidate, ec).string();
  }
  return "";
}

std::vector<std::string> TakeMujocoWarnings() {
  std::vector<std::string> out;
  out.swap(t_warnings);
  return out;
}

std::string MujocoVersion() { return mj_versionString(); }

void Model::Deleter::operator()(mjModel* m) const {
  if (owned) mj_deleteModel(m);
}

Model Model::Borrow(mjModel* m, std::string name) {
  InstallMujocoHandlers();
  Model model(m, std::move(name));
  model.m_.get_deleter().owned = false;
  return model;
}

Model::Model(mjModel* m, std::string file) : m_(m, Deleter{true}), file_(std::move(file)) {}
Model::Model(Model&&) noexcept = default;
Model& Model::operator=(Model&&) noexcept = default;
Model::~Model() = default;

Model Model::Load(const std::string& path) {
  InstallMujocoHandlers();
  std::string text;
  try {
    text = ReadInputFile(path, InputKind::kModel);  // a FIFO or a device is refused, not waited on
  } catch (const IoError& e) {
    throw LoadError(e.what(), "");
  }
  // the content decides, not the name: MJCF named .mjb is compiled, a compiled model named
  // otherwise is loaded; an empty or JSON file is named for what it is
  bool binary = SniffFileKind(text) == FileKind::kBinary;
  if (!binary) CheckModelText(path, text);

  // binary models: mj_loadModel reports problems as warnings and returns nullptr
  if (binary) {
    mjModel* m = nullptr;
    TakeMujocoWarnings();
    try {
      m = mj_loadModel(path.c_str(), nullptr);
    } catch (const MujocoError& e) {
      throw LoadError("cannot load binary model '" + path + "': " + e.what(), "");
    }
    if (!m && !EndsWith(path, ".mjb")) {
      TakeMujocoWarnings();
      CheckModelText(path, text);  // throws: "a binary file, not an MJCF model"
    }
    if (!m) {
      std::string detail = Join(TakeMujocoWarnings(), "; ");
      throw LoadError(
          "cannot load binary model '" + path + "': " +
              (detail.empty() ? "not a valid .mjb file for MuJoCo " + MujocoVersion() : detail) +
              ". A .mjb file only loads in the MuJoCo version that wrote it.",
          "");
    }
    return Model(m, path);
  }

  // MJCF: keep MuJoCo's whole error buffer, which names the element, its name/id and line
  std::lock_guard<std::mutex> lock(LoaderMutex());
  char error[4096] = {0};
  mjModel* m = nullptr;
  try {
    m = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
  } catch (const MujocoError& e) {
    throw LoadError("cannot load model '" + path + "': " + e.what(), "");
  }
  if (!m) {
    std::string detail = Trimmed(error);
    if (detail.empty()) detail = "MuJoCo gave no further detail";
    // an element of an included file comes as "line 0" of no file: name the file and line
    if (std::string place = SchemaErrorPlace(detail, path); !place.empty()) {
      detail += "\n" + place;
    }
    fs::path dir = fs::path(path).parent_path();
    if (dir.empty()) dir = ".";
    throw LoadError("cannot load model '" + path + "':\n" + detail, LoadHint(detail, text, dir));
  }
  Model model(m, path);
  model.compile_warnings_ = Trimmed(error);
  model.xml_load_id_ = g_next_xml_load_id++;
  g_last_xml_load_id = model.xml_load_id_;
  return model;
}

Model Model::FromXmlString(std::string_view xml, std::string_view name) {
  InstallMujocoHandlers();
  std::lock_guard<std::mutex> lock(LoaderMutex());
  std::string text(xml);
  char error[4096] = {0};
  mjModel* m = CompileFromTempFile(text, fs::temp_directory_path(), error, sizeof(error));
  if (!m) {
    std::string detail = Trimmed(error);
    throw LoadError("cannot load model " + std::string(name) + ":\n" +
                        (detail.empty() ? "MuJoCo gave no further detail" : detail),
                    LoadHint(detail, text, fs::temp_directory_path()));
  }
  Model model(m, std::string(name));
  model.compile_warnings_ = Trimmed(error);
  model.xml_source_ = std::make_shared<const std::string>(std::move(text));
  model.xml_load_id_ = g_next_xml_load_id++;
  g_last_xml_load_id = model.xml_load_id_;
  return model;
}

const std::string& Model::xml_text() const {
  static const std::string kNone;
  return xml_source_ ? *xml_source_ : kNone;
}

Model Model::Clone() const {
  mjModel* copy = mj_copyModel(nullptr, m_.get());
  if (!copy) throw MujocoError("MuJoCo could not copy the model (out of memory?)");
  Model clone(copy, file_);
  clone.compile_warnings_ = compile_warnings_;
  clone.xml_source_ = xml_source_;
  clone.xml_load_id_ = xml_load_id_;
  return clone;
}

void Model::SaveXml(const std::string& path) const {
  if (xml_load_id_ == 0) {
    throw IoError("cannot write '" + path + "' as MJCF: model '" + file_ +
                  "' was not loaded from XML (save it with SaveBinary instead)");
  }
  std::lock_guard<std::mutex> lock(LoaderMutex());
  // make MuJoCo's global "last XML" this model's again by parsing its source once more
  if (g_last_xml_load_id != xml_load_id_) {
    char error[1024] = {0};
    mjModel* reparsed = xml_source_ ? CompileFromTempFile(*xml_source_, fs::temp_directory_path(),
                                                          error, sizeof(error))
                                    : mj_loadXML(file_.c_str(), nullptr, error, sizeof(error));
    if (!reparsed) {
      throw IoError("cannot write '" + path + "': re-reading '" + file_ + "' failed: " + error);
    }
    mj_deleteModel(reparsed);
    g_last_xml_load_id = xml_load_id_;
  }
  char error[1024] = {0};
  if (!mj_saveLastXML(path.c_str(), m_.get(), error, sizeof(error))) {
    throw IoError("cannot write MJCF to '" + path + "': " + Trimmed(error));
  }
}

bool Model::SaveLastXml(const std::string& path, std::string* reason) const {
  std::lock_guard<std::mutex> lock(LoaderMutex());
  char error[1024] = {0};
  try {
    if (mj_saveLastXML(path.c_str(), m_.get(), error, sizeof(error))) return true;
  } catch (const MujocoError& e) {  // MuJoCo 2.x: mju_error for a model of other sizes
    *reason = e.what();
    return false;
  }
  *reason = Trimmed(error);
  return false;
}

void Model::SaveBinary(const std::string& path) const {
  // mj_saveModel reports an unopenable file through mju_warning only: check first
  FILE* probe = std::fopen(path.c_str(), "wb");
  if (!probe) throw IoError("cannot write '" + path + "': " + std::strerror(errno));
  std::fclose(probe);
  mj_saveModel(m_.get(), path.c_str(), nullptr, 0);
}

std::string Model::Name(int type, int id) const {
  const char* name = mj_id2name(m_.get(), type, id);
  return name ? name : "";
}

void Data::Deleter::operator()(mjData* d) const { mj_deleteData(d); }

Data::Data(const mjModel* m, mjData* d) : m_(m), d_(d) {}

Data::Data(const Model& model) : m_(model.get()) {
  InstallMujocoHandlers();
  mjData* d = mj_makeData(m_);
  if (!d) throw MujocoError("MuJoCo could not allocate data for model '" + model.file() + "'");
  d_.reset(d);
}

Data::Data(Data&&) noexcept = default;
Data& Data::operator=(Data&&) noexcept = default;
Data::~Data() = default;

Data Data::Clone() const {
  mjData* copy = mj_makeData(m_);
  if (!copy) throw MujocoError("MuJoCo could not allocate a copy of the data");
  mj_copyData(copy, m_, d_.get());
  return Data(m_, copy);
}

void Data::Reset() { mj_resetData(m_, d_.get()); }
void Data::Forward() {
  mj_forward(m_, d_.get());
  CompleteDerived(m_, d_.get());
}

void internal::CompleteDerived(const mjModel* m, mjData* d) {
  // energy: without the flag mj_forward leaves it as it was (0 after a reset), and
  // mj_energyPos/Vel check the flag themselves: they get a shallow copy of the model
  // with it set (the arrays are shared, nothing is written to the model)
  if (!(m->opt.enableflags & mjENBL_ENERGY)) {
    mjModel with_energy = *m;
    with_energy.opt.enableflags |= mjENBL_ENERGY;
    mj_energyPos(&with_energy, d);
    mj_energyVel(&with_energy, d);
  }
  // subtree momenta and the com-based accelerations and forces of every body
  mj_subtreeVel(m, d);
  mj_rnePostConstraint(m, d);
}
void Data::Step() { mj_step(m_, d_.get()); }

}  // namespace plumb
