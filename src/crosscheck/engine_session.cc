#include "crosscheck/engine_session.h"

#include <fmt/format.h>
#include <stdlib.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/demand.h"
#include "core/fields.h"
#include "core/mujoco_compat.h"
#include "plumb/error.h"
#include "plumb/version.h"

namespace plumb::internal {
namespace {

constexpr int kProtocol = 1;

// The named state arrays of the protocol: one row per world.
struct StateField {
  const char* name;
  const mjtNum* (*at)(const mjData*);
  long (*size)(const mjModel*);
};
const StateField kStateFields[] = {
    {"time", [](const mjData* d) -> const mjtNum* { return &d->time; },
     [](const mjModel*) { return 1L; }},
    {"qpos", [](const mjData* d) -> const mjtNum* { return d->qpos; },
     [](const mjModel* m) { return long(m->nq); }},
    {"qvel", [](const mjData* d) -> const mjtNum* { return d->qvel; },
     [](const mjModel* m) { return long(m->nv); }},
    {"act", [](const mjData* d) -> const mjtNum* { return d->act; },
     [](const mjModel* m) { return long(m->na); }},
    {"ctrl", [](const mjData* d) -> const mjtNum* { return d->ctrl; },
     [](const mjModel* m) { return long(m->nu); }},
    {"qacc_warmstart", [](const mjData* d) -> const mjtNum* { return d->qacc_warmstart; },
     [](const mjModel* m) { return long(m->nv); }},
    {"qfrc_applied", [](const mjData* d) -> const mjtNum* { return d->qfrc_applied; },
     [](const mjModel* m) { return long(m->nv); }},
    {"xfrc_applied", [](const mjData* d) -> const mjtNum* { return d->xfrc_applied; },
     [](const mjModel* m) { return 6L * m->nbody; }},
    {"mocap_pos", [](const mjData* d) -> const mjtNum* { return d->mocap_pos; },
     [](const mjModel* m) { return 3L * m->nmocap; }},
    {"mocap_quat", [](const mjData* d) -> const mjtNum* { return d->mocap_quat; },
     [](const mjModel* m) { return 4L * m->nmocap; }},
};

std::vector<EngineArray> StateArrays(const mjModel* m, const std::vector<const mjData*>& states) {
  std::vector<EngineArray> arrays;
  const long w = static_cast<long>(states.size());
  for (const StateField& f : kStateFields) {
    const long n = f.size(m);
    EngineArray a{f.name, {w, n}, {}};
    a.values.reserve(w * n);
    for (const mjData* d : states) {
      const mjtNum* p = f.at(d);
      a.values.insert(a.values.end(), p, p + n);
    }
    arrays.push_back(std::move(a));
  }
  return arrays;
}

}  // namespace

nlohmann::json ModelEdits(const Model& base, const Model& model) {
  nlohmann::json edits = nlohmann::json::array();
  for (const FieldInfo& f : Fields()) {
    if (f.source != FieldSource::kModelArray && f.source != FieldSource::kOption) continue;
    if (f.type == compat::ElemType::kChar || f.type == compat::ElemType::kOther) continue;
    const long n = f.rows(model.get()) * f.cols(model.get());
    PLUMB_DEMAND(n == f.rows(base.get()) * f.cols(base.get()));
    const std::size_t size = ElemSize(f.type);
    auto* a = static_cast<const unsigned char*>(FieldBase(f, base.get(), nullptr));
    auto* b = static_cast<const unsigned char*>(FieldBase(f, model.get(), nullptr));
    if (n == 0 || std::memcmp(a, b, n * size) == 0) continue;
    for (long i = 0; i < n; ++i) {
      if (std::memcmp(a + i * size, b + i * size, size) == 0) continue;
      edits.push_back({f.name, i, ReadElement(f.type, b + i * size)});
    }
  }
  return edits;
}

std::vector<double> FieldValues(const Model& model, const std::string& field) {
  const FieldInfo* f = FindField(field);
  PLUMB_DEMAND(f != nullptr);
  const long n = f->rows(model.get()) * f->cols(model.get());
  auto* base = static_cast<const unsigned char*>(FieldBase(*f, model.get(), nullptr));
  std::vector<double> out(n);
  for (long i = 0; i < n; ++i) out[i] = ReadElement(f->type, base + i * ElemSize(f->type));
  return out;
}

void ApplyEdits(const nlohmann::json& edits, Model& model) {
  for (const nlohmann::json& e : edits) {
    const FieldInfo* f = FindField(e.at(0).get<std::string>());
    PLUMB_DEMAND(f != nullptr);
    auto* base =
        static_cast<unsigned char*>(const_cast<void*>(FieldBase(*f, model.get_mutable(), nullptr)));
    WriteElement(f->type, base + e.at(1).get<long>() * ElemSize(f->type), e.at(2).get<double>());
  }
}

StageValues CpuStages(const Model& model, const std::vector<const mjData*>& states) {
  const mjModel* m = model.get();
  StageValues v;
  v.worlds = static_cast<int>(states.size());
  Data work(model);
  std::vector<mjtNum> full(static_cast<std::size_t>(m->nv) * m->nv);
  for (int w = 0; w < v.worlds; ++w) {
    mjData* d = work.get();
    mj_copyData(d, m, states[w]);
    mj_forward(m, d);
    v.xpos.insert(v.xpos.end(), d->xpos, d->xpos + 3 * m->nbody);
    v.xquat.insert(v.xquat.end(), d->xquat, d->xquat + 4 * m->nbody);
    compat::FullInertia(m, d, full.data());
    v.qM.insert(v.qM.end(), full.begin(), full.end());
    for (int i = 0; i < d->ncon; ++i) {
      const mjContact& c = d->contact[i];
      StageContact s;
      s.world = w;
      s.geom1 = c.geom1;
      s.geom2 = c.geom2;
      s.dist = c.dist;
      s.dim = c.dim;
      std::copy(c.pos, c.pos + 3, s.pos);
      std::copy(c.frame, c.frame + 9, s.frame);
      mj_contactForce(m, d, i, s.force);
      v.contacts.push_back(s);
    }
    for (int i = 0; i < d->nefc; ++i) {
      v.constraints.push_back({w, d->efc_type[i], d->efc_id[i], d->efc_pos[i], d->efc_force[i]});
    }
    v.qacc.insert(v.qacc.end(), d->qacc, d->qacc + m->nv);
    v.sensordata.insert(v.sensordata.end(), d->sensordata, d->sensordata + m->nsensordata);
    mj_copyData(d, m, states[w]);  // the step starts from the state itself, as the engine's does
    mj_step(m, d);
    v.next_qpos.insert(v.next_qpos.end(), d->qpos, d->qpos + m->nq);
    v.next_qvel.insert(v.next_qvel.end(), d->qvel, d->qvel + m->nv);
    v.next_act.insert(v.next_act.end(), d->act, d->act + m->na);
  }
  return v;
}

EngineSession::EngineSession(const EngineSetup& setup, const std::string& engine,
                             const std::string& device, StopToken stop)
    : timeout_(setup.timeout), stop_(std::move(stop)) {
  for (const std::string& file : {setup.python, setup.adapter}) {
    if (file.empty() || access(file.c_str(), R_OK) != 0) {
      throw UnavailableError(fmt::format(
          "the {} engine's {} is missing ({}): run `{}` to make its virtual environment (it "
          "downloads from PyPI)",
          engine, file == setup.python ? "Python" : "adapter", file.empty() ? "not found" : file,
          EngineSetupCommand(engine)));
    }
  }
  process_ = std::make_unique<EngineProcess>(
      std::vector<std::string>{setup.python, setup.adapter, "--engine", engine,  // argv
                               "--device", device},                              // argv
      setup.env);
  EngineReply hello = Ask({{"op", "hello"}, {"protocol", kProtocol}}, {});
  const nlohmann::json& h = hello.header;
  if (h.value("protocol", 0) != kProtocol) {
    throw EngineError(fmt::format(
        "the engine adapter {} speaks protocol {}, this plumb speaks {}: they come from "
        "different releases; reinstall plumb",
        setup.adapter, h.value("protocol", 0), kProtocol));
  }
  info_.engine = h.value("engine", engine);
  info_.engine_version = h.value("engine_version", "");
  info_.backend = h.value("backend", "");
  info_.mujoco_version = h.value("mujoco_version", "");
  info_.mujoco_library = h.value("mujoco_library", "");
  info_.device = h.value("device", device);
  info_.precision = h.value("precision", "");
}

EngineSession::~EngineSession() {
  if (!temp_dir_.empty()) {
    std::error_code ignored;
    std::filesystem::remove_all(temp_dir_, ignored);
  }
}

EngineReply EngineSession::Ask(const nlohmann::json& header,
                               const std::vector<EngineArray>& arrays) {
  return process_->Request(header, arrays, timeout_, stop_);
}

std::string EngineSession::Load(const Model& model) {
  std::string file = model.file();
  Model base = [&] {
    if (model.xml_text().empty()) return Model::Load(file);
    char dir[] = "/tmp/plumb-crosscheck-XXXXXX";
    if (mkdtemp(dir) == nullptr) throw IoError("plumb crosscheck: cannot make a folder in /tmp");
    temp_dir_ = dir;
    file = temp_dir_ + "/model.xml";
    std::ofstream(file) << model.xml_text();
    return Model::FromXmlString(model.xml_text(), model.file());
  }();
  nlohmann::json edits = ModelEdits(base, model);
  EngineReply reply = Ask({{"op", "load"}, {"model", file}, {"edits", edits}}, {});
  const nlohmann::json& sizes = reply.header.at("sizes");
  const mjModel* m = model.get();
  for (auto [name, ours] : {std::pair<const char*, int>{"nq", m->nq},
                            {"nv", m->nv},
                            {"nbody", m->nbody},
                            {"ngeom", m->ngeom},
                            {"nu", m->nu},
                            {"nsensordata", m->nsensordata}}) {
    if (sizes.value(name, -1) != ours) {
      throw EngineError(
          fmt::format("the engine compiled {} with {} = {}, plumb with {}: not the "
                      "same model",
                      file, name, sizes.value(name, -1), ours));
    }
  }
  const bool binary = file.size() > 4 && file.substr(file.size() - 4) == ".mjb";
  return fmt::format("{} + {} edit{}", binary ? "MJB" : "MJCF", edits.size(),
                     edits.size() == 1 ? "" : "s");
}

StageValues EngineSession::Stages(const Model& model, const std::vector<const mjData*>& states) {
  const mjModel* m = model.get();
  EngineReply r = Ask({{"op", "stages"}}, StateArrays(m, states));
  StageValues v;
  v.worlds = static_cast<int>(states.size());
  v.xpos = r.Get("xpos").values;
  v.xquat = r.Get("xquat").values;
  v.qM = r.Get("qM").values;
  v.qacc = r.Get("qacc").values;
  v.sensordata = r.Get("sensordata").values;
  v.next_qpos = r.Get("next_qpos").values;
  v.next_qvel = r.Get("next_qvel").values;
  v.next_act = r.Get("next_act").values;
  const std::vector<double>& cw = r.Get("contact_world").values;
  const std::vector<double>& geom = r.Get("contact_geom").values;
  const std::vector<double>& dist = r.Get("contact_dist").values;
  const std::vector<double>& pos = r.Get("contact_pos").values;
  const std::vector<double>& frame = r.Get("contact_frame").values;
  const std::vector<double>& dim = r.Get("contact_dim").values;
  const std::vector<double>& force = r.Get("contact_force").values;
  for (std::size_t i = 0; i < cw.size(); ++i) {
    StageContact c;
    c.world = static_cast<int>(cw[i]);
    c.geom1 = static_cast<int>(geom[2 * i]);
    c.geom2 = static_cast<int>(geom[2 * i + 1]);
    c.dist = dist[i];
    c.dim = static_cast<int>(dim[i]);
    std::copy(&pos[3 * i], &pos[3 * i] + 3, c.pos);
    std::copy(&frame[9 * i], &frame[9 * i] + 9, c.frame);
    std::copy(&force[6 * i], &force[6 * i] + 6, c.force);
    v.contacts.push_back(c);
  }
  const std::vector<double>& ew = r.Get("efc_world").values;
  const std::vector<double>& type = r.Get("efc_type").values;
  const std::vector<double>& id = r.Get("efc_id").values;
  const std::vector<double>& efc_pos = r.Get("efc_pos").values;
  const std::vector<double>& efc_force = r.Get("efc_force").values;
  for (std::size_t i = 0; i < ew.size(); ++i) {
    v.constraints.push_back({static_cast<int>(ew[i]), static_cast<int>(type[i]),
                             static_cast<int>(id[i]), efc_pos[i], efc_force[i]});
  }
  const nlohmann::json overflow = r.header.value("overflow", nlohmann::json::object());
  v.overflow_contacts = overflow.value("contacts", 0L);
  v.overflow_constraints = overflow.value("constraints", 0L);
  return v;
}

EngineRollout EngineSession::Rollout(const Model& model, const std::vector<const mjData*>& starts,
                                     const std::vector<double>& ctrl, long steps, long every,
                                     const std::vector<WorldField>& fields) {
  const mjModel* m = model.get();
  const long w = static_cast<long>(starts.size());
  std::vector<EngineArray> arrays = StateArrays(m, starts);
  arrays.push_back({"ctrl_sequence", {steps, w * m->nu}, ctrl});
  for (const WorldField& f : fields) {
    arrays.push_back({"model:" + f.field, {w, static_cast<long>(f.values.size()) / w}, f.values});
  }
  EngineReply r = Ask({{"op", "rollout"}, {"steps", steps}, {"every", every}}, arrays);
  EngineRollout out;
  out.rows = steps / every + 1;
  out.qpos = r.Get("qpos").values;
  out.qvel = r.Get("qvel").values;
  out.act = r.Get("act").values;
  out.ncon_max = r.Get("ncon_max").values;
  if (static_cast<long>(out.qpos.size()) != out.rows * w * m->nq) {
    throw EngineError(
        fmt::format("the engine adapter returned {} qpos values for a rollout of "
                    "{} rows of {} worlds (nq = {})",
                    out.qpos.size(), out.rows, w, m->nq));
  }
  const nlohmann::json overflow = r.header.value("overflow", nlohmann::json::object());
  out.overflow_contacts = overflow.value("contacts", 0L);
  out.overflow_constraints = overflow.value("constraints", 0L);
  for (const auto& u : r.header.value("unvaried", nlohmann::json::array())) {
    out.unvaried.push_back(u.is_string() ? u.get<std::string>()
                                         : u.value("field", "") + ": " + u.value("reason", ""));
  }
  return out;
}

std::pair<double, double> EngineSession::Throughput(const Model& model, const mjData* start,
                                                    int worlds, long steps) {
  EngineReply r = Ask({{"op", "throughput"}, {"worlds", worlds}, {"steps", steps}},
                      StateArrays(model.get(), {start}));
  const double seconds = r.header.at("seconds").get<double>();
  const double rate = seconds > 0 ? double(worlds) * double(steps) / seconds : 0;
  return {rate, r.header.value("compile_seconds", 0.0)};
}

}  // namespace plumb::internal
