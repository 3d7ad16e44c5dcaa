#include "crosscheck/stage_compare.h"

#include <fmt/format.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <map>
#include <string>

#include "core/geometry.h"
#include "core/joint_size.h"

namespace plumb::internal {
namespace {

constexpr double kEps = FLT_EPSILON;  // float32's epsilon, 2^-23

// The worst disagreement of one stage: the largest |difference| / tolerance seen.
struct Worst {
  double ratio = -1;  // -1: nothing compared yet; > 1: disagrees
  double error = 0, tol = 0;
  std::string unit;
  CheckElement element;
  std::string subject;  // when not one element (a geom pair)
  std::string what;     // "body position", "contact missing on the engine"
  double time = 0;
  long compared = 0;

  void Offer(double err, double tolerance, double t, std::string quantity, std::string u,
             CheckElement el = {}, std::string about = "") {
    ++compared;
    const double r = tolerance > 0 ? err / tolerance : (err > 0 ? INFINITY : 0);
    if (!(r > ratio) && !(std::isnan(err) && !std::isnan(error))) return;
    ratio = std::isnan(err) ? INFINITY : r;
    error = err;
    tol = tolerance;
    unit = std::move(u);
    element = std::move(el);
    subject = std::move(about);
    what = std::move(quantity);
    time = t;
  }
  bool disagrees() const { return ratio > 1; }
};

double MaxAbs(const std::vector<double>& v, double floor) {
  double s = floor;
  for (double x : v) s = std::max(s, std::abs(x));
  return s;
}

CheckElement Element(const Model& model, const char* kind, int type, int id) {
  return {kind, model.Name(type, id), id};
}

CheckElement DofJoint(const Model& model, int dof) {
  return Element(model, "joint", mjOBJ_JOINT, model->dof_jntid[dof]);
}

std::string GeomPair(const Model& model, int g1, int g2) {
  return ElementLabel(Element(model, "geom", mjOBJ_GEOM, g1)) + " / " +
         ElementLabel(Element(model, "geom", mjOBJ_GEOM, g2));
}

using PairKey = std::pair<int, std::pair<int, int>>;  // world, geom pair (smaller id first)

using PairContacts = std::map<PairKey, std::vector<int>>;

// Each side's contacts by state and geom pair (indices into its contact list).
PairContacts ContactsByPair(const StageValues& v) {
  PairContacts pairs;
  for (int i = 0; i < static_cast<int>(v.contacts.size()); ++i) {
    const StageContact& c = v.contacts[i];
    pairs[{c.world, {std::min(c.geom1, c.geom2), std::max(c.geom1, c.geom2)}}].push_back(i);
  }
  return pairs;
}

struct Context {
  Context(const Model& m, const StageValues& a, const StageValues& b, const std::vector<double>& t)
      : model(m),
        cpu(a),
        engine(b),
        times(t),
        length(MaxAbs(a.xpos, 1)),
        cpu_pairs(ContactsByPair(a)),
        engine_pairs(ContactsByPair(b)) {}
  const Model& model;
  const StageValues& cpu;
  const StageValues& engine;
  const std::vector<double>& times;
  double length;  // m: the model's extent, at least 1
  PairContacts cpu_pairs, engine_pairs;
  // States where a contact at the edge of detection is on one side only: rounding decides its
  // contact set, so what follows from contacts is not compared there.
  std::vector<bool> edge;
  bool Skipped(int world) const { return !edge.empty() && edge[world]; }
};

Worst Kinematics(const Context& c) {
  Worst w;
  const mjModel* m = c.model.get();
  const double tol = StageFactor("kinematics") * kEps * c.length;
  for (int s = 0; s < c.cpu.worlds; ++s) {
    for (int b = 1; b < m->nbody; ++b) {
      const double* p = &c.cpu.xpos[(s * m->nbody + b) * 3];
      const double* q = &c.engine.xpos[(s * m->nbody + b) * 3];
      const double err = std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
      w.Offer(err, tol, c.times[s], "body position", "m", Element(c.model, "body", mjOBJ_BODY, b));
      const double angle = RotationAngle(&c.cpu.xquat[(s * m->nbody + b) * 4],
                                         &c.engine.xquat[(s * m->nbody + b) * 4]);
      w.Offer(angle, StageFactor("kinematics") * kEps, c.times[s], "body orientation", "rad",
              Element(c.model, "body", mjOBJ_BODY, b));
    }
  }
  return w;
}

Worst MassMatrix(const Context& c) {
  Worst w;
  const int nv = c.model->nv;
  if (c.engine.qM.size() != c.cpu.qM.size()) return w;  // the engine did not send it
  const double tol = StageFactor("mass_matrix") * kEps * MaxAbs(c.cpu.qM, 1e-12);
  for (int s = 0; s < c.cpu.worlds; ++s) {
    for (int i = 0; i < nv; ++i) {
      for (int j = 0; j <= i; ++j) {
        const std::size_t k = (static_cast<std::size_t>(s) * nv + i) * nv + j;
        const CheckElement joint = DofJoint(c.model, i);
        w.Offer(std::abs(c.cpu.qM[k] - c.engine.qM[k]), tol, c.times[s],
                fmt::format("M[{},{}]", i, j), "", joint);
      }
    }
  }
  return w;
}

// Contacts of both sides, matched within each geom pair by nearest position.
struct ContactMatch {
  std::vector<std::pair<int, int>> matched;  // (cpu index, engine index)
  Worst set;                                 // the contacts stage
  std::vector<bool> edge;                    // per state: see Context::edge
};

// A contact only one side has is a difference unless it sits at the edge of detection (its
// distance within float32 rounding of the pair's margin, as the kinematics are): then rounding
// alone decides. A resting contact (0.1 mm into the floor) is well inside.
bool AtTheEdge(const Model& model, const StageContact& c, double length) {
  const double margin = std::max(model->geom_margin[c.geom1], model->geom_margin[c.geom2]);
  return std::abs(c.dist - margin) <= StageFactor("kinematics") * kEps * length;
}

void MatchPair(const Context& c, const PairKey& key, const std::vector<int>& a,
               const std::vector<int>& b, double tol, ContactMatch* out) {
  // the closest pairs of contacts first, so that a missing contact leaves its own partner alone
  std::vector<std::tuple<double, std::size_t, std::size_t>> candidates;
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (std::size_t j = 0; j < b.size(); ++j) {
      const double* p = c.cpu.contacts[a[i]].pos;
      const double* q = c.engine.contacts[b[j]].pos;
      candidates.emplace_back(std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]), i, j);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<bool> taken_a(a.size(), false), used(b.size(), false);
  for (auto [d, i, j] : candidates) {
    if (taken_a[i] || used[j]) continue;
    taken_a[i] = used[j] = true;
    out->matched.push_back({a[i], b[j]});
  }
  std::vector<int> lonely_cpu;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!taken_a[i]) lonely_cpu.push_back(a[i]);
  }
  const double t = c.times[key.first];
  const std::string pair = GeomPair(c.model, key.second.first, key.second.second);
  for (int i : lonely_cpu) {
    if (AtTheEdge(c.model, c.cpu.contacts[i], c.length)) {
      out->edge[key.first] = true;
      continue;
    }
    out->set.Offer(INFINITY, tol, t,
                   fmt::format("{} contact(s) on CPU MuJoCo, {} on the engine", a.size(), b.size()),
                   "", {}, pair);
  }
  for (std::size_t j = 0; j < b.size(); ++j) {
    if (used[j]) continue;
    if (AtTheEdge(c.model, c.engine.contacts[b[j]], c.length)) {
      out->edge[key.first] = true;
      continue;
    }
    out->set.Offer(INFINITY, tol, t,
                   fmt::format("{} contact(s) on CPU MuJoCo, {} on the engine", a.size(), b.size()),
                   "", {}, pair);
  }
}

