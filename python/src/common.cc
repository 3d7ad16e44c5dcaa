#include "common.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "io/atomic_file.h"
#include "io/temp_file.h"
#include "plumb/error.h"
#include "plumb/keyframe.h"
#include "plumb/load.h"

namespace plumb::python {
namespace {

// The exception classes, made once by BindErrors (module state lives as long as the module).
struct ErrorTypes {
  PyObject* error = nullptr;
  PyObject* load = nullptr;
  PyObject* path = nullptr;
  PyObject* value = nullptr;
  PyObject* argument = nullptr;
  PyObject* mujoco = nullptr;
  PyObject* io = nullptr;
  PyObject* unavailable = nullptr;
  PyObject* engine = nullptr;
  PyObject* engine_refused = nullptr;
  PyObject* internal = nullptr;
};
ErrorTypes g_errors;

// The warning classes, one per notice topic (plumb/notice.h), made once by BindErrors.
struct WarningTypes {
  PyObject* base = nullptr;  // plumb.PlumbWarning, for kOther
  PyObject* compile = nullptr;
  PyObject* start = nullptr;
  PyObject* log = nullptr;
  PyObject* batch = nullptr;
  PyObject* model = nullptr;
};
WarningTypes g_warnings;

PyObject* WarningType(NoticeTopic topic) {
  switch (topic) {
    case NoticeTopic::kCompile: return g_warnings.compile;
    case NoticeTopic::kStart: return g_warnings.start;
    case NoticeTopic::kLog: return g_warnings.log;
    case NoticeTopic::kBatch: return g_warnings.batch;
    case NoticeTopic::kModel: return g_warnings.model;
    case NoticeTopic::kOther: break;
  }
  return g_warnings.base;
}

// Raises `type`(message) with the given attributes set on the instance.
void Raise(PyObject* type, const char* message,
           const std::vector<std::pair<const char*, std::string>>& attributes = {}) {
  nb::object instance = nb::steal(PyObject_CallFunction(type, "s", message));
  if (!instance.is_valid()) return;  // the call raised; that error stands
  for (const auto& [name, value] : attributes) instance.attr(name) = nb::str(value.c_str());
  PyErr_SetObject(type, instance.ptr());
}

PyObject* NewError(nb::module_& m, const char* name, nb::handle bases, const char* doc) {
  std::string full = std::string("plumb.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(full.c_str(), doc, bases.ptr(), nullptr);
  if (type == nullptr) throw nb::python_error();
  m.attr(name) = nb::borrow(type);
  return type;
}

// The Python type of `value`, for a TypeError: "bytes", "list", ...
std::string TypeName(nb::handle value) { return nb::type_name(value.type()).c_str(); }

// bytes or bytearray, which plumb never takes for text or paths
bool IsBytes(nb::handle value) {
  return PyBytes_Check(value.ptr()) || PyByteArray_Check(value.ptr());
}

// What a TypeError adds for bytes.
std::string BytesAdvice(nb::handle value) {
  return IsBytes(value)
             ? " (decode bytes first: os.fsdecode(value) for a path, value.decode() for text)"
             : "";
}

std::string ValueText(nb::handle value, const char* argument) {
  if (nb::isinstance<nb::str>(value)) return nb::cast<std::string>(value);
  if (IsBytes(value)) {
    throw nb::type_error(fmt::format("{}: a value must be a number, a string or a sequence of "
                                     "numbers, not {}{}",
                                     argument, TypeName(value), BytesAdvice(value))
                             .c_str());
  }
  if (nb::isinstance<nb::bool_>(value)) return nb::cast<bool>(value) ? "1" : "0";
  // a sequence of numbers (opt.gravity, a free joint's qpos, a numpy array): comma separated
  if (nb::hasattr(value, "__iter__") &&
      !(nb::hasattr(value, "ndim") && value.attr("ndim").equal(nb::int_(0)))) {
    std::string out;
    for (nb::handle item : value) {
      if (!out.empty()) out += ",";
      out += ValueText(item, argument);
    }
    return out;
  }
  if (PyIndex_Check(value.ptr())) return nb::str(nb::int_(value)).c_str();  // int, numpy ints
  if (PyNumber_Check(value.ptr()) && nb::hasattr(value, "__float__")) {
    // the shortest text that reads back as the same double (Python's repr): 0.7 is "0.7", as
    // the command line's --set takes it, so both name the same stored batch
    return nb::cast<std::string>(nb::repr(nb::float_(value)));
  }
  throw nb::type_error(fmt::format("{}: a value must be a number, a string or a sequence of "
                                   "numbers, not {}",
                                   argument, TypeName(value))
                           .c_str());
}

}  // namespace

PyModel::PyModel(std::shared_ptr<Model> model, nb::object mjmodel, std::string keyframe,
                 std::vector<std::string> sets)
    : model_(std::move(model)),
      mjmodel_(std::move(mjmodel)),
      keyframe_(std::move(keyframe)),
      sets_(std::move(sets)) {}

StartSpec PyModel::Spec(const std::optional<std::string>& keyframe, const std::string& pose,
                        const std::string& qpos, const std::vector<std::string>& more) const {
  return {keyframe.value_or(keyframe_), pose, qpos, SetTexts(more)};
}

std::vector<std::string> PyModel::SetTexts(const std::vector<std::string>& more) const {
  std::vector<std::string> out = sets_;
  out.insert(out.end(), more.begin(), more.end());
  return out;
}

std::shared_ptr<Model> PyModel::EditableFor(const std::vector<Assignment>& assignments) const {
  for (const Assignment& a : assignments) {
    if (a.path.role == Role::kParameter) {
      return std::make_shared<Model>(model_->Clone());
    }
  }
  return model_;
}

std::shared_ptr<PyModel> ToModel(nb::handle model, Notices* notices) {
  if (nb::isinstance<PyModel>(model)) return nb::cast<std::shared_ptr<PyModel>>(model);
  CallNotices own;  // issued at once when the caller gives no sink of its own
  if (notices == nullptr) notices = own.sink();
  nb::handle type = model.type();
  std::string type_name = nb::type_name(type).c_str();
  if (type_name == "mujoco._structs.MjModel" || type_name == "MjModel") {
    auto address = nb::cast<std::uintptr_t>(model.attr("_address"));
    auto* m = reinterpret_cast<mjModel*>(address);
    std::string name = fmt::format("<MjModel '{}'>", m->nnames > 0 ? m->names : "");
    MujocoCallScope scope;
    auto borrowed = std::make_shared<Model>(Model::Borrow(m, name));
    AddModelNotices(*borrowed, name, notices);
    own.Issue();
    return std::make_shared<PyModel>(std::move(borrowed), nb::borrow(model), "",
                                     std::vector<std::string>{});
  }
  if (nb::isinstance<nb::str>(model) || nb::hasattr(model, "__fspath__")) {
    std::string path = PathArg(model, "model");
    std::shared_ptr<Model> loaded;
    {
      nb::gil_scoped_release release;
      MujocoCallScope scope;
      loaded = std::make_shared<Model>(LoadModel(path, notices));
    }
    own.Issue();
    return std::make_shared<PyModel>(std::move(loaded), nb::none(), "", std::vector<std::string>{});
  }
  throw nb::type_error(fmt::format("model: expected a plumb.Model, a mujoco.MjModel or a path "
                                   "to an MJCF or .mjb file, not {}",
                                   type_name)
                           .c_str());
}

std::vector<std::string> SetTexts(nb::handle set) {
  std::vector<std::string> out;
  if (set.is_none()) return out;
  if (nb::isinstance<nb::str>(set)) return {nb::cast<std::string>(set)};
  if (nb::isinstance<nb::dict>(set)) {
    for (auto [key, value] : nb::borrow<nb::dict>(set)) {
      out.push_back(nb::cast<std::string>(nb::str(key)) + "=" + ValueText(value, "set"));
    }
    return out;
  }
  if (!IsBytes(set) && nb::hasattr(set, "__iter__")) {
    for (nb::handle item : set) {
      if (!nb::isinstance<nb::str>(item)) {
        throw nb::type_error(fmt::format("set: each item of a list must be a 'PATH=VALUE' "
                                         "string, not {}{}",
                                         TypeName(item), BytesAdvice(item))
                                 .c_str());
      }
      out.push_back(nb::cast<std::string>(item));
    }
    return out;
  }
  throw nb::type_error(fmt::format("set: expected a dict {{PATH: value}}, a list of "
                                   "'PATH=VALUE' strings or one such string, not {}{}",
                                   TypeName(set), BytesAdvice(set))
                           .c_str());
}

std::string QposText(QposArg qpos) {
  if (qpos.object.is_none()) return "";
  if (nb::isinstance<nb::str>(qpos.object)) return nb::cast<std::string>(qpos.object);
  if (IsBytes(qpos.object) || !nb::hasattr(qpos.object, "__iter__")) {
    throw nb::type_error(fmt::format("qpos: expected a string of nq numbers or a sequence of "
                                     "numbers, not {}{}",
                                     TypeName(qpos.object), BytesAdvice(qpos.object))
                             .c_str());
  }
  std::string text;
  for (nb::handle v : qpos.object) text += (text.empty() ? "" : ",") + ValueText(v, "qpos");
  return text;
}

std::vector<std::string> StringList(nb::handle value, const char* argument) {
  std::vector<std::string> out;
  if (value.is_none()) return out;
  if (nb::isinstance<nb::str>(value)) return {nb::cast<std::string>(value)};
  auto refuse = [&](nb::handle wrong, const char* what) {
    return nb::type_error(fmt::format("{}: expected a string or a list of strings, {}{}{}",
                                      argument, what, TypeName(wrong), BytesAdvice(wrong))
                              .c_str());
  };
  if (IsBytes(value) || !nb::hasattr(value, "__iter__")) {
    throw refuse(value, "not ");
  }
  for (nb::handle item : value) {
    if (!nb::isinstance<nb::str>(item)) throw refuse(item, "not a list holding ");
    out.push_back(nb::cast<std::string>(item));
  }
  return out;
}

std::string PathArg(nb::handle path, const char* argument) {
  nb::object text;
  if (nb::isinstance<nb::str>(path)) {
    text = nb::borrow(path);
  } else if (!nb::isinstance<nb::type_object>(path) && nb::hasattr(path, "__fspath__")) {
    text = path.attr("__fspath__")();  // what os.fspath calls: a str, or bytes
  }
  if (!text.is_valid() || !nb::isinstance<nb::str>(text)) {
    nb::handle wrong = text.is_valid() ? nb::handle(text) : path;
    throw nb::type_error(fmt::format("{}: expected a path, a str or an os.PathLike such as "
                                     "pathlib.Path, not {}{}",
                                     argument, TypeName(wrong), BytesAdvice(wrong))
                             .c_str());
  }
  std::string out = nb::cast<std::string>(text);
  if (out.find('\0') != std::string::npos) {
    throw ArgumentError(argument, out.substr(0, out.find('\0')) + "\\0...",
                        "a path cannot hold a NUL character: no file has one");
  }
  return out;
}

std::string OptionalPathArg(const std::optional<FileArg>& path, const char* argument) {
  return path && !path->object.is_none() ? PathArg(path->object, argument) : std::string();
}

ReportInfo PythonReportInfo(const char* call, bool pictures, ReportView view) {
  ReportInfo info{{"python", fmt::format("plumb.{}(...)", call)}};
  info.pictures = pictures;
  if (view == ReportView::kLight) {
    info.frames = 0;
    info.start_only = true;
  }
  return info;
}

void WriteHtml(const std::string& path, const std::string& html) {
  internal::AtomicFile out(path);
  if (std::fwrite(html.data(), 1, html.size(), out.stream()) != html.size()) {
    throw IoError("cannot write the report to " + Quoted(path) + ": " + std::strerror(errno) +
                  ". Check the disk space and the folder's permissions.");
  }
  out.Commit();
}

nb::object FromJson(const std::string& json) {
  return nb::module_::import_("json").attr("loads")(nb::str(json.c_str(), json.size()));
}

std::string ReportHtml(const std::function<void(const std::string& path)>& write) {
  internal::TempFolder dir("plumb-report", "the report");
  write(dir.File("report.html"));
  std::ifstream in(dir.File("report.html"), std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

nb::list RowList(const std::vector<CheckRow>& rows) {
  nb::list out;
  for (const CheckRow& row : rows) out.append(nb::cast(row));
  return out;
}

nb::object Pandas() {
  try {
    return nb::module_::import_("pandas");
  } catch (const nb::python_error&) {
    throw nb::import_error("to_pandas() needs pandas, which is not installed: pip install pandas");
  }
}

nb::object DataFrame(const std::vector<std::pair<std::string, nb::object>>& columns) {
  nb::dict data;
  for (const auto& [name, values] : columns) data[name.c_str()] = values;
  return Pandas().attr("DataFrame")(data);
}

nb::object Array(const std::vector<double>& values) {
  return OwnedArray(std::vector<double>(values), {values.size()});
}

void IssueNotice(const Notice& notice) {
  // stacklevel 2: the warning points at the user's line that made the plumb call
  if (PyErr_WarnEx(WarningType(notice.topic), notice.Line().c_str(), 2) != 0) {
    throw nb::python_error();
  }
}

void CallNotices::Issue() {
  std::vector<Notice> notices = notices_.all();
  while (issued_ < notices.size()) IssueNotice(notices[issued_++]);
}

CallNotices::~CallNotices() {
  if (issued_ == notices_.all().size()) return;
  nb::gil_scoped_acquire acquire;  // a no-op when the caller holds it, as it does here
  // the call's own error, if one is being raised, is not set in Python yet (nanobind
  // translates it later); a warning filter's error must not be left pending in its place
  try {
    Issue();
  } catch (nb::python_error& e) {
    e.discard_as_unraisable("plumb: a warning filter raised while a plumb call failed");
  }
}

void BindErrors(nb::module_& m) {
  nb::handle builtins = nb::module_::import_("builtins");
  g_warnings.base = NewError(m, "PlumbWarning", PyExc_UserWarning,
                               "Base of every warning, note and hint a plumb call gives (the "
                               "lines the plumb command prints on stderr); the call's result "
                               "keeps them too (.notices).");
  g_warnings.compile = NewError(m, "CompileWarning", g_warnings.base,
                                  "MuJoCo's compiler or loader said something about the model.");
  g_warnings.start = NewError(m, "StartWarning", g_warnings.base,
                                "A start value the model changes (a ctrl outside its ctrlrange, "
                                "which MuJoCo clamps).");
  g_warnings.log = NewError(m, "LogWarning", g_warnings.base,
                              "A robot log: a last line cut short, a column left out.");
  g_warnings.batch = NewError(m, "BatchWarning", g_warnings.base,
                                "A rollout, sweep or identify run: resumed, stopped, cases "
                                "skipped or unmeasured.");
  g_warnings.model = NewError(m, "ModelWarning", g_warnings.base,
                                "The model as a check reads it (a randomized field that "
                                "changes nothing).");
  g_errors.error = NewError(m, "Error", PyExc_Exception,
                            "Base of every error plumb raises for bad input or a failed run: the "
                            "message says what failed, where, and what to do.");
  nb::handle base = g_errors.error;
  g_errors.load = NewError(m, "LoadError", base,
                           "A model file could not be read or compiled (.hint: advice, or '').");
  g_errors.path = NewError(m, "PathError", base,
                           "A path such as qpos[hinge] names nothing in "
                           "the model; the message lists the nearest names.");
  g_errors.value = NewError(m, "ValueError", nb::make_tuple(base, builtins.attr("ValueError")),
                            "A value is unusable (non-numeric, out of range, inconsistent).");
  g_errors.argument = NewError(m, "ArgumentError", g_errors.value,
                               "A keyword argument's value is unusable: .argument names it, "
                               ".value is what was passed, .problem what is wrong.");
  g_errors.mujoco = NewError(m, "MujocoError", base,
                             "MuJoCo stopped a plumb call with a fatal "
                             "error (mju_error).");
  g_errors.io = NewError(m, "IoError", nb::make_tuple(base, builtins.attr("OSError")),
                         "A file could not be written or read.");
  g_errors.unavailable = NewError(m, "UnavailableError", base,
                                  "Something plumb needs from the machine is missing (GL, "
                                  "ffmpeg); the message says how to get it.");
  g_errors.engine = NewError(m, "EngineError", base, "The engine adapter failed.");
  g_errors.engine_refused =
      NewError(m, "EngineRefused", g_errors.engine, "The engine refuses the model or an option.");
  g_errors.internal = NewError(m, "InternalError", builtins.attr("RuntimeError"),
                               "A bug in plumb (a broken internal contract), never bad input.");
  nb::register_exception_translator([](const std::exception_ptr& p, void*) {
    try {
      std::rethrow_exception(p);
    } catch (const Interrupted& e) {
      PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    } catch (const ArgumentError& e) {
      Raise(g_errors.argument, e.what(),
            {{"argument", e.argument()}, {"value", e.value()}, {"problem", e.problem()}});
    } catch (const LoadError& e) {
      Raise(g_errors.load, e.what(), {{"hint", e.hint()}});
    } catch (const PathError& e) {
      Raise(g_errors.path, e.what());
    } catch (const ValueError& e) {
      Raise(g_errors.value, e.what());
    } catch (const MujocoError& e) {
      Raise(g_errors.mujoco, e.what());
    } catch (const IoError& e) {
      Raise(g_errors.io, e.what());
    } catch (const UnavailableError& e) {
      Raise(g_errors.unavailable, e.what());
    } catch (const EngineRefused& e) {
      Raise(g_errors.engine_refused, e.what());
    } catch (const EngineError& e) {
      Raise(g_errors.engine, e.what());
    } catch (const Error& e) {
      Raise(g_errors.error, e.what());
    } catch (const InternalError& e) {
      Raise(g_errors.internal, e.what());
    }
  });
}

void BindCore(nb::module_& m) {
  nb::class_<Notice>(m, "Notice",
                     "What a call said besides its result (a result's .notices): the lines the "
                     "plumb command prints on stderr, each also issued as a plumb.PlumbWarning.")
      .def_prop_ro(
          "level", [](const Notice& n) { return std::string(LevelName(n.level)); },
          "'warning', 'note' or 'hint'")
      .def_prop_ro(
          "topic", [](const Notice& n) { return std::string(TopicName(n.topic)); },
          "'compile', 'start', 'log', 'batch', 'model' or 'other' (the warning class)")
      .def_ro("subject", &Notice::subject, "the file or option it is about, or ''")
      .def_ro("text", &Notice::text)
      .def("__str__", &Notice::Line)
      .def("__repr__", [](const Notice& n) { return "<plumb.Notice " + n.Line() + ">"; });

  nb::enum_<CheckStatus>(m, "Status", "A check row's verdict.")
      .value("PASS", CheckStatus::kPass)
      .value("WARN", CheckStatus::kWarn)
      .value("FAIL", CheckStatus::kFail)
      .value("SKIP", CheckStatus::kSkip);

  nb::class_<CheckRow>(m, "CheckRow",
                       "One row of a check: its verdict, the element it judges, the measured "
                       "value against its reference, and what to do. The fields are those of "
                       "the CLI's JSON rows.")
      .def_prop_ro(
          "status", [](const CheckRow& r) { return std::string(CheckStatusName(r.status)); },
          "'PASS', 'WARN', 'FAIL' or 'SKIP'")
      .def_ro("id", &CheckRow::id)
      .def_ro("section", &CheckRow::section)
      .def_ro("title", &CheckRow::title)
      .def_prop_ro(
          "element", [](const CheckRow& r) { return r.About(); },
          "the element's label or the row's subject ('' for the whole model)")
      .def_prop_ro("element_type", [](const CheckRow& r) { return r.element.kind; })
      .def_prop_ro("element_name", [](const CheckRow& r) { return r.element.name; })
      .def_prop_ro("element_id", [](const CheckRow& r) { return r.element.id; })
      .def_prop_ro(
          "measured", [](const CheckRow& r) { return r.measured.value; },
          "the measured number (nan when the row has none)")
      .def_prop_ro("measured_unit", [](const CheckRow& r) { return r.measured.unit; })
      .def_ro("measured_text", &CheckRow::measured_text)
      .def_prop_ro(
          "reference", [](const CheckRow& r) { return r.reference.value; },
          "the reference or threshold (nan when none)")
      .def_prop_ro("reference_unit", [](const CheckRow& r) { return r.reference.unit; })
      .def_ro("reference_text", &CheckRow::reference_text)
      .def_ro("threshold", &CheckRow::threshold)
      .def_ro("rel_error", &CheckRow::rel_error)
      .def_ro("explanation", &CheckRow::explanation)
      .def_ro("fix", &CheckRow::fix)
      .def_ro("accepted", &CheckRow::accepted)
      .def_prop_ro(
          "ok", [](const CheckRow& r) { return r.status != CheckStatus::kFail; }, "not FAIL")
      .def("__repr__", [](const CheckRow& r) {
        std::string about = r.About();
        return fmt::format("<CheckRow {} {}{}{}>", CheckStatusName(r.status), r.id,
                           about.empty() ? "" : " ", about);
      });

  nb::class_<PyModel>(m, "Model",
                      "A compiled model and the start its calls begin from. plumb.load makes "
                      "one; every call also takes a mujoco.MjModel or a path directly.")
      .def_prop_ro("name", &PyModel::name, "the file, or <MjModel 'NAME'> for a wrapped MjModel")
      .def_prop_ro("mjmodel", &PyModel::mjmodel,
                   "the mujoco.MjModel this wraps (not a copy), or None when plumb loaded the "
                   "file")
      .def_prop_ro(
          "address",
          [](const PyModel& p) { return reinterpret_cast<std::uintptr_t>(p.model().get()); },
          "the mjModel's address (MjModel._address of a wrapped model)")
      .def_prop_ro("keyframe", &PyModel::keyframe)
      .def_prop_ro(
          "sets", [](const PyModel& p) { return p.sets(); },
          "the start's set assignments, as PATH=VALUE")
      .def_prop_ro("nq", [](const PyModel& p) { return p.model()->nq; })
      .def_prop_ro("nv", [](const PyModel& p) { return p.model()->nv; })
      .def_prop_ro("nu", [](const PyModel& p) { return p.model()->nu; })
      .def_prop_ro("nbody", [](const PyModel& p) { return p.model()->nbody; })
      .def_prop_ro("timestep", [](const PyModel& p) { return p.model()->opt.timestep; })
      .def("__repr__", [](const PyModel& p) {
        return fmt::format("<plumb.Model {} nq={} nv={} nu={}{}>", p.name(), p.model()->nq,
                           p.model()->nv, p.model()->nu,
                           p.sets().empty() && p.keyframe().empty() ? "" : " (with a start)");
      });

  m.def(
      "load",
      [](ModelArg model, SetArg set, std::optional<NameOrId> keyframe) {
        CallNotices notices;
        std::shared_ptr<PyModel> base = ToModel(model, notices.sink());
        std::vector<std::string> sets = base->SetTexts(SetTexts(set));
        auto out = std::make_shared<PyModel>(base->shared(), base->mjmodel(),
                                             (keyframe ? keyframe->text : base->keyframe()), sets);
        {
          MujocoCallScope scope;
          out->Start({}, notices.sink());  // validates the keyframe and every assignment now
        }
        notices.Issue();
        return out;
      },
      nb::arg("model"), nb::arg("set") = nb::none(), nb::arg("keyframe") = nb::none(),
      "Loads an MJCF or .mjb file, or wraps a mujoco.MjModel without copying it, with the start "
      "its calls begin from: the keyframe, then each set assignment "
      "(set={'qpos[hinge]': 0.7}, the CLI's --set). Issues plumb.CompileWarning for what MuJoCo's "
      "compiler said and plumb.StartWarning for a start value MuJoCo changes. Raises "
      "plumb.LoadError, plumb.PathError, plumb.ArgumentError.");

  m.def("mujoco_version", &MujocoVersion, "the version of the MuJoCo library in use");
  m.def("compiled_mujoco_version", &CompiledMujocoVersion,
        "the MuJoCo version plumb was built against");
  m.def("mujoco_library", &MujocoLibraryPath, "the file of the MuJoCo library in use");
}

}  // namespace plumb::python
