// What every binding of plumb's Python module shares: the model a call is given, the CLI's
// vocabulary for keyword arguments, plumb's errors as Python exceptions, long calls that
// release the GIL and stop on Ctrl-C, and the JSON and HTML every result offers.
//
// Each binding file (checks.cc, run.cc, batch.cc, identify.cc, rehearse.cc) registers its
// functions and result types with one Bind* function that module.cc calls.

#ifndef PLUMB_PYTHON_SRC_COMMON_H_
#define PLUMB_PYTHON_SRC_COMMON_H_

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/shared_ptr.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <chrono>
#include <condition_variable>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include "io/output_path.h"
#include "plumb/check.h"
#include "plumb/error.h"
#include "plumb/keyframe.h"
#include "plumb/model.h"
#include "plumb/notice.h"
#include "plumb/path.h"
#include "plumb/report.h"
#include "plumb/stop.h"

// An argument that takes several Python types: `Name` holds the object as given, and the
// function that converts it (ToModel, SetTexts, ...) raises TypeError naming the argument for a
// wrong one. `annotation` is what the stubs (_plumb.pyi) show for it. Use at global scope.
#define PLUMB_PYTHON_ARG(Name, annotation)                                                    \
  namespace plumb::python {                                                                   \
  struct Name {                                                                               \
    nanobind::handle object;                                                                  \
  };                                                                                          \
  }                                                                                           \
  namespace nanobind::detail {                                                                \
  template <>                                                                                 \
  struct type_caster<plumb::python::Name> {                                                   \
    NB_TYPE_CASTER(plumb::python::Name, const_name(annotation))                               \
    bool from_python(handle src, uint8_t, cleanup_list*) noexcept {                           \
      value.object = src;                                                                     \
      return true;                                                                            \
    }                                                                                         \
    static handle from_cpp(const plumb::python::Name& v, rv_policy, cleanup_list*) noexcept { \
      return v.object.inc_ref();                                                              \
    }                                                                                         \
  };                                                                                          \
  }

PLUMB_PYTHON_ARG(ModelArg, "Model | mujoco.MjModel | str | os.PathLike[str]")
// {"PATH": value} | ["PATH=VALUE", ...] | "PATH=VALUE" (or None)
PLUMB_PYTHON_ARG(SetArg,
                 "collections.abc.Mapping[str, float | str | collections.abc.Sequence["
                 "float]] | collections.abc.Sequence[str] | str")
PLUMB_PYTHON_ARG(StringsArg, "str | collections.abc.Sequence[str]")  // "text" | ["text", ...]
PLUMB_PYTHON_ARG(FileArg, "str | os.PathLike[str]")
PLUMB_PYTHON_ARG(QposArg,
                 "str | collections.abc.Sequence[float]")  // nq numbers: "0.1 0.2" | [0.1, 0.2]

// A keyframe or camera by its name (str) or its id (int): `text` is what the library takes,
// "#2" for id 2. Converts to std::string, so std::optional<NameOrId> passes as an optional name.
namespace plumb::python {
struct NameOrId {
  std::string text;
  operator const std::string&() const { return text; }  // NOLINT: converts on purpose
};
}  // namespace plumb::python
namespace nanobind::detail {
template <>
struct type_caster<plumb::python::NameOrId> {
  NB_TYPE_CASTER(plumb::python::NameOrId, const_name("str | int"))
  bool from_python(handle src, uint8_t, cleanup_list*) noexcept {
    if (PyUnicode_Check(src.ptr())) {
      Py_ssize_t size = 0;
      const char* text = PyUnicode_AsUTF8AndSize(src.ptr(), &size);
      if (text == nullptr) {
        PyErr_Clear();
        return false;
      }
      value.text.assign(text, static_cast<std::size_t>(size));
      return true;
    }
    if (PyLong_Check(src.ptr()) && !PyBool_Check(src.ptr())) {
      long long id = PyLong_AsLongLong(src.ptr());
      if (id == -1 && PyErr_Occurred()) {
        PyErr_Clear();
        return false;
      }
      value.text = "#" + std::to_string(id);
      return true;
    }
    return false;
  }
  static handle from_cpp(const plumb::python::NameOrId& v, rv_policy, cleanup_list*) noexcept {
    return PyUnicode_FromStringAndSize(v.text.data(), static_cast<Py_ssize_t>(v.text.size()));
  }
};
}  // namespace nanobind::detail