ContactMatch Contacts(const Context& c) {
  ContactMatch out;
  out.edge.assign(c.cpu.worlds, false);
  const double tol = StageFactor("contacts") * kEps * c.length;
  const double angle_tol = StageFactor("contacts") * kEps;
  const PairContacts& cpu = c.cpu_pairs;
  const PairContacts& engine = c.engine_pairs;
  static const std::vector<int> kNone;
  for (const auto& [key, list] : cpu) {
    auto it = engine.find(key);
    MatchPair(c, key, list, it == engine.end() ? kNone : it->second, tol, &out);
  }
  for (const auto& [key, list] : engine) {
    if (cpu.count(key) == 0) MatchPair(c, key, kNone, list, tol, &out);
  }
  for (auto [i, j] : out.matched) {
    const StageContact& a = c.cpu.contacts[i];
    const StageContact& b = c.engine.contacts[j];
    const std::string pair = GeomPair(c.model, a.geom1, a.geom2);
    const double t = c.times[a.world];
    out.set.Offer(std::abs(a.dist - b.dist), tol, t, "contact distance", "m", {}, pair);
    out.set.Offer(std::hypot(a.pos[0] - b.pos[0], a.pos[1] - b.pos[1], a.pos[2] - b.pos[2]), tol, t,
                  "contact position", "m", {}, pair);
    out.set.Offer(AngleBetween(a.frame, b.frame), angle_tol, t, "contact normal", "rad", {}, pair);
  }
  return out;
}

