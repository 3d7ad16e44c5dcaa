// Ownership of MuJoCo's mjModel and mjData.
//
// plumb::Model and plumb::Data are move-only RAII owners: the MuJoCo objects they hold
// are freed exactly once, data before model as MuJoCo requires. Loading never calls
// exit(): plumb installs MuJoCo error/warning handlers the first time any of these
// types is used, turning mju_error into plumb::MujocoError and collecting warnings
// (see TakeMujocoWarnings) instead of printing them.
//
// Example:
//   plumb::Model model = plumb::Model::Load("models/pendulum.xml");
//   plumb::Data data(model);
//   data->qpos[0] = 0.7;
//   data.Forward();
//   while (data->time < 2.0) data.Step();
//
// A Data keeps a pointer to the Model it was made from: a Data must never outlive its
// Model, and the Model must not be moved while a Data made from it is alive.

#ifndef PLUMB_INCLUDE_PLUMB_MODEL_H_
#define PLUMB_INCLUDE_PLUMB_MODEL_H_

#include <mujoco/mujoco.h>

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace plumb {

// A compiled MuJoCo model. Thread-safety: const methods may be called concurrently;
// loading is serialised internally because MuJoCo's XML loader keeps global state.
class Model {
 public:
  // Loads an MJCF (.xml) or binary (.mjb) model from `path`.
  // @throws LoadError with the file name and MuJoCo's complete error text, plus a hint
  //         for known pitfalls, when the file is missing or fails to compile.
  static Model Load(const std::string& path);

  // Compiles MJCF text. `name` is used in error messages only. Relative asset paths
  // resolve against the current directory.
  // @throws LoadError as Load does.
  static Model FromXmlString(std::string_view xml, std::string_view name = "<string>");

  // Wraps a model someone else owns (the `mujoco` Python package's MjModel) without copying
  // it: `m` is never freed here and must outlive the returned Model and everything made from
  // it. `name` stands for the file in messages and results. Clone() makes an owned copy.
  static Model Borrow(mjModel* m, std::string name);
  // Whether this Model owns its mjModel (false for Borrow).
  bool owned() const { return m_.get_deleter().owned; }

  Model(Model&&) noexcept;
  Model& operator=(Model&&) noexcept;
  Model(const Model&) = delete;
  Model& operator=(const Model&) = delete;
  ~Model();

  // Returns an independent deep copy (mj_copyModel). @throws MujocoError.
  Model Clone() const;

  const mjModel* get() const { return m_.get(); }
  mjModel* get_mutable() { return m_.get(); }
  const mjModel* operator->() const { return m_.get(); }

  // The file this model was loaded from ("<string>" style name for FromXmlString).
  const std::string& file() const { return file_; }

  // The MJCF text a model made by FromXmlString was compiled from ("" for a model loaded from
  // a file, whose text is the file's).
  const std::string& xml_text() const;

  // Text MuJoCo's compiler left in the error buffer although it succeeded (compile
  // warnings); empty when it had nothing to say.
  const std::string& compile_warnings() const { return compile_warnings_; }

  // Writes the model as MJCF with mj_saveLastXML, including runtime edits that
  // MuJoCo can express (it does not write an edited body_mass). Only possible for
  // models loaded from XML. @throws IoError when the file cannot be written or the
  // model did not come from XML.
  void SaveXml(const std::string& path) const;

  // Whether this model was compiled from an MJCF file by Load (file() is that file): false for
  // a .mjb file, FromXmlString and Borrow.
  bool from_xml_file() const { return xml_load_id_ != 0 && !xml_source_; }

  // For a model without an MJCF file of its own (Borrow: the Python package's mujoco.MjModel):
  // writes the XML MuJoCo parsed last, whoever parsed it, with this model's values
  // (mj_saveLastXML) to `path`. False, with `reason` set, when MuJoCo has parsed no XML or the
  // last one has other sizes; the caller checks that it names the same elements.
  bool SaveLastXml(const std::string& path, std::string* reason) const;

  // Writes the exact compiled model, edits included, as a binary .mjb file.
  // @throws IoError when the file cannot be written.
  void SaveBinary(const std::string& path) const;

  // Name of element `id` of MuJoCo object type `type` (mjOBJ_BODY, ...), or "" when
  // it has none.
  std::string Name(int type, int id) const;

 private:
  struct Deleter {
    bool owned;  // false for Borrow
    void operator()(mjModel* m) const;
  };
  Model(mjModel* m, std::string file);

  std::unique_ptr<mjModel, Deleter> m_;
  std::string file_;
  std::string compile_warnings_;
  // The XML text the model was compiled from (empty for .mjb), so SaveXml can
  // re-parse it when MuJoCo's global "last XML" belongs to another model.
  std::shared_ptr<const std::string> xml_source_;
  std::uint64_t xml_load_id_ = 0;
};

// One simulation instance of a Model (MuJoCo's mjData).
class Data {
 public:
  // Allocates data for `model` and resets it to qpos0. @throws MujocoError.
  explicit Data(const Model& model);
  // Data keeps a pointer to its model: a temporary model would dangle.
  explicit Data(Model&&) = delete;

  Data(Data&&) noexcept;
  Data& operator=(Data&&) noexcept;
  Data(const Data&) = delete;
  Data& operator=(const Data&) = delete;
  ~Data();

  // Returns an independent copy of the whole data (mj_copyData). @throws MujocoError when
  // MuJoCo cannot allocate it.
  Data Clone() const;

  mjData* get() { return d_.get(); }
  const mjData* get() const { return d_.get(); }
  mjData* operator->() { return d_.get(); }
  const mjData* operator->() const { return d_.get(); }
  const mjModel* model() const { return m_; }

  // mj_resetData: time 0, qpos = qpos0, zero velocities, controls and warnings.
  void Reset();
  // mj_forward: recomputes every derived quantity from the state without advancing time,
  // including those MuJoCo computes only on request (energy without
  // <flag energy="enable"/>, cacc, cfrc_int, cfrc_ext, subtree_linvel, subtree_angmom).
  // @throws MujocoError.
  void Forward();
  // mj_step: advances the state by one timestep. @throws MujocoError.
  void Step();

 private:
  struct Deleter {
    void operator()(mjData* d) const;
  };
  Data(const mjModel* m, mjData* d);

  const mjModel* m_;
  std::unique_ptr<mjData, Deleter> d_;
};

// Returns and clears the MuJoCo warning messages raised on the calling thread since
// the last call (MuJoCo passes each warning kind's first occurrence to its handler).
std::vector<std::string> TakeMujocoWarnings();

// Installs plumb's MuJoCo error and warning handlers (idempotent; Model and Data do it
// themselves). Also checks that the MuJoCo library matches the headers plumb was built
// with. @throws Error when it does not.
void InstallMujocoHandlers();

// How plumb's MuJoCo handlers are installed.
//   kProcess (the default; programs of their own, the plumb command): once, for the whole
//     process, with every plugin library beside MuJoCo loaded.
//   kAroundCalls (plumb inside a process that uses MuJoCo too: the Python module beside the
//     `mujoco` package): only while a MujocoCallScope is alive on some thread, and then only
//     for threads inside one. A MuJoCo error or warning on any other thread goes to the
//     handler that was there before (the `mujoco` package's, raising mujoco.FatalError). No
//     plugin library is loaded: the other user of MuJoCo loads its own.
// Set it before the first Model is made. Thread-safety: not synchronised with calls.
enum class MujocoHandlerMode { kProcess, kAroundCalls };
void SetMujocoHandlerMode(MujocoHandlerMode mode);

// Marks the calling thread as running plumb's code for its lifetime (scopes nest), and in
// kAroundCalls mode installs plumb's handlers while any scope is alive. plumb's worker
// threads hold one per job; a caller in kAroundCalls mode holds one around each call.
class MujocoCallScope {
 public:
  MujocoCallScope();
  ~MujocoCallScope();
  MujocoCallScope(const MujocoCallScope&) = delete;
  MujocoCallScope& operator=(const MujocoCallScope&) = delete;
};

// "2.2.2"-style version of the MuJoCo library in use.
std::string MujocoVersion();

// The MuJoCo version plumb was compiled against ("4.0.1"), from mjVERSION_HEADER.
std::string CompiledMujocoVersion();

// The file of the MuJoCo library loaded into this process, or "" if it cannot be told.
std::string MujocoLibraryPath();

// The folder plumb loads MuJoCo's plugin libraries from: $PLUMB_MUJOCO_PLUGIN_PATH, else
// bin/mujoco_plugin of the release folder the loaded library sits in (lib/../bin/
// mujoco_plugin), else lib/mujoco_plugin beside it (an installed plumb), else plugin/ beside
// it (the mujoco-core wheel's layout, which plumb's wheel uses); "" when none exists (and
// always on MuJoCo 2.x, which has no plugins). An empty PLUMB_MUJOCO_PLUGIN_PATH counts as
// unset. @throws ValueError naming PLUMB_MUJOCO_PLUGIN_PATH when it is set to what is not a
// folder (MuJoCo would skip it silently; the first model load then fails with this, exit 2).
std::string MujocoPluginPath();

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_MODEL_H_