namespace plumb::python {

namespace nb = nanobind;

// plumb.Model: a compiled model and the start it was loaded with (a keyframe, then `set`
// assignments). Made from a path (plumb owns the model) or from a mujoco.MjModel, which it
// wraps without copying and keeps alive; nothing plumb does changes the caller's MjModel
// (calls that edit parameters work on a copy).
class PyModel {
 public:
  PyModel(std::shared_ptr<Model> model, nb::object mjmodel, std::string keyframe,
          std::vector<std::string> sets);

  const Model& model() const { return *model_; }
  // The caller's mujoco.MjModel this wraps, or None for a model plumb loaded.
  const nb::object& mjmodel() const { return mjmodel_; }
  const std::string& keyframe() const { return keyframe_; }
  const std::vector<std::string>& sets() const { return sets_; }
  // The file it came from, or "<MjModel 'NAME'>" for a wrapped MjModel.
  const std::string& name() const { return model_->file(); }

  // What a call starts from, in the CLI's words: the call's keyframe (else the load's), its
  // pose file and whole qpos, then the load's `set` and the call's (`more`, "PATH=VALUE").
  StartSpec Spec(const std::optional<std::string>& keyframe = std::nullopt,
                 const std::string& pose = "", const std::string& qpos = "",
                 const std::vector<std::string>& more = {}) const;
  // Its assignments, in the order a run applies them (StartAssignments); their warnings go to
  // `notices` (a call's CallNotices::sink(): plumb.StartWarning, "set 'ctrl[hip]=5': ...").
  // @throws PathError / ArgumentError / ValueError for what the model refuses.
  std::vector<Assignment> Start(const std::vector<std::string>& more = {},
                                Notices* notices = nullptr) const {
    return StartAssignments(*model_, Spec(std::nullopt, "", "", more), notices);
  }
  // The keyframe and every `set` text, in order (the CLI's --keyframe and --set words).
  std::vector<std::string> SetTexts(const std::vector<std::string>& more = {}) const;

  // A model the call may edit: a copy when any of `assignments` changes a model array (the
  // caller's MjModel stays as it was), else this model (shared, read only).
  std::shared_ptr<Model> EditableFor(const std::vector<Assignment>& assignments) const;
  std::shared_ptr<Model> shared() const { return model_; }