// A contact's force and torque (mj_contactForce's, in the contact frame) in world coordinates.
void WorldWrench(const StageContact& c, double out[6]) {
  for (int k = 0; k < 3; ++k) {
    out[k] = c.force[0] * c.frame[k] + c.force[1] * c.frame[3 + k] + c.force[2] * c.frame[6 + k];
    out[3 + k] =
        c.force[3] * c.frame[k] + c.force[4] * c.frame[3 + k] + c.force[5] * c.frame[6 + k];
  }
}

bool IsContactRow(int type) {
  return type == mjCNSTR_CONTACT_FRICTIONLESS || type == mjCNSTR_CONTACT_PYRAMIDAL ||
         type == mjCNSTR_CONTACT_ELLIPTIC;
}

const char* ConstraintName(int type) {
  switch (type) {
    case mjCNSTR_EQUALITY:
      return "equality";
    case mjCNSTR_FRICTION_DOF:
      return "dof friction";
    case mjCNSTR_FRICTION_TENDON:
      return "tendon friction";
    case mjCNSTR_LIMIT_JOINT:
      return "joint limit";
    case mjCNSTR_LIMIT_TENDON:
      return "tendon limit";
    default:
      return "contact";
  }
}

CheckElement ConstraintElement(const Model& model, int type, int id) {
  switch (type) {
    case mjCNSTR_EQUALITY:
      return Element(model, "equality", mjOBJ_EQUALITY, id);
    case mjCNSTR_FRICTION_DOF:
      return DofJoint(model, id);
    case mjCNSTR_LIMIT_JOINT:
      return Element(model, "joint", mjOBJ_JOINT, id);
    default:
      return Element(model, "tendon", mjOBJ_TENDON, id);
  }
}

// Non-contact rows keyed by (world, type, id, k-th row of that element).
std::map<std::tuple<int, int, int, int>, int> RowsByElement(const StageValues& v) {
  std::map<std::tuple<int, int, int, int>, int> rows;
  std::map<std::tuple<int, int, int>, int> seen;
  for (int i = 0; i < static_cast<int>(v.constraints.size()); ++i) {
    const StageConstraint& r = v.constraints[i];
    if (IsContactRow(r.type)) continue;
    const int k = seen[{r.world, r.type, r.id}]++;
    rows[{r.world, r.type, r.id, k}] = i;
  }
  return rows;
}

// Rows of each contact, by the contact's index in its world.
std::map<std::pair<int, int>, std::vector<int>> RowsOfContacts(const StageValues& v) {
  std::map<std::pair<int, int>, std::vector<int>> rows;
  for (int i = 0; i < static_cast<int>(v.constraints.size()); ++i) {
    const StageConstraint& r = v.constraints[i];
    if (IsContactRow(r.type)) rows[{r.world, r.id}].push_back(i);
  }
  return rows;
}

// Index of contact `i` of `v` within its own world's list.
std::vector<int> IndexInWorld(const StageValues& v) {
  std::vector<int> index(v.contacts.size());
  std::map<int, int> count;
  for (std::size_t i = 0; i < v.contacts.size(); ++i) index[i] = count[v.contacts[i].world]++;
  return index;
}

struct RowsAndForces {
  Worst rows, forces;
};