 private:
  std::shared_ptr<Model> model_;
  nb::object mjmodel_;
  std::string keyframe_;
  std::vector<std::string> sets_;
};

// A call's `model` argument: a plumb.Model, a mujoco.MjModel (wrapped, not copied) or a path
// (str or os.PathLike). What loading a path says (plumb/load.h: MuJoCo's compiler warnings, a
// shortened delay; for a wrapped MjModel the shortened delays only) goes to `notices`, the
// call's CallNotices::sink(), or is issued at once (plumb.CompileWarning) when it is null.
// @throws LoadError for a path that does not load; TypeError otherwise.
std::shared_ptr<PyModel> ToModel(nb::handle model, Notices* notices = nullptr);
inline std::shared_ptr<PyModel> ToModel(ModelArg model, Notices* notices = nullptr) {
  return ToModel(model.object, notices);
}

// A `set` argument in the CLI's vocabulary: None, {"qpos[hinge]": 0.7, "opt.gravity":
// [0, 0, -1.62], "opt.integrator": "RK4"}, or a list of "PATH=VALUE" strings. Values are
// written with 17 significant digits, so a float goes over exactly. TypeError naming `set`
// for anything else (bytes, a list of non-strings).
std::vector<std::string> SetTexts(nb::handle set);
// A `qpos` argument as QposAssignment reads it: the text as given, or the numbers joined by
// commas (each in its shortest exact form); "" for None.
std::string QposText(QposArg qpos);
inline std::vector<std::string> SetTexts(SetArg set) { return SetTexts(set.object); }
// A list argument that also takes one string (randomize="body_mass[*]=*U(0.9,1.1)").
// TypeError naming `argument` for anything else (bytes, a number, a list of non-strings).
std::vector<std::string> StringList(nb::handle value, const char* argument);
inline std::vector<std::string> StringList(StringsArg value, const char* argument) {
  return StringList(value.object, argument);
}

// A result's HTML page: the whole report (save_report, html()), or the light view a notebook
// shows by default (_repr_html_): the same page with one picture, the start, and no animation.
enum class ReportView { kFull, kLight };

// What a report from Python shows as its command line: "python plumb.CALL(...)". Pages that
// draw no model pictures of their own (run, inspect, render) pass `pictures` false.
ReportInfo PythonReportInfo(const char* call, bool pictures = true,
                            ReportView view = ReportView::kFull);

// The JSON text as Python objects (json.loads).
nb::object FromJson(const std::string& json);

// The HTML document `write` writes to the path it is given (a report writer), as a string.
// The file lives in a temporary folder that is removed afterwards.
std::string ReportHtml(const std::function<void(const std::string& path)>& write);

// The check rows as a list of plumb.CheckRow.
nb::list RowList(const std::vector<CheckRow>& rows);
// The pandas module; ImportError naming pip when it is not installed (plumb never needs it
// but for to_pandas()).
nb::object Pandas();
// A pandas.DataFrame of `columns` (name, array-like); ImportError naming pip when pandas is
// not installed.
nb::object DataFrame(const std::vector<std::pair<std::string, nb::object>>& columns);
// A 1-D float64 numpy array holding a copy of `values`.
nb::object Array(const std::vector<double>& values);
// A numpy array of `shape` (C order) that takes over `values` without copying.
template <typename T>
nb::object OwnedArray(std::vector<T>&& values, const std::vector<std::size_t>& shape) {
  auto* owned = new std::vector<T>(std::move(values));
  nb::capsule owner(owned, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
  return nb::cast(nb::ndarray<nb::numpy, T>(owned->data(), shape.size(), shape.data(), owner));
}
// One number of every item (a field of each level, fit or estimate), in order, as a 1-D float64
// numpy array.
template <typename Item>
nb::object FieldArray(const std::vector<Item>& items, double Item::*field) {
  std::vector<double> values;
  values.reserve(items.size());
  for (const Item& item : items) values.push_back(item.*field);
  return OwnedArray(std::move(values), {items.size()});
}
// A rows x cols float64 numpy array that takes over `values` (row major) without copying.
inline nb::object Matrix(std::vector<double>&& values, std::size_t rows, std::size_t cols) {
  return OwnedArray(std::move(values), {rows, cols});
}

// Runs `body(token)` on a thread of its own while the calling thread waits without the GIL,
// so other Python threads run. Every 20 ms the caller checks for signals (PyErr_CheckSignals:
// Ctrl-C on the main thread); when one raised, it asks `body` to stop through its token,
// waits for it (a rollout or sweep keeps what it finished) and raises the signal's exception
// (KeyboardInterrupt; when `body` ended in Interrupted, with its message). `body` runs inside
// a MujocoCallScope; what it throws is rethrown here.
template <typename Body>
auto RunLong(Body&& body) -> decltype(body(StopToken{})) {
  using Result = decltype(body(StopToken{}));
  StopSource source;
  std::optional<Result> result;
  std::exception_ptr error;
  bool done = false, signalled = false;
  std::mutex mutex;
  std::condition_variable finished;
  {
    nb::gil_scoped_release release;
    std::thread worker([&] {
      try {
        MujocoCallScope scope;
        result.emplace(body(source.token()));
      } catch (...) {
        error = std::current_exception();
      }
      std::lock_guard<std::mutex> lock(mutex);
      done = true;
      finished.notify_all();
    });
    for (;;) {
      {
        std::unique_lock<std::mutex> lock(mutex);
        if (finished.wait_for(lock, std::chrono::milliseconds(20), [&] { return done; })) break;
      }
      if (!signalled) {
        nb::gil_scoped_acquire acquire;
        if (PyErr_CheckSignals() != 0) {
          signalled = true;
          source.RequestStop();
        }
      }
    }
    worker.join();
  }
  if (signalled) {
    nb::python_error raised;  // the signal handler's exception
    // a KeyboardInterrupt that stopped a batch carries what the batch says of it (Interrupted)
    if (error && raised.matches(PyExc_KeyboardInterrupt)) {
      try {
        std::rethrow_exception(error);
      } catch (const Interrupted&) {
        throw;
      } catch (...) {
      }
    }
    throw raised;
  }
  if (error) std::rethrow_exception(error);
  return std::move(*result);
}

// The notices of one call (plumb/notice.h): give sink() to the library call; when the call
// returns, Issue() hands each notice to Python's `warnings` with plumb's class for its topic
// (plumb.CompileWarning, plumb.StartWarning, plumb.LogWarning, plumb.BatchWarning,
// plumb.ModelWarning, else plumb.PlumbWarning; all subclasses of plumb.PlumbWarning, a
// UserWarning), its message Notice::Line(), and all() keeps them for the result's `.notices`
// (a result struct's `std::vector<Notice> notices`, which AddResultMethods binds).
// A notice added while the call runs on another thread (RunLong) waits for Issue(), which
// needs the GIL. Notices not issued when this is destroyed (the call raised) are issued then,
// so a warning that came before an error is still heard; a warning filter that turns one into
// an error then is dropped, as the call's own error stands.
class CallNotices {
 public:
  CallNotices() = default;
  CallNotices(const CallNotices&) = delete;
  CallNotices& operator=(const CallNotices&) = delete;
  ~CallNotices();

  Notices* sink() { return &notices_; }
  // Issues the notices not issued yet. @throws nb::python_error when a warning filter turned
  // one into an error (warnings.simplefilter("error")).
  void Issue();
  std::vector<Notice> all() const { return notices_.all(); }

 private:
  Notices notices_;
  std::size_t issued_ = 0;
};

// Issues `notice` through Python's `warnings` (the GIL held). @throws nb::python_error when a
// warning filter turned it into an error.
void IssueNotice(const Notice& notice);

// A file argument: str or os.PathLike (pathlib.Path) whose os.fspath is a str. TypeError
// naming `argument` for anything else (bytes, a list, a number); plumb.ArgumentError for a
// path with a NUL character, which no file has.
std::string PathArg(nb::handle path, const char* argument);
inline std::string PathArg(FileArg path, const char* argument) {
  return PathArg(path.object, argument);
}
// A file argument that may be None: "" for None.
std::string OptionalPathArg(const std::optional<FileArg>& path, const char* argument);

// The files a result was made from, which its save_report must not replace (io/output_path.h):
// the model's file; a result that read more files (logs) gives them with an overload of its own.
template <typename Result>
std::vector<internal::NamedPath> ResultInputs(const Result& r) {
  return {{"the model", r.model->name()}};
}

// Whether a result struct keeps its call's notices (`std::vector<Notice> notices`).
template <typename Result, typename = void>
struct HasNotices : std::false_type {};
template <typename Result>
struct HasNotices<Result, std::void_t<decltype(std::declval<const Result&>().notices)>>
    : std::true_type {};

// A result's JSON document: Json(), with "notices" when the result keeps them, as the CLI's
// --format json carries the command's (JsonWithNotices).
template <typename Result>
std::string ResultJson(const Result& r) {
  if constexpr (HasNotices<Result>::value) {
    return JsonWithNotices(r.Json(), r.notices);
  } else {
    return r.Json();
  }
}

// Whether a result's report has a light view: `void WriteReport(path, ReportView) const` and
// `std::string full_html` beside `html` (the light page).
template <typename Result, typename = void>
struct HasLightView : std::false_type {};
template <typename Result>
struct HasLightView<Result, std::void_t<decltype(std::declval<const Result&>().WriteReport(
                                            std::string(), ReportView::kLight)),
                                        decltype(std::declval<Result&>().full_html)>>
    : std::true_type {};

// The result's report page as text, made once and kept on the result: the whole report
// (`full`) or, for a result with a light view, that view.
template <typename Result>
const std::string& ResultHtml(Result& r, bool full) {
  if constexpr (HasLightView<Result>::value) {
    std::string& page = full ? r.full_html : r.html;
    if (page.empty()) {
      ReportView view = full ? ReportView::kFull : ReportView::kLight;
      page = RunLong([&](StopToken) {
        return ReportHtml([&](const std::string& path) { r.WriteReport(path, view); });
      });
    }
    return page;
  } else {
    (void)full;
    if (r.html.empty()) {
      r.html = RunLong([&](StopToken) {
        return ReportHtml([&](const std::string& path) { r.WriteReport(path); });
      });
    }
    return r.html;
  }
}

// Writes `html` to `path` whole or not at all (io/atomic_file.h).
void WriteHtml(const std::string& path, const std::string& html);

// .notices of a result type that keeps them: a list of plumb.Notice.
template <typename Result>
void AddNoticesProperty(nb::class_<Result>& type) {
  type.def_ro("notices", &Result::notices,
              "what the call said besides its result (each also issued as a plumb.PlumbWarning "
              "subclass): a list of plumb.Notice");
}

// The methods every result type has, made from what its struct provides:
//   std::string Json() const;                          the CLI's --format json document
//   std::string Table() const;                         the CLI's table text
//   void WriteReport(const std::string& path) const;   the CLI's --report HTML
//   std::string html;                                  the report, kept once made
//   std::vector<Notice> notices;                       (optional) the call's notices
// to_json(), to_dict(), save_report(path), _repr_html_() and __repr__; .notices when kept.
template <typename Result>
void AddResultMethods(nb::class_<Result>& type, const char* command) {
  if constexpr (HasNotices<Result>::value) AddNoticesProperty(type);
  type.def("to_json", &ResultJson<Result>,
           (std::string("the JSON document `plumb ") + command + " --format json` prints").c_str())
      .def(
          "to_dict", [](const Result& r) { return FromJson(ResultJson(r)); },
          "to_json() as Python objects (json.loads)")
      .def(
          "save_report",
          [](Result& r, nb::handle path) {
            std::string file = PathArg(path, "path");
            internal::RefuseOutputsOntoInputs({{"path", file}}, ResultInputs(r));
            if constexpr (HasLightView<Result>::value) {
              const std::string& page = ResultHtml(r, true);  // drawn once, kept
              RunLong([&](StopToken) {
                WriteHtml(file, page);
                return 0;
              });
            } else {
              RunLong([&](StopToken) {
                r.WriteReport(file);
                return 0;
              });
            }
          },
          nb::arg("path"),
          (std::string("writes the self-contained HTML report (`plumb ") + command +
           " --report FILE.html`): whole or not at all; drawn once, then kept on the result")
              .c_str())
      .def(
          "html", [](Result& r, bool full) { return ResultHtml(r, full); },
          nb::arg("full") = true,
          "the HTML report as text (full=False: the light view a notebook shows), drawn once "
          "and kept on the result")
      .def(
          "_repr_html_", [](Result& r) { return ResultHtml(r, false); },
          HasLightView<Result>::value
              ? "the light view a notebook shows inline: the page with one picture, the start "
                "(html() is the whole report, with the run's pictures and animation)"
              : "the HTML report, which a notebook shows inline")
      .def("__repr__", &Result::Table);
}

// Registers plumb's exceptions (plumb.Error and its subclasses) and their translation.
void BindErrors(nb::module_& m);
// plumb.Model, plumb.load, plumb.CheckRow.
void BindCore(nb::module_& m);
// verify, audit, converge, snapshot, diff (checks.cc).
void BindChecks(nb::module_& m);
// run, inspect (run.cc).
void BindRun(nb::module_& m);
// render (render.cc).
void BindRender(nb::module_& m);
// sweep, rollout (batch.cc).
void BindBatch(nb::module_& m);
// replay, identify (identify.cc).
void BindIdentify(nb::module_& m);
// rehearse (rehearse.cc). After BindErrors: its RehearsalFailed is a plumb.Error.
void BindRehearse(nb::module_& m);

}  // namespace plumb::python

#endif  // PLUMB_PYTHON_SRC_COMMON_H_