void CompareElementRows(const Context& c, double pos_tol, double force_tol, RowsAndForces* out) {
  const auto a = RowsByElement(c.cpu), b = RowsByElement(c.engine);
  auto lonely = [&](const auto& key, const StageConstraint& r, const char* side) {
    if (std::abs(r.pos) <= pos_tol) return;  // at the edge of activating
    out->rows.Offer(INFINITY, pos_tol, c.times[std::get<0>(key)],
                    fmt::format("{} row on {} only (its violation {:.3g})", ConstraintName(r.type),
                                side, r.pos),
                    "", ConstraintElement(c.model, r.type, r.id));
  };
  for (const auto& [key, i] : a) {
    auto it = b.find(key);
    const StageConstraint& r = c.cpu.constraints[i];
    if (c.Skipped(r.world)) continue;
    if (it == b.end()) {
      lonely(key, r, "CPU MuJoCo");
      continue;
    }
    const StageConstraint& e = c.engine.constraints[it->second];
    const CheckElement el = ConstraintElement(c.model, r.type, r.id);
    const double t = c.times[r.world];
    out->rows.Offer(std::abs(r.pos - e.pos), pos_tol, t,
                    fmt::format("{} violation", ConstraintName(r.type)), "", el);
    out->forces.Offer(std::abs(r.force - e.force), force_tol, t,
                      fmt::format("{} force", ConstraintName(r.type)), "", el);
  }
  for (const auto& [key, i] : b) {
    if (c.Skipped(std::get<0>(key))) continue;
    if (a.count(key) == 0) lonely(key, c.engine.constraints[i], "the engine");
  }
}

// The total force and torque (about the pair's CPU contacts' centroid) of a pair's contacts, in
// world coordinates: well defined where the split among the pair's contacts is not (four
// corners of a resting box share its weight as the solver's regularization says).
struct PairWrench {
  double force[3] = {0, 0, 0}, torque[3] = {0, 0, 0};
};

PairWrench SumWrench(const StageValues& v, const std::vector<int>& contacts, const double* centre) {
  PairWrench w;
  for (int i : contacts) {
    const StageContact& c = v.contacts[i];
    double f[6];
    WorldWrench(c, f);  // each side picks its own tangents for the contact frame
    const double r[3] = {c.pos[0] - centre[0], c.pos[1] - centre[1], c.pos[2] - centre[2]};
    const double moment[3] = {r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2],
                              r[0] * f[1] - r[1] * f[0]};
    for (int k = 0; k < 3; ++k) {
      w.force[k] += f[k];
      w.torque[k] += moment[k] + f[3 + k];
    }
  }
  return w;
}

void ComparePairWrenches(const Context& c, double force_tol, Worst* forces) {
  const PairContacts& cpu = c.cpu_pairs;
  const PairContacts& engine = c.engine_pairs;
  static const std::vector<int> kNone;
  auto compare = [&](const PairKey& key, const std::vector<int>& a, const std::vector<int>& b) {
    if (c.Skipped(key.first)) return;
    const StageValues& side = a.empty() ? c.engine : c.cpu;
    const std::vector<int>& around = a.empty() ? b : a;
    double centre[3] = {0, 0, 0}, extent = 0.01;
    for (int i : around) {
      for (int k = 0; k < 3; ++k) centre[k] += side.contacts[i].pos[k] / around.size();
    }
    for (int i : around) {
      const double* p = side.contacts[i].pos;
      extent = std::max(extent, std::hypot(p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]));
    }
    const PairWrench wa = SumWrench(c.cpu, a, centre), wb = SumWrench(c.engine, b, centre);
    const std::string pair = GeomPair(c.model, key.second.first, key.second.second);
    const double t = c.times[key.first];
    const double* fa = wa.force;
    const double* fb = wb.force;
    forces->Offer(std::hypot(fa[0] - fb[0], fa[1] - fb[1], fa[2] - fb[2]), force_tol, t,
                  "contact force of the pair", "N", {}, pair);
    const double* ta = wa.torque;
    const double* tb = wb.torque;
    forces->Offer(std::hypot(ta[0] - tb[0], ta[1] - tb[1], ta[2] - tb[2]), force_tol * extent, t,
                  "contact torque of the pair", "N*m", {}, pair);
  };
  for (const auto& [key, list] : cpu) {
    auto it = engine.find(key);
    compare(key, list, it == engine.end() ? kNone : it->second);
  }
  for (const auto& [key, list] : engine) {
    if (cpu.count(key) == 0) compare(key, kNone, list);
  }
}

RowsAndForces ConstraintsAndForces(const Context& c, const ContactMatch& match) {
  RowsAndForces out;
  // the scale: the largest constraint force, a row's or a pair's total (a resting box's weight)
  double force_scale = 1e-9;
  for (const StageConstraint& r : c.cpu.constraints) {
    force_scale = std::max(force_scale, std::abs(r.force));
  }
  for (const auto& [key, list] : c.cpu_pairs) {
    const double origin[3] = {0, 0, 0};
    const PairWrench w = SumWrench(c.cpu, list, origin);
    force_scale = std::max(force_scale, std::hypot(w.force[0], w.force[1], w.force[2]));
  }
  const double pos_tol = StageFactor("constraint_rows") * kEps * c.length;
  const double force_tol = StageFactor("constraint_forces") * kEps * force_scale;
  CompareElementRows(c, pos_tol, force_tol, &out);
  const auto cpu_rows = RowsOfContacts(c.cpu), engine_rows = RowsOfContacts(c.engine);
  const std::vector<int> cpu_index = IndexInWorld(c.cpu), engine_index = IndexInWorld(c.engine);
  for (auto [i, j] : match.matched) {
    const StageContact& a = c.cpu.contacts[i];
    const StageContact& b = c.engine.contacts[j];
    if (c.Skipped(a.world)) continue;
    const std::string pair = GeomPair(c.model, a.geom1, a.geom2);
    const double t = c.times[a.world];
    auto ra = cpu_rows.find({a.world, cpu_index[i]});
    auto rb = engine_rows.find({b.world, engine_index[j]});
    const std::size_t na = ra == cpu_rows.end() ? 0 : ra->second.size();
    const std::size_t nb = rb == engine_rows.end() ? 0 : rb->second.size();
    if (na == nb) {
      out.rows.Offer(0, pos_tol, t, "constraint rows of a contact", "", {}, pair);
    } else {
      out.rows.Offer(INFINITY, pos_tol, t,
                     fmt::format("{} constraint row(s) for a contact on CPU MuJoCo, {} on the "
                                 "engine (friction cone or condim treated differently)",
                                 na, nb),
                     "", {}, pair);
    }
  }
  ComparePairWrenches(c, force_tol, &out.forces);
  return out;
}

Worst Accelerations(const Context& c) {
  Worst w;
  const int nv = c.model->nv;
  const double tol = StageFactor("accelerations") * kEps * MaxAbs(c.cpu.qacc, 1);
  for (int s = 0; s < c.cpu.worlds; ++s) {
    if (c.Skipped(s)) continue;
    for (int i = 0; i < nv; ++i) {
      const std::size_t k = static_cast<std::size_t>(s) * nv + i;
      w.Offer(std::abs(c.cpu.qacc[k] - c.engine.qacc[k]), tol, c.times[s], "qacc", "",
              DofJoint(c.model, i));
    }
  }
  return w;
}

Worst Sensors(const Context& c) {
  Worst w;
  const mjModel* m = c.model.get();
  const int n = m->nsensordata;
  for (int id = 0; id < m->nsensor; ++id) {
    const int adr = m->sensor_adr[id], dim = m->sensor_dim[id];
    double scale = 1e-6;
    for (int s = 0; s < c.cpu.worlds; ++s) {
      if (c.Skipped(s)) continue;
      for (int k = 0; k < dim; ++k)
        scale = std::max(scale, std::abs(c.cpu.sensordata[s * n + adr + k]));
    }
    const double tol = StageFactor("sensors") * kEps * scale;
    for (int s = 0; s < c.cpu.worlds; ++s) {
      if (c.Skipped(s)) continue;
      for (int k = 0; k < dim; ++k) {
        const std::size_t at = static_cast<std::size_t>(s) * n + adr + k;
        w.Offer(std::abs(c.cpu.sensordata[at] - c.engine.sensordata[at]), tol, c.times[s],
                "sensor value", "", Element(c.model, "sensor", mjOBJ_SENSOR, id));
      }
    }
  }
  return w;
}

Worst NextState(const Context& c) {
  Worst w;
  const mjModel* m = c.model.get();
  const double qpos_tol = StageFactor("next_state") * kEps * MaxAbs(c.cpu.next_qpos, 1);
  const double qvel_tol =
      StageFactor("next_state") * kEps * MaxAbs(c.cpu.next_qvel, 1) +
      m->opt.timestep * StageFactor("accelerations") * kEps * MaxAbs(c.cpu.qacc, 1);
  for (int s = 0; s < c.cpu.worlds; ++s) {
    if (c.Skipped(s)) continue;
    for (int j = 0; j < m->njnt; ++j) {
      const int adr = m->jnt_qposadr[j];
      const int nq = JointQposSize(m->jnt_type[j]);
      for (int k = 0; k < nq; ++k) {
        const std::size_t at = static_cast<std::size_t>(s) * m->nq + adr + k;
        w.Offer(std::abs(c.cpu.next_qpos[at] - c.engine.next_qpos[at]), qpos_tol, c.times[s],
                "next qpos", "", Element(c.model, "joint", mjOBJ_JOINT, j));
      }
    }
    for (int i = 0; i < m->nv; ++i) {
      const std::size_t at = static_cast<std::size_t>(s) * m->nv + i;
      w.Offer(std::abs(c.cpu.next_qvel[at] - c.engine.next_qvel[at]), qvel_tol, c.times[s],
              "next qvel", "", DofJoint(c.model, i));
    }
  }
  return w;
}

CheckRow StageRow(const char* stage, const Worst& w, const char* first_failure) {
  CheckRow row;
  row.id = std::string("stages.") + stage;
  row.section = "stages";
  row.title = fmt::format("one step, {}: the engine against CPU MuJoCo", stage);
  row.element = w.element;
  row.subject = w.subject;
  row.threshold = true;
  if (w.compared == 0) {
    row.status = CheckStatus::kSkip;
    row.explanation = "nothing to compare at these states";
    return row;
  }
  row.measured = {std::isfinite(w.error) ? w.error : NAN, w.unit};
  row.reference = {w.tol, w.unit};
  const std::string unit = w.unit.empty() ? "" : " " + w.unit;
  row.measured_text = std::isfinite(w.error) ? fmt::format("{} {:.3g}{} at t = {:.4g} s", w.what,
                                                           w.error, unit, w.time)
                                             : fmt::format("{} at t = {:.4g} s", w.what, w.time);
  row.reference_text =
      fmt::format("<= {:.3g}{} ({:g} x float32 epsilon x scale)", w.tol, unit, StageFactor(stage));
  if (!w.disagrees()) {
    row.status = CheckStatus::kPass;
    row.explanation = "agrees within float32 rounding";
  } else if (first_failure == stage) {
    row.status = CheckStatus::kFail;
    row.finding = "first difference";
    row.explanation = fmt::format(
        "the first stage where the engine computes different physics "
        "({} at the worst state)",
        w.what);
    row.fix = "see docs/crosscheck.md, 'Reading the stage check', for what each stage means";
  } else {
    row.status = CheckStatus::kWarn;
    row.finding = "follows";
    row.explanation = fmt::format("differs too, downstream of the {} stage", first_failure);
  }
  return row;
}

}  // namespace

const std::vector<const char*>& StageNames() {
  static const std::vector<const char*> kNames = {
      "kinematics",        "mass_matrix",   "contacts", "constraint_rows",
      "constraint_forces", "accelerations", "sensors",  "next_state"};
  return kNames;
}

double StageFactor(const char* stage) {
  // calibrated on robots nobody here wrote (docs/crosscheck.md): about 10 times the largest
  // disagreement MuJoCo Warp or MJX showed on any of them
  static const std::map<std::string, double> kFactors = {
      {"kinematics", 64},       {"mass_matrix", 64},        {"contacts", 2048},
      {"constraint_rows", 256}, {"constraint_forces", 1e5}, {"accelerations", 1e5},
      {"sensors", 1e5},         {"next_state", 4096}};
  return kFactors.at(stage);
}

std::vector<CheckRow> CompareStages(const Model& model, const StageValues& cpu,
                                    const StageValues& engine, const std::vector<double>& times) {
  Context c(model, cpu, engine, times);
  const ContactMatch match = Contacts(c);
  c.edge = match.edge;
  const long edge = std::count(c.edge.begin(), c.edge.end(), true);
  const RowsAndForces rows = ConstraintsAndForces(c, match);
  const std::vector<Worst> worst = {Kinematics(c), MassMatrix(c),    match.set,  rows.rows,
                                    rows.forces,   Accelerations(c), Sensors(c), NextState(c)};
  const char* first = nullptr;
  for (std::size_t i = 0; i < worst.size() && first == nullptr; ++i) {
    if (worst[i].disagrees()) first = StageNames()[i];
  }
  std::vector<CheckRow> out;
  for (std::size_t i = 0; i < worst.size(); ++i) {
    out.push_back(StageRow(StageNames()[i], worst[i], first));
    if (edge > 0 && i >= 3) {
      out.back().explanation += fmt::format(
          " ({} of {} states left out: a contact at the edge of detection is on one side only, "
          "so rounding decides what follows from it)",
          edge, cpu.worlds);
    }
  }
  return out;
}

}  // namespace plumb::internal
