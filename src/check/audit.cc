// The five layers of model acceptance, after the chapter's section 1.3.5: structure,
// inertia, actuator, contact, behaviour; plus every MuJoCo warning raised on the way.

#include "plumb/audit.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <regex>
#include <set>

#include "check/collision_graph.h"
#include "core/geometry.h"
#include "core/mujoco_compat.h"
#include "plumb/describe.h"
#include "plumb/error.h"
#include "plumb/keyframe.h"
#include "plumb/output.h"
#include "plumb/timing.h"

namespace plumb {
namespace {

// Per-element rows are listed for up to this many elements; beyond, a summary row.
constexpr int kMaxListed = 60;

std::string Elem(const Model& model, int obj, int id, const char* noun) {
  std::string name = model.Name(obj, id);
  return name.empty() ? fmt::format("{} #{}", noun, id)
                      : fmt::format("{} '{}' (id {})", noun, name, id);
}

Finding Make(const char* layer, std::string check, std::string element, std::string measured,
             std::string threshold, CheckStatus status, std::string fix) {
  Finding f{layer, std::move(check),    std::move(element),   "",     "",
            -1,    std::move(measured), std::move(threshold), status, std::move(fix)};
  // one element, as Elem writes it: "body 'hand' (id 3)" or "body #3"
  static const std::regex kNamed(R"(^([a-z ]+) '([^']*)' \(id (\d+)\)$)"),
      kUnnamed(R"(^([a-z ]+) #(\d+)$)");
  std::smatch match;
  if (std::regex_match(f.element, match, kNamed)) {
    f.element_type = match[1];
    f.element_name = match[2];
    f.element_id = std::stoi(match[3]);
  } else if (std::regex_match(f.element, match, kUnnamed)) {
    f.element_type = match[1];
    f.element_id = std::stoi(match[2]);
  }
  return f;
}

// When a check has more rows than kMaxListed, one row saying how many were listed.
void ListedNote(const char* layer, const char* check, const char* noun, int total,
                std::vector<Finding>* out, int shown = kMaxListed) {
  if (total <= shown) return;
  out->push_back(
      Make(layer, check, "", fmt::format("{} of {} {} listed", shown, total, noun), "",
           CheckStatus::kPass,
           fmt::format("only {} rows are shown; plumb inspect lists every element", shown)));
}

// |gravity|, 0 when <flag gravity="disable"/> switches it off.
double GravityNorm(const mjModel* m) {
  return (m->opt.disableflags & mjDSBL_GRAVITY) ? 0 : mju_norm3(m->opt.gravity);
}

// Moving bodies: those not welded to the world.
bool Moves(const mjModel* m, int b) { return b > 0 && m->body_weldid[b] != 0; }

// Volume of geom g (PrimitiveVolume), NaN when it is not a primitive.
double GeomVolume(const mjModel* m, int g) {
  return PrimitiveVolume(m->geom_type[g], m->geom_size + 3 * g);
}

// The reference pose: the keyframe the user named (--keyframe), else keyframe "home" or
// "test" if present, else qpos0; then --set.
struct Reference {
  int keyframe = -1;
  std::string description;
};

Reference FindReference(const Model& model, const std::string& keyframe) {
  Reference ref;
  if (!keyframe.empty()) {
    ref.keyframe = FindKeyframe(model, keyframe);
    ref.description = fmt::format("keyframe '{}' (--keyframe)", keyframe);
    return ref;
  }
  for (const char* name : {"home", "test"}) {
    int k = mj_name2id(model.get(), mjOBJ_KEY, name);
    if (k >= 0) {
      ref.keyframe = k;
      ref.description = fmt::format("keyframe '{}'", name);
      return ref;
    }
  }
  ref.description = "qpos0";
  return ref;
}

void StartAt(Model& model, Data& data, const Reference& ref, const std::vector<Assignment>& sets) {
  ApplyAssignments(model, data, sets);
  if (ref.keyframe >= 0) {
    mj_resetDataKeyframe(model.get(), data.get(), ref.keyframe);
    // the user's state assignments win over the keyframe
    for (const Assignment& a : sets) {
      if (a.path.role != Role::kParameter) WriteValues(model, data, a.path, a.values);
    }
    data.Forward();
  }
}

// ---- structure -----------------------------------------------------------------------

void StructureLayer(const Model& model, std::vector<Finding>* out) {
  const mjModel* m = model.get();
  const char* L = "structure";
  out->push_back(
      Make(L, "structure.counts", "",
           fmt::format("nbody {} njnt {} nq {} nv {} nu {} na {} nsensor {} ngeom {}", m->nbody,
                       m->njnt, m->nq, m->nv, m->nu, m->na, m->nsensor, m->ngeom),
           "", CheckStatus::kPass, "sizes of the compiled model"));

  // names matter where people and code refer to elements
  struct Kind {
    const char* noun;
    const char* plural;
    int obj;
    int count;
  } kinds[] = {{"joint", "joints", mjOBJ_JOINT, static_cast<int>(m->njnt)},
               {"actuator", "actuators", mjOBJ_ACTUATOR, compat::ActuatorCount(m)},
               {"sensor", "sensors", mjOBJ_SENSOR, static_cast<int>(m->nsensor)},
               {"body", "bodies", mjOBJ_BODY, static_cast<int>(m->nbody)}};
  for (const Kind& k : kinds) {
    std::vector<std::string> unnamed;
    for (int i = 0; i < k.count; ++i) {
      if (k.obj == mjOBJ_BODY && !Moves(m, i)) continue;
      if (model.Name(k.obj, i).empty()) unnamed.push_back("#" + std::to_string(i));
    }
    if (unnamed.empty()) continue;
    std::string list = fmt::format(
        "{}",
        fmt::join(unnamed.begin(), unnamed.begin() + std::min<size_t>(8, unnamed.size()), ", "));
    if (unnamed.size() > 8) list += fmt::format(", ... ({} in all)", unnamed.size());
    out->push_back(Make(L, std::string("structure.unnamed_") + k.plural,
                        fmt::format("{} {}", k.plural, list),
                        fmt::format("{} unnamed", unnamed.size()), "0", CheckStatus::kWarn,
                        fmt::format("name every {}: controllers, logs and plumb paths "
                                    "(qpos[name]) refer to {} by name, ids shift when the "
                                    "model changes",
                                    k.noun, k.plural)));
  }

  // joints: type, axis, addresses, range; a range warning comes with the joint's row
  for (int j = 0; j < m->njnt; ++j) {
    int type = m->jnt_type[j];
    std::string element = Elem(model, mjOBJ_JOINT, j, "joint");
    double lo = m->jnt_range[2 * j], hi = m->jnt_range[2 * j + 1];
    bool limited = m->jnt_limited[j];
    std::string range = limited ? fmt::format("[{:.4g}, {:.4g}]", lo, hi) : "unlimited";
    bool rotational = type == mjJNT_HINGE || type == mjJNT_BALL;
    if (limited && hi <= lo) {
      out->push_back(Make(L, "structure.joint_range", element, range, "lower < upper",
                          CheckStatus::kFail,
                          "a limited joint with an empty range is locked: give range=\"lo hi\" "
                          "or drop limited"));
    } else if (limited &&
               ((rotational && hi - lo > 4 * M_PI) || (type == mjJNT_SLIDE && hi - lo > 100))) {
      out->push_back(Make(L, "structure.joint_range", element, range,
                          rotational ? "<= 4*pi rad" : "<= 100 m", CheckStatus::kWarn,
                          rotational ? "a range wider than two turns never engages: was it "
                                       "written in degrees with <compiler angle=\"radian\">?"
                                     : "a slide range this long never engages: check units"));
    } else if (limited && type == mjJNT_HINGE && hi - lo < 0.1) {
      // MJCF angles are degrees unless <compiler angle="radian">: radians written there
      // become a range 57 times too narrow
      out->push_back(Make(L, "structure.joint_range", element, range + " rad", ">= 0.1 rad",
                          CheckStatus::kWarn,
                          fmt::format("a hinge range of {:.2g} degrees barely moves: MJCF reads "
                                      "angles in degrees unless <compiler angle=\"radian\">; "
                                      "were radians written?",
                                      (hi - lo) * 180 / M_PI)));
    }
    if (j < kMaxListed) {
      const mjtNum* axis = m->jnt_axis + 3 * j;
      out->push_back(Make(L, "structure.joint", element,
                          fmt::format("{} axis ({:.3g} {:.3g} {:.3g}) qpos[{}] dof[{}] range {}",
                                      compat::NameOf(compat::kJointTypes, type), axis[0], axis[1],
                                      axis[2], m->jnt_qposadr[j], m->jnt_dofadr[j], range),
                          "", CheckStatus::kPass,
                          "type, axis (body frame), addresses and range as compiled"));
    }
  }
  ListedNote(L, "structure.joint", "joints", m->njnt, out);

  // nq vs nv
  if (m->nq != m->nv) {
    std::vector<std::string> causes;
    for (int j = 0; j < m->njnt && causes.size() < 8; ++j) {
      if (m->jnt_type[j] == mjJNT_FREE || m->jnt_type[j] == mjJNT_BALL) {
        causes.push_back(Elem(model, mjOBJ_JOINT, j,
                              compat::NameOf(compat::kJointTypes, m->jnt_type[j]).c_str()));
      }
    }
    out->push_back(Make(L, "structure.nq_nv", fmt::format("{}", fmt::join(causes, ", ")),
                        fmt::format("nq {} != nv {}", m->nq, m->nv), "", CheckStatus::kPass,
                        "free joints have 7 qpos and 6 dofs, ball joints 4 and 3: index qvel, "
                        "qacc and forces with dof addresses, never qpos addresses"));
  }

  // actuators -> transmission targets, sensors -> sensordata layout
  for (int u = 0; u < compat::ActuatorCount(m) && u < kMaxListed; ++u) {
    int trn = m->actuator_trntype[u];
    int target_type = trn == mjTRN_TENDON ? mjOBJ_TENDON
                      : trn == mjTRN_SITE ? mjOBJ_SITE
                      : trn == mjTRN_BODY ? mjOBJ_BODY
                                          : mjOBJ_JOINT;
    out->push_back(Make(L, "structure.actuator", Elem(model, mjOBJ_ACTUATOR, u, "actuator"),
                        fmt::format("{} -> {}", compat::NameOf(compat::kTransmissions, trn),
                                    Elem(model, target_type, m->actuator_trnid[2 * u],
                                         compat::NameOf(compat::kTransmissions, trn).c_str())),
                        "", CheckStatus::kPass, "transmission and the element it drives"));
  }
  ListedNote(L, "structure.actuator", "actuators", compat::ActuatorCount(m), out);
  for (int s = 0; s < m->nsensor && s < kMaxListed; ++s) {
    out->push_back(Make(L, "structure.sensor", Elem(model, mjOBJ_SENSOR, s, "sensor"),
                        fmt::format("{} sensordata[{}..{}]",
                                    compat::NameOf(compat::kSensorTypes, m->sensor_type[s]),
                                    m->sensor_adr[s], m->sensor_adr[s] + m->sensor_dim[s] - 1),
                        "", CheckStatus::kPass, "sensor type and its place in sensordata"));
  }
  ListedNote(L, "structure.sensor", "sensors", m->nsensor, out);
}

// ---- inertia -------------------------------------------------------------------------

// How far from the point `com` (body frame) the mass of body `b` lies (rms, in m) if
// it all sits in one of the body's geoms, filled uniformly: the smallest and largest
// over its geoms (which geom carries the mass is not in the compiled model: a
// decorative geom may have none). {-1, -1} when a geom has no primitive volume.
std::pair<double, double> GeomSpread(const mjModel* m, int b, const mjtNum* com) {
  double lo = INFINITY, hi = 0;
  for (int g = m->body_geomadr[b]; g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
    if (std::isnan(GeomVolume(m, g))) return {-1, -1};
    const mjtNum* s = m->geom_size + 3 * g;
    // mean squared distance of a uniform solid from its centre
    double within = 0;
    switch (m->geom_type[g]) {
      case mjGEOM_SPHERE:
        within = 0.6 * s[0] * s[0];
        break;
      case mjGEOM_ELLIPSOID:
        within = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]) / 5;
        break;
      case mjGEOM_BOX:
        within = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]) / 3;
        break;
      case mjGEOM_CYLINDER:
        within = s[0] * s[0] / 2 + s[1] * s[1] / 3;
        break;
      case mjGEOM_CAPSULE: {
        // the cylinder and the two hemispherical caps (centroid 3r/8 beyond the ends)
        double cylinder = M_PI * s[0] * s[0] * 2 * s[1];
        double caps = 4.0 / 3 * M_PI * std::pow(s[0], 3);
        within = (cylinder * (s[0] * s[0] / 2 + s[1] * s[1] / 3) +
                  caps * (s[1] * s[1] + 0.75 * s[1] * s[0] + 0.6 * s[0] * s[0])) /
                 (cylinder + caps);
        break;
      }
    }
    const mjtNum* p = m->geom_pos + 3 * g;
    double offset = (p[0] - com[0]) * (p[0] - com[0]) + (p[1] - com[1]) * (p[1] - com[1]) +
                    (p[2] - com[2]) * (p[2] - com[2]);
    lo = std::min(lo, std::sqrt(offset + within));
    hi = std::max(hi, std::sqrt(offset + within));
  }
  return hi > 0 ? std::make_pair(lo, hi) : std::make_pair(-1.0, -1.0);
}

// Extreme eigenvalues of the mass matrix by power iteration (with M) and inverse power
// iteration (with MuJoCo's sparse factorisation): fine for any nv.
std::pair<double, double> MassMatrixExtremes(const mjModel* m, mjData* d) {
  int nv = m->nv;
  std::vector<mjtNum> x(nv), y(nv);
  auto iterate = [&](bool inverse) {
    for (int i = 0; i < nv; ++i) x[i] = 1.0 + 0.01 * i;
    double lambda = 0;
    for (int it = 0; it < 200; ++it) {
      double norm = mju_norm(x.data(), nv);
      mju_scl(x.data(), x.data(), 1 / norm, nv);
      if (inverse) {
        mj_solveM(m, d, y.data(), x.data(), 1);
      } else {
        mj_mulM(m, d, y.data(), x.data());
      }
      double next = mju_dot(x.data(), y.data(), nv);
      x.swap(y);
      if (it > 10 && std::fabs(next - lambda) <= 1e-10 * std::fabs(next)) {
        lambda = next;
        break;
      }
      lambda = next;
    }
    return inverse ? 1 / lambda : lambda;
  };
  return {iterate(true), iterate(false)};
}

// How far, as a factor, the rms mass radius an inertia implies may lie from its geoms'
// before audit warns and fails (calibrated on every sample and dm_control model: see
// tests/check/audit_models_test.cc).
constexpr double kSpreadWarn = 3;
constexpr double kSpreadFail = 10;

void InertiaLayer(const Model& model, Data& data, std::vector<Finding>* out) {
  const mjModel* m = model.get();
  const char* L = "inertia";
  double total = 0;
  for (int b = 1; b < m->nbody; ++b) total += m->body_mass[b];
  out->push_back(Make(L, "inertia.total_mass", "", fmt::format("{:.6g} kg", total), "> 0 kg",
                      total > 0 || m->nv == 0 ? CheckStatus::kPass : CheckStatus::kFail,
                      total > 0 ? "sum of body masses as compiled"
                                : "nothing has mass: give geoms a mass or density"));
  // bodies welded together (no joint between them) move as one: mass conditioning is a
  // matter of these weld groups, not of the marker bodies inside them
  std::vector<double> group_mass(m->nbody, 0.0);
  std::vector<int> group_size(m->nbody, 0);
  for (int b = 1; b < m->nbody; ++b) {
    group_mass[m->body_weldid[b]] += m->body_mass[b];
    ++group_size[m->body_weldid[b]];
  }
  int listed = 0, moving = 0;
  for (int b = 1; b < m->nbody; ++b) {
    if (!Moves(m, b)) continue;
    ++moving;
    std::string element = Elem(model, mjOBJ_BODY, b, "body");
    const mjtNum* I = m->body_inertia + 3 * b;
    double mass = m->body_mass[b];
    bool weld_root = m->body_weldid[b] == b;
    // principal moments: positive and each no larger than the sum of the other two; a
    // massless body welded to its parent (a marker) has none and needs none
    double slack = 1e-9 * (I[0] + I[1] + I[2]);
    bool marker = !weld_root && mass == 0 && I[0] == 0 && I[1] == 0 && I[2] == 0;
    bool positive = marker || (I[0] > 0 && I[1] > 0 && I[2] > 0);
    bool triangle =
        I[0] + I[1] + slack >= I[2] && I[1] + I[2] + slack >= I[0] && I[0] + I[2] + slack >= I[1];
    if (!positive || !triangle) {
      out->push_back(Make(L, "inertia.principal", element,
                          fmt::format("I = ({:.4g}, {:.4g}, {:.4g}) kg*m^2", I[0], I[1], I[2]),
                          "> 0, triangle inequality", CheckStatus::kFail,
                          "no rigid body has these moments: fix <inertial diaginertia>, or let "
                          "the compiler derive them from geoms (inertiafromgeom), or use "
                          "<compiler balanceinertia=\"true\">"));
    }
    // tiny weld groups and extreme ratios between a group and the group it hangs from
    // make the mass matrix ill-conditioned
    if (weld_root) {
      double group = group_mass[b];
      std::string what = group_size[b] > 1 ? fmt::format("{:.3g} kg (with {} bodies welded to it)",
                                                         group, group_size[b] - 1)
                                           : fmt::format("{:.3g} kg", group);
      if (total > 0 && group < 1e-4 * total) {
        out->push_back(Make(L, "inertia.tiny_mass", element,
                            fmt::format("{} = {:.2g} of total", what, group / total),
                            ">= 1e-4 of total", CheckStatus::kWarn,
                            "a moving body this light makes the dynamics stiff and slow or "
                            "unstable: give it a realistic mass, add armature to its joint, or "
                            "weld it to its parent"));
      }
      int parent = m->body_weldid[m->body_parentid[b]];
      double parent_mass = group_mass[parent];
      if (parent > 0 && group > 0 && parent_mass > 0) {
        double ratio = std::max(group / parent_mass, parent_mass / group);
        if (ratio > 1e3) {
          out->push_back(
              Make(L, "inertia.mass_ratio", element,
                   fmt::format("{} vs parent {} {:.3g} kg: ratio {:.3g}", what,
                               Elem(model, mjOBJ_BODY, parent, "body"), parent_mass, ratio),
                   "<= 1e3", ratio > 1e6 ? CheckStatus::kFail : CheckStatus::kWarn,
                   "extreme mass ratios between a body and its parent ill-condition "
                   "the mass matrix: rebalance masses or add joint armature"));
        }
      }
    }
    // implied density from the volume of the body's primitive geoms
    double volume = 0;
    bool all_primitive = m->body_geomnum[b] > 0;
    for (int g = m->body_geomadr[b]; g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
      double v = GeomVolume(m, g);
      if (std::isnan(v)) all_primitive = false;
      if (!std::isnan(v)) volume += v;
    }
    if (all_primitive && volume > 0 && mass > 0) {
      double density = mass / volume;
      if (density < 1 || density > 25000) {
        out->push_back(
            Make(L, "inertia.density", element,
                 fmt::format("{:.4g} kg/m^3 ({:.4g} kg in {:.3g} m^3)", density, mass, volume),
                 "1 .. 25000 kg/m^3", CheckStatus::kWarn,
                 "no solid is this light or heavy (water 1000, steel 7850): check "
                 "the mass, the geom sizes and their units"));
      }
    }
    // inertia against mass and size: the principal moments say how far the mass lies
    // from the com on average (I1 + I2 + I3 = 2 * sum m r^2); the body's geoms say how
    // far it can lie. A factor kSpreadFail beyond them is no solid of this shape (a
    // 1000 kg pole with the 0.0094 kg*m^2 of a light one), kSpreadWarn is suspect.
    if (all_primitive && mass > 0 && positive && triangle && !marker) {
      auto [lo, hi] = GeomSpread(m, b, m->body_ipos + 3 * b);
      double implied = std::sqrt((I[0] + I[1] + I[2]) / (2 * mass));
      double factor = lo > 0 ? std::max(lo / implied, implied / hi) : 0;
      if (factor > kSpreadWarn) {
        bool low = implied < lo;
        std::string range =
            lo < hi ? fmt::format("{:.3g} .. {:.3g} m", lo, hi) : fmt::format("{:.3g} m", lo);
        out->push_back(Make(
            L, "inertia.size", element,
            fmt::format("I = ({:.3g}, {:.3g}, {:.3g}) kg*m^2 for {:.4g} kg puts the mass "
                        "{:.3g} m (rms) from the com; its geoms, filled uniformly: {}",
                        I[0], I[1], I[2], mass, implied, range),
            fmt::format("within x{:g} of {}", kSpreadWarn, range),
            factor > kSpreadFail ? CheckStatus::kFail : CheckStatus::kWarn,
            fmt::format("the inertia is {:.3g} times too {} for this mass and size: was the mass "
                        "changed without the inertia (it scales with the mass at fixed shape), or "
                        "<inertial diaginertia> given in other units? Omit <inertial> to let the "
                        "compiler derive both from the geoms",
                        factor * factor, low ? "small" : "large")));
      }
    }
    // centre of mass far outside the body's geoms
    if (m->body_geomnum[b] > 0) {
      const mjtNum* com = m->body_ipos + 3 * b;
      double nearest = INFINITY, reach = 0;
      for (int g = m->body_geomadr[b]; g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
        if (m->geom_type[g] == mjGEOM_PLANE) continue;
        double d = std::sqrt(std::pow(com[0] - m->geom_pos[3 * g], 2) +
                             std::pow(com[1] - m->geom_pos[3 * g + 1], 2) +
                             std::pow(com[2] - m->geom_pos[3 * g + 2], 2)) -
                   m->geom_rbound[g];
        nearest = std::min(nearest, d);
        reach = std::max(reach, m->geom_rbound[g]);
      }
      if (std::isfinite(nearest) && reach > 0 && nearest > reach) {
        out->push_back(Make(L, "inertia.com_outside", element,
                            fmt::format("com {:.3g} m outside its geoms", nearest),
                            fmt::format("<= {:.3g} m", reach), CheckStatus::kWarn,
                            "the centre of mass lies far outside the body's shape: check "
                            "<inertial pos> and the body frame"));
      }
    }
    if (listed < kMaxListed && !marker && positive && triangle) {
      ++listed;
      out->push_back(Make(
          L, "inertia.body", element,
          fmt::format("{:.4g} kg, I = ({:.3g}, {:.3g}, {:.3g}) kg*m^2", mass, I[0], I[1], I[2]), "",
          CheckStatus::kPass, "mass and principal inertia as compiled"));
    }
  }
  ListedNote(L, "inertia.body", "moving bodies", moving, out, listed);
  // condition number of the mass matrix at the reference pose
  if (m->nv > 0) {
    mj_forward(m, data.get());
    auto [lo, hi] = MassMatrixExtremes(m, data.get());
    double cond = hi / std::max(lo, 1e-300);
    out->push_back(
        Make(L, "inertia.mass_matrix", "",
             fmt::format("condition number {:.3g} (eigenvalues {:.3g} .. {:.3g})", cond, lo, hi),
             "<= 1e8", cond > 1e8 ? CheckStatus::kWarn : CheckStatus::kPass,
             cond > 1e8 ? "an ill-conditioned mass matrix slows the solver and loses "
                          "digits: add armature to light joints, rebalance masses"
                        : "mass matrix at the reference pose (mj_fullM) is "
                          "well-conditioned"));
  }
}

// ---- runs shared by the actuator, contact and behaviour layers ----------------------

struct Observed {
  std::string label;  // "passive settle", "step response of actuator 'elbow' (id 3)"
  RunResult result;
  double duration = 0;
  double deepest = 0;  // deepest penetration relative to the smaller geom size
  std::string deepest_pair;
  double deepest_late = 0;  // the same over the last part of the run, once impacts are over
  std::string deepest_late_pair;
  double deepest_m = 0, deepest_soft = 0;  // the deepest contact in m, and its SoftDepth
  double deepest_late_m = 0;     // that contact's penetration in m
  double deepest_late_soft = 0;  // and the depth its softness explains (SoftDepth), in m
  int max_iterations = 0;
  long steps_at_limit = 0;
  double energy0 = 0, energy_max = -INFINITY, energy_end = 0;
  double max_speed_end = 0;    // max |qvel| at the end
  double support_ratio = NAN;  // contact normal force / weight at the end
  double max_slip = 0;         // tangential speed at contacts at the end
  std::string slip_pair;
  std::string repro;
};

// Cost budget of one audit run, in dof-steps (steps x max(nv, 30)): about a second of
// compute on a laptop core, so each run of a big model is shortened, never skipped.
constexpr double kDofStepBudget = 4e5;

// `wanted` s of simulated time, shortened for big models to the dof-step budget (at
// least 20 steps), as a whole number of timesteps.
double Duration(const mjModel* m, double wanted, double budget = kDofStepBudget) {
  double steps = std::max(20.0, std::min(wanted / m->opt.timestep,
                                         budget / std::max(30.0, static_cast<double>(m->nv))));
  return std::ceil(steps) * m->opt.timestep;
}

// The repro folder of a diverged run ("" when none is wanted or it did not diverge).
std::string ReproOf(const Model& work, const RunResult& r, const AuditOptions& options,
                    const std::string& label) {
  if (!r.diverged || options.repro_dir.empty()) return "";
  return WriteRepro(work, r, options.argv, options.repro_dir,
                    "the audit run that diverged: " + label);
}

// What to do about a diverged audit run, after MuJoCo's reason.
std::string DivergedFix(const Observed& o) {
  return o.result.divergence->reason +
         " Fix: a smaller timestep (or the implicit integrator), joint damping or armature "
         "on the named joint, softer contacts or gains; plumb converge shows whether the "
         "timestep is the cause." +
         (o.repro.empty() ? "" : " Repro folder: " + o.repro + ".");
}

// ---- actuators -----------------------------------------------------------------------

// The force interval [lo, hi] actuator u can produce; infinite where nothing bounds it.
std::pair<double, double> ForceRange(const mjModel* m, int u) {
  double lo = -INFINITY, hi = INFINITY;
  if (m->actuator_forcelimited[u]) {
    lo = m->actuator_forcerange[2 * u];
    hi = m->actuator_forcerange[2 * u + 1];
  }
  const mjtNum* gain = m->actuator_gainprm + mjNGAIN * u;
  if (m->actuator_gaintype[u] == mjGAIN_MUSCLE) {
    // a muscle only pulls, at most its peak force F0 (gainprm[2], which mj_setConst
    // derives from scale) times the larger of the force-velocity and passive factors;
    // its control is implicitly 0..1
    double f0 = std::fabs(gain[2]);
    if (f0 > 0) {
      lo = std::max(lo, -f0 * (gain[8] + gain[7]));
      hi = std::min(hi, 0.0);
    }
  } else if (m->actuator_ctrllimited[u] && m->actuator_gaintype[u] == mjGAIN_FIXED &&
             m->actuator_biastype[u] == mjBIAS_NONE && m->actuator_dyntype[u] == mjDYN_NONE) {
    // a fixed-gain, bias-free actuator: force = gain * ctrl
    double a = gain[0] * m->actuator_ctrlrange[2 * u],
           b = gain[0] * m->actuator_ctrlrange[2 * u + 1];
    lo = std::max(lo, std::min(a, b));
    hi = std::min(hi, std::max(a, b));
  }
  return {lo, hi};
}

// What kind of response a ctrl step gives.
enum class ActuatorKind { kPositionServo, kVelocityServo, kMotor, kOther };

ActuatorKind KindOf(const mjModel* m, int u) {
  const mjtNum* bias = m->actuator_biasprm + mjNBIAS * u;
  bool fixed = m->actuator_gaintype[u] == mjGAIN_FIXED;
  if (fixed && m->actuator_biastype[u] == mjBIAS_AFFINE && bias[1] != 0) {
    return ActuatorKind::kPositionServo;
  }
  if (fixed && m->actuator_biastype[u] == mjBIAS_AFFINE && bias[2] != 0) {
    return ActuatorKind::kVelocityServo;
  }
  if (fixed && m->actuator_biastype[u] == mjBIAS_NONE && m->actuator_dyntype[u] == mjDYN_NONE) {
    return ActuatorKind::kMotor;
  }
  return ActuatorKind::kOther;
}

struct StepResponse {
  Observed run;
  std::string measured;  // in words
  bool moved = false;
};

// A step of ctrl by 10% of its range (0.1 when unlimited) from the reference pose,
// gravity and contacts off so only the actuator acts, every other ctrl at its middle.
// Servos: rise time to 63% of the step in their setpoint (length or velocity), overshoot
// and steady-state error. Motors have no setpoint: how far and how fast the step moves
// the actuator. Others (muscles, filtered actuators): how fast the force follows.
// `work` is a copy of the model with gravity and contacts off, `data` its data (reused
// from one actuator to the next: a big model's mjData costs more to make than to step).
StepResponse MeasureStep(Model& work, Data& data, const std::vector<Assignment>& sets,
                         const Reference& ref, int u, double duration, const AuditOptions& options,
                         const std::string& element) {
  StepResponse out;
  const mjModel* m = work.get();
  mj_resetData(m, data.get());
  StartAt(work, data, ref, sets);
  ActuatorKind kind = KindOf(m, u);
  bool limited = m->actuator_ctrllimited[u] || m->actuator_gaintype[u] == mjGAIN_MUSCLE;
  double lo = m->actuator_ctrllimited[u] ? m->actuator_ctrlrange[2 * u] : 0;
  double hi = m->actuator_ctrllimited[u]                 ? m->actuator_ctrlrange[2 * u + 1]
              : m->actuator_gaintype[u] == mjGAIN_MUSCLE ? 1
                                                         : 0;
  for (int i = 0; i < m->nu; ++i) {
    data->ctrl[i] = m->actuator_ctrllimited[i]
                        ? 0.5 * (m->actuator_ctrlrange[2 * i] + m->actuator_ctrlrange[2 * i + 1])
                        : 0;
  }
  data.Forward();
  double step = limited ? 0.1 * (hi - lo) : 0.1;
  double length0 = data->actuator_length[u];
  double before = data->ctrl[u];
  if (kind == ActuatorKind::kPositionServo) before = length0;  // hold where it is
  if (kind == ActuatorKind::kVelocityServo) before = 0;
  double after = before + step;
  if (limited && after > hi) after = before - step;  // stay inside ctrlrange
  data->ctrl[u] = before;
  data.Forward();
  auto quantity = [&](const mjData* d) {
    switch (kind) {
      case ActuatorKind::kPositionServo:
        return d->actuator_length[u];
      case ActuatorKind::kVelocityServo:
        return d->actuator_velocity[u];
      default:
        return d->actuator_force[u];
    }
  };
  double y0 = quantity(data.get());
  std::vector<double> t, y;
  double max_speed = 0;
  RunSpec spec;
  spec.until = duration;
  spec.every = m->opt.timestep;
  spec.before_step = [&](mjData* d, long) { d->ctrl[u] = after; };
  spec.after_step = [&](const mjData* d, long) {
    t.push_back(d->time);
    y.push_back(quantity(d));
    max_speed = std::max(max_speed, std::fabs(d->actuator_velocity[u]));
  };
  NullSink sink;
  out.run.label = "step response of " + element;
  out.run.duration = duration;
  out.run.result = Run(work, data, spec, sink);
  TakeMujocoWarnings();  // counted in the run's result, reported in the warnings layer
  out.run.repro = ReproOf(work, out.run.result, options, out.run.label);
  if (out.run.result.diverged || y.size() < 2) return out;
  double moved = data->actuator_length[u] - length0;
  if (kind == ActuatorKind::kMotor) {
    out.moved = std::fabs(moved) > 1e-9 || max_speed > 1e-9;
    // the actuator length is gear x the joint (tendon) position
    double gear = m->actuator_gear[6 * u];
    std::string unit = ActuatorPositionUnit(m, u);
    std::string by = gear == 1 ? fmt::format("{:.3g} {}", moved, unit)
                               : fmt::format("{:.3g} (gear {:g} x {:.3g} {} at the joint)", moved,
                                             gear, moved / gear, unit);
    out.measured = fmt::format(
        "no setpoint (motor): ctrl {:.3g} -> {:.3g} moves the actuator length by {} in {:g} s "
        "(peak speed {:.3g} {}/s{})",
        before, after, by, duration, max_speed / std::fabs(gear), unit,
        gear == 1 ? "" : " at the joint");
    return out;
  }
  // servos reach for their setpoint; other actuators' force settles where it settles
  bool servo = kind != ActuatorKind::kOther;
  double goal = servo ? after : y.back();
  double change = goal - y0;
  if (std::fabs(change) < 1e-12) return out;
  out.moved = true;
  double rise = NAN, peak = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    double share = (y[i] - y0) / change;
    if (std::isnan(rise) && share >= 0.63) rise = t[i] - t.front() + m->opt.timestep;
    peak = std::max(peak, share);
  }
  std::string rise_text =
      std::isfinite(rise) ? fmt::format("{:.3g} s", rise) : fmt::format("> {:g} s", duration);
  if (servo) {
    out.measured =
        fmt::format("{} servo: rise {}, overshoot {:.1f}%, steady-state error {:.1f}% after {:g} s",
                    kind == ActuatorKind::kPositionServo ? "position" : "velocity", rise_text,
                    100 * std::max(0.0, peak - 1),
                    100 * std::fabs(goal - y.back()) / std::fabs(change), duration);
  } else {
    out.measured = fmt::format("no setpoint ({}): force {:.3g} -> {:.3g}, rise {}",
                               m->actuator_gaintype[u] == mjGAIN_MUSCLE ? "muscle" : "actuator", y0,
                               y.back(), rise_text);
  }
  return out;
}

// At most this many actuators get a step response (evenly spaced when there are more).
constexpr int kStepActuators = 12;

void ActuatorLayer(const Model& original, const Model& model, Data& data,
                   const std::vector<Assignment>& sets, const Reference& ref,
                   const AuditOptions& options, std::vector<Observed>* runs,
                   std::vector<Finding>* out) {
  const mjModel* m = model.get();
  const char* L = "actuator";
  if (compat::ActuatorCount(m) == 0) {
    out->push_back(Make(L, "actuator.none", "", "no actuators", "", CheckStatus::kSkip,
                        "a passive model: nothing to check in this layer"));
    return;
  }
  // the generalized force each joint needs to hold the reference pose (qvel = 0)
  mju_zero(data->qvel, m->nv);
  data.Forward();
  int holding_rows = 0;
  for (int u = 0; u < compat::ActuatorCount(m); ++u) {
    std::string element = Elem(model, mjOBJ_ACTUATOR, u, "actuator");
    double gear = m->actuator_gear[6 * u];
    auto [flo, fhi] = ForceRange(m, u);
    if (!std::isfinite(flo) || !std::isfinite(fhi)) {
      out->push_back(Make(L, "actuator.limits", element,
                          fmt::format("ctrl {}, force {}, gear {:g}",
                                      m->actuator_ctrllimited[u] ? "limited" : "unlimited",
                                      m->actuator_forcelimited[u] ? "limited" : "unlimited", gear),
                          "a force bound", CheckStatus::kWarn,
                          "a real motor saturates: set ctrllimited/ctrlrange (and forcerange) "
                          "from the motor's datasheet, torque = gear x force"));
    }
    int trn = m->actuator_trntype[u];
    int joint = m->actuator_trnid[2 * u];
    bool joint_trn = trn == mjTRN_JOINT || trn == mjTRN_JOINTINPARENT;
    if (KindOf(m, u) == ActuatorKind::kPositionServo && joint_trn && m->jnt_limited[joint] &&
        m->actuator_ctrllimited[u] && gear != 0) {
      // a position servo's targets (ctrl / gear, in joint units) should lie within reach
      double lo = m->actuator_ctrlrange[2 * u] / gear, hi = m->actuator_ctrlrange[2 * u + 1] / gear;
      double jlo = m->jnt_range[2 * joint], jhi = m->jnt_range[2 * joint + 1];
      double margin = 0.5 * (jhi - jlo);
      if (std::min(lo, hi) < jlo - margin || std::max(lo, hi) > jhi + margin) {
        out->push_back(Make(L, "actuator.target_range", element,
                            fmt::format("targets [{:.4g}, {:.4g}] vs joint range [{:.4g}, {:.4g}]",
                                        lo, hi, jlo, jhi),
                            "within the joint range", CheckStatus::kWarn,
                            "the servo asks for positions its joint can never reach: make "
                            "ctrlrange match the joint range (and check the compiler's angle "
                            "units)"));
      }
    }
    if (joint_trn && (m->jnt_type[joint] == mjJNT_HINGE || m->jnt_type[joint] == mjJNT_SLIDE)) {
      // the actuator adds gear * force to its dof: it holds the pose when the needed
      // generalized force lies within gear * [flo, fhi], sign included
      double need = data->qfrc_bias[m->jnt_dofadr[joint]];
      double tlo = std::min(gear * flo, gear * fhi), thi = std::max(gear * flo, gear * fhi);
      if (gear == 0) tlo = thi = 0;
      double bound = need >= 0 ? thi : tlo;
      if (std::isfinite(bound) && holding_rows++ < kMaxListed) {
        bool weak = need > thi || need < tlo;
        out->push_back(
            Make(L, "actuator.holding", element,
                 fmt::format("delivers {:.4g} .. {:.4g}, gravity needs {:.4g} at {}", tlo, thi,
                             need, Elem(model, mjOBJ_JOINT, joint, "joint")),
                 fmt::format("{} {:.4g}", need >= 0 ? ">=" : "<=", need),
                 weak ? CheckStatus::kWarn : CheckStatus::kPass,
                 weak ? "it cannot hold its limb against gravity at the reference pose (in this "
                        "direction): raise the gear or the force/ctrl range on that side, or "
                        "lighten the limb"
                      : "gear x force range covers the gravity torque at the reference pose"));
      }
    }
  }
  ListedNote(L, "actuator.holding", "holding rows", holding_rows, out);
  // step responses, within one dof-step budget for all of them
  int count = std::min(compat::ActuatorCount(m), kStepActuators);
  double duration = Duration(m, 1.0, kDofStepBudget / count);
  Model work = original.Clone();
  work.get_mutable()->opt.disableflags |= mjDSBL_GRAVITY | mjDSBL_CONTACT;
  Data step_data(work);
  for (int i = 0; i < count; ++i) {
    int u = static_cast<int>(static_cast<long>(i) * compat::ActuatorCount(m) / count);
    std::string element = Elem(model, mjOBJ_ACTUATOR, u, "actuator");
    StepResponse r = MeasureStep(work, step_data, sets, ref, u, duration, options, element);
    runs->push_back(r.run);
    if (r.run.result.diverged) {
      out->push_back(Make(L, "actuator.step_response", element, "diverged", "stays finite",
                          CheckStatus::kFail, DivergedFix(r.run)));
      continue;
    }
    if (!r.moved) {
      out->push_back(Make(L, "actuator.step_response", element, "no response", "",
                          CheckStatus::kWarn,
                          fmt::format("a step in ctrl moved nothing in {:g} s (gravity and "
                                      "contacts off): check the transmission, gain and ctrl "
                                      "range",
                                      duration)));
      continue;
    }
    out->push_back(Make(L, "actuator.step_response", element, r.measured, "", CheckStatus::kPass,
                        "a step of 10% of ctrlrange from the reference pose, gravity and "
                        "contacts off"));
  }
  ListedNote(L, "actuator.step_response", "actuators", compat::ActuatorCount(m), out, count);
}

// Adds the steps and warnings of `part` (a later piece of the same run) to `total`.
void Append(RunResult* total, const RunResult& part) {
  for (const WarningSummary& w : part.warnings) {
    auto same = std::find_if(total->warnings.begin(), total->warnings.end(),
                             [&](const WarningSummary& v) { return v.kind == w.kind; });
    if (same == total->warnings.end()) {
      total->warnings.push_back(w);
      total->warnings.back().first_step += total->steps;
    } else {
      same->count += w.count;
      same->message = w.message;
    }
  }
  if (part.divergence) {
    // the piece counts its steps from its own start: number them from the run's start,
    // so that step and time agree (time = start + step * timestep)
    Divergence divergence = *part.divergence;
    std::string local = fmt::format("(in step {},", divergence.bad.step);
    std::size_t at = divergence.reason.find(local);
    if (at != std::string::npos) {
      divergence.reason.replace(at, local.size(),
                                fmt::format("(in step {},", divergence.bad.step + total->steps));
    }
    divergence.last_good.step += total->steps;
    divergence.bad.step += total->steps;
    total->divergence = std::move(divergence);
  }
  total->steps += part.steps;
  total->samples += part.samples;
  total->diverged = part.diverged;
}

// Max |qvel| below which a model counts as at rest.
constexpr double kRestSpeed = 0.05;

// Runs `model` after `sets` from `ref` under `control` for `duration` s in four pieces;
// when `longest` > duration it goes on, a quarter of `duration` at a time, until the
// model is at rest or `longest` s have passed. Penetration "late" is over the last
// piece, once impacts are over.
// How deep a resting contact sinks by design: MuJoCo's contacts are soft, a spring-damper
// reference a_ref = -b v - k r with k = 1 / (dmax^2 timeconst^2 dampratio^2) for solref =
// (timeconst, dampratio), timeconst at least two timesteps (k = -solref[0] / dmax^2 for a
// direct stiffness), dmax = solimp[1]. Carrying gravity on that spring takes r = |g| / k: 3.5
// mm for the default solref (0.02, 1), as a Go2 foot at rest shows (3.8 mm). Penetration is
// judged against the larger of this and solimp's width, not only against the geoms' size: a
// foot 2 cm across sinking 4 mm is the model's softness, not a fault.
double SoftDepth(const mjModel* m, const mjContact& c) {
  double dmax = std::clamp(c.solimp[1], 0.0001, 0.9999);
  double k;
  if (c.solref[0] > 0) {
    double timeconst = c.solref[0];
    if (compat::ReferenceTimeconstClamped(m)) timeconst = std::max(timeconst, 2 * m->opt.timestep);
    double dampratio = c.solref[1] > 0 ? c.solref[1] : 1;
    k = 1 / (dmax * dmax * timeconst * timeconst * dampratio * dampratio);
  } else {
    k = -c.solref[0] / (dmax * dmax);
  }
  double g = GravityNorm(m);
  // solimp's width is the depth over which the designer let the impedance ramp up (Menagerie's
  // Spot feet: 36 mm): sinking within it is the contact working as designed
  return std::max(k > 0 && g > 0 ? g / k : 0.0, c.solimp[2]);
}

Observed Observe(const Model& model, const std::vector<Assignment>& sets, const Reference& ref,
                 double duration, const std::function<void(mjData*, double)>& control,
                 const AuditOptions& options, const std::string& label, double longest = 0) {
  Observed o;
  o.label = label;
  Model work = model.Clone();
  work.get_mutable()->opt.enableflags |= mjENBL_ENERGY;
  const mjModel* m = work.get();
  Data data(work);
  StartAt(work, data, ref, sets);
  o.energy0 = data->energy[0] + data->energy[1];
  long piece_steps = std::max(1L, std::lround(duration / m->opt.timestep / 4));
  long min_pieces = 4,
       max_pieces =
           std::max(4L, static_cast<long>(std::floor(longest / (piece_steps * m->opt.timestep))));
  RunSpec spec;
  spec.until = piece_steps * m->opt.timestep;
  spec.every = m->opt.timestep;
  spec.before_step = [&](mjData* d, long) {
    if (control) control(d, d->time);
  };
  spec.after_step = [&](const mjData* d, long) {
    double e = d->energy[0] + d->energy[1];
    o.energy_max = std::max(o.energy_max, e);
    o.energy_end = e;
    int iterations = compat::SolverIterations(d);
    o.max_iterations = std::max(o.max_iterations, iterations);
    if (d->nefc > 0 && iterations >= m->opt.iterations) ++o.steps_at_limit;
    for (int i = 0; i < d->ncon; ++i) {
      const mjContact& c = d->contact[i];
      double size = INFINITY;
      for (int g : {c.geom1, c.geom2}) {
        if (m->geom_type[g] != mjGEOM_PLANE && m->geom_type[g] != mjGEOM_HFIELD) {
          size = std::min(size, m->geom_rbound[g]);
        }
      }
      if (!std::isfinite(size) || size <= 0) continue;
      double depth = -c.dist / size;
      if (depth > o.deepest) {
        o.deepest = depth;
        o.deepest_m = -c.dist;
        o.deepest_soft = SoftDepth(m, c);
        o.deepest_pair = Elem(work, mjOBJ_GEOM, c.geom1, "geom") + " / " +
                         Elem(work, mjOBJ_GEOM, c.geom2, "geom");
      }
      if (depth > o.deepest_late) {
        o.deepest_late = depth;
        o.deepest_late_pair = Elem(work, mjOBJ_GEOM, c.geom1, "geom") + " / " +
                              Elem(work, mjOBJ_GEOM, c.geom2, "geom");
        o.deepest_late_m = -c.dist;
        o.deepest_late_soft = SoftDepth(m, c);
      }
    }
  };
  NullSink sink;
  for (long piece = 0; piece < max_pieces; ++piece) {
    if (piece >= min_pieces) {
      double speed = 0;
      for (int i = 0; i < m->nv; ++i) speed = std::max(speed, std::fabs(data->qvel[i]));
      if (speed < kRestSpeed) break;
    }
    o.deepest_late = 0;  // only the last piece counts
    o.deepest_late_pair.clear();
    o.deepest_late_m = o.deepest_late_soft = 0;
    Append(&o.result, Run(work, data, spec, sink));
    if (o.result.diverged) break;
  }
  o.duration = o.result.steps * m->opt.timestep;
  TakeMujocoWarnings();  // counted in the run's result, reported in the warnings layer
  o.repro = ReproOf(work, o.result, options, label);
  if (o.result.diverged) return o;

  // the state at the end: at rest? supported? slipping?
  const mjData* d = data.get();
  for (int i = 0; i < m->nv; ++i)
    o.max_speed_end = std::max(o.max_speed_end, std::fabs(d->qvel[i]));
  double normal = 0;
  std::vector<mjtNum> jac1(3 * m->nv), jac2(3 * m->nv);
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    mjtNum force[6];
    mj_contactForce(m, d, i, force);
    int b1 = m->geom_bodyid[c.geom1], b2 = m->geom_bodyid[c.geom2];
    // the ground: the world and every static body welded to it
    if (m->body_weldid[b1] == 0 || m->body_weldid[b2] == 0) normal += force[0];
    // relative velocity of the two bodies at the contact point, tangential part
    mj_jac(m, d, jac1.data(), nullptr, c.pos, b1);
    mj_jac(m, d, jac2.data(), nullptr, c.pos, b2);
    mjtNum v1[3], v2[3], rel[3];
    mju_mulMatVec(v1, jac1.data(), d->qvel, 3, m->nv);
    mju_mulMatVec(v2, jac2.data(), d->qvel, 3, m->nv);
    mju_sub3(rel, v1, v2);
    double along = mju_dot3(rel, c.frame);
    double slip = std::sqrt(std::max(0.0, mju_dot3(rel, rel) - along * along));
    if (c.friction[0] > 0 && slip > o.max_slip) {
      o.max_slip = slip;
      o.slip_pair =
          Elem(work, mjOBJ_GEOM, c.geom1, "geom") + " / " + Elem(work, mjOBJ_GEOM, c.geom2, "geom");
    }
  }
  // weight of everything that floats freely (supported only by contacts)
  double floating = 0;
  for (int b = 1; b < m->nbody; ++b) {
    if (m->body_parentid[b] == 0 && m->body_jntnum[b] > 0 &&
        m->jnt_type[m->body_jntadr[b]] == mjJNT_FREE) {
      floating += m->body_subtreemass[b];
    }
  }
  double weight = floating * GravityNorm(m);
  if (weight > 0) o.support_ratio = normal / weight;
  return o;
}

void ContactLayer(const Model& model, const Observed& settle, std::vector<Finding>* out) {
  const mjModel* m = model.get();
  const char* L = "contact";
  CollisionGraph graph = MakeCollisionGraph(m);
  // per body: whether it can collide at all, and with what (visual-only geoms beside
  // separate collision geoms, as in the Menagerie, are normal)
  for (int b = 1; b < m->nbody; ++b) {
    std::vector<std::string> names;
    for (int p : graph.partners[b]) {
      names.push_back(p == 0 ? std::string("the world") : Elem(model, mjOBJ_BODY, p, "body"));
    }
    std::string with =
        names.empty() ? (graph.collides[b] ? "nothing: its contype/conaffinity meet no other geom's"
                                           : "nothing: visual geoms only, or no geoms")
        : names.size() <= 4
            ? fmt::format("{}", fmt::join(names, ", "))
            : fmt::format("{}, ... ({} bodies)", fmt::join(names.begin(), names.begin() + 3, ", "),
                          names.size());
    out->push_back(Make(L, "contact.collides_with", Elem(model, mjOBJ_BODY, b, "body"),
                        "collides with " + with, "", CheckStatus::kPass,
                        "which bodies this body's geoms can touch (contype/conaffinity, <pair>, "
                        "<exclude>, parent-child filter)"));
  }
  // a free body that can touch nothing static, directly or through other bodies, falls
  // forever (under gravity; <flag gravity="disable"/> means nothing falls)
  for (int b = 1; b < m->nbody && GravityNorm(m) > 0; ++b) {
    if (m->body_parentid[b] != 0 || m->body_jntnum[b] == 0 ||
        m->jnt_type[m->body_jntadr[b]] != mjJNT_FREE) {
      continue;
    }
    if (!graph.grounded[b]) {
      // a robot description with no floor is meant to be included by a scene: a warning that
      // says so; a model with a floor that this body cannot reach is wrong
      bool fragment = !graph.static_collider;
      out->push_back(Make(
          L, "contact.free_fall", Elem(model, mjOBJ_BODY, b, "body"),
          fragment ? "nothing static in the model can collide (no floor)"
                   : "none of its geoms can reach a static geom through collisions",
          "a collision chain to the world", fragment ? CheckStatus::kWarn : CheckStatus::kFail,
          fragment ? "a free body under gravity with no floor falls forever: if this file is a "
                     "robot description that a scene includes (as Menagerie's robot.xml and "
                     "scene.xml), audit the scene; else add a floor"
                   : "a free body under gravity that collides with nothing static falls "
                     "forever: give one of its geoms contype/conaffinity that match the "
                     "floor's, or add a <contact><pair>"));
      continue;
    }
    // resting on the ground only through a much lighter free body: its contacts carry a
    // weight far beyond their own, the ill-conditioned case of MuJoCo's soft contacts
    int s = graph.support[b];
    double mass = m->body_subtreemass[b];
    if (s > 0 && graph.support_mass[b] > 0 && mass > 10 * graph.support_mass[b]) {
      out->push_back(Make(
          L, "contact.heavy_on_light", Elem(model, mjOBJ_BODY, b, "body"),
          fmt::format("{:.3g} kg reaches the ground only through {} ({:.3g} kg)", mass,
                      Elem(model, mjOBJ_BODY, s, "body"), graph.support_mass[b]),
          "<= 10 x the lightest body on its way to the ground", CheckStatus::kWarn,
          "a heavy body that can rest only on a much lighter one loads that body's contacts "
          "far beyond its own weight: let the heavy body's geoms collide with the floor, or "
          "check the lighter body's mass"));
    }
  }
  if (settle.result.diverged) {
    out->push_back(Make(L, "contact.settle", "", "the settle run diverged", "", CheckStatus::kFail,
                        DivergedFix(settle)));
    return;
  }
  bool any_contact =
      settle.deepest > 0 || !settle.deepest_pair.empty() || settle.max_iterations > 0;
  bool at_rest = settle.max_speed_end < kRestSpeed;
  // judged at rest, once impacts are over (the last quarter-second piece of the settle);
  // the peak during impacts alone is a warning, and so is a deep contact in a model
  // still moving when the settle budget ran out
  // at rest, a contact deeper than a tenth of the smaller geom is judged against the depth
  // its softness explains (SoftDepth): only a contact beyond 3x that is a warning, beyond 10x
  // (and half the geom) a failure
  double late = settle.deepest_late;
  double soft = settle.deepest_late_soft;
  double excess = soft > 0 ? settle.deepest_late_m / soft : INFINITY;
  double impact_excess =
      settle.deepest_soft > 0 ? settle.deepest_m / settle.deepest_soft : INFINITY;
  CheckStatus status = late > 0.5 && at_rest && excess > 10 ? CheckStatus::kFail
                       : (late > 0.1 && excess > 3) || (settle.deepest > 0.5 && impact_excess > 10)
                           ? CheckStatus::kWarn
                           : CheckStatus::kPass;
  std::string measured =
      fmt::format("{:.3g} of the smaller geom's size at the end, {:.3g} at the worst impact", late,
                  settle.deepest);
  if (settle.deepest_late_m > 0 && soft > 0) {
    measured += fmt::format("; {:.3g} mm deep at the end, {:.2g}x the {:.3g} mm its solref/solimp "
                            "soften it by",
                            1e3 * settle.deepest_late_m, excess, 1e3 * soft);
  }
  if (!at_rest) {
    measured += fmt::format("; did not settle in {:g} s (max |qvel| {:.3g} at the end)",
                            settle.duration, settle.max_speed_end);
  }
  out->push_back(Make(
      L, "contact.penetration", late > 0.1 ? settle.deepest_late_pair : settle.deepest_pair,
      measured,
      "<= 0.1 of the geom or <= 3x the soft-contact depth at the end (FAIL > 0.5 and > 10x at "
      "rest); <= 0.5 of the geom or <= 10x the soft depth at impacts",
      status,
      status == CheckStatus::kPass
          ? fmt::format("deepest contact penetration during a {:g} s settle", settle.duration)
      : at_rest ? "geoms sink deep into each other: stiffen solref (smaller time constant, at "
                  "least 2 timesteps), raise solimp, or shrink the timestep"
                : "geoms sink deep into each other while the model still moves: judge again at "
                  "rest (plumb run for longer), or stiffen solref / raise solimp"));
  if (std::isfinite(settle.support_ratio) && at_rest) {
    double r = settle.support_ratio;
    out->push_back(Make(L, "contact.support", "",
                        fmt::format("contact normal force / weight = {:.3f}", r), "0.9 .. 1.1",
                        r > 0.9 && r < 1.1 ? CheckStatus::kPass : CheckStatus::kWarn,
                        r > 0.9 && r < 1.1 ? "at rest, the ground carries the free bodies' weight"
                                           : "at rest but the contacts do not carry the weight: "
                                             "check contact softness (solref/solimp) and "
                                             "equality constraints"));
    out->push_back(Make(
        L, "contact.slip", settle.slip_pair, fmt::format("{:.3g} m/s", settle.max_slip),
        "<= 0.01 m/s", settle.max_slip <= 0.01 ? CheckStatus::kPass : CheckStatus::kWarn,
        settle.max_slip <= 0.01 ? "contacts that should stick do not slide at rest"
                                : "a resting contact still slides: raise friction, use condim 4-6 "
                                  "or an elliptic cone, or more solver iterations"));
  } else if (!std::isnan(settle.support_ratio)) {
    out->push_back(Make(L, "contact.support", "",
                        fmt::format("did not settle in {:g} s: max |qvel| {:.3g} at the end",
                                    settle.duration, settle.max_speed_end),
                        fmt::format("< {:g} to judge", kRestSpeed), CheckStatus::kSkip,
                        "the model does not come to rest within the settle budget: support "
                        "and slip are judged only at rest"));
  }
  if (m->nv > 0 && (any_contact || m->neq > 0)) {
    double share = settle.result.steps > 0
                       ? static_cast<double>(settle.steps_at_limit) / settle.result.steps
                       : 0;
    out->push_back(Make(L, "contact.solver", "",
                        fmt::format("max {} of {} iterations; at the limit in {:.0f}% of steps",
                                    settle.max_iterations, m->opt.iterations, 100 * share),
                        "at the limit in <= 10% of steps",
                        share > 0.1 ? CheckStatus::kWarn : CheckStatus::kPass,
                        share > 0.1 ? "the constraint solver often stops at its iteration "
                                      "limit: raise <option iterations>, use the Newton solver, "
                                      "or loosen tolerance"
                                    : "the solver converges within its iteration limit"));
  }
  for (const WarningSummary& w : settle.result.warnings) {
    if (w.kind == "CONTACTFULL" || w.kind == "CNSTRFULL") {
      out->push_back(Make(L, "contact.buffer", "", fmt::format("{} x{}", w.kind, w.count), "0",
                          CheckStatus::kFail,
                          "contacts or constraints were dropped: raise <size nconmax/njmax> "
                          "(MuJoCo 2.x) or memory (3.x)"));
    }
  }
}

// ---- behaviour ------------------------------------------------------------------------


// A run is bounded when its total energy stays within `allowed_rise` x max(1 J, |E0|)
// above where it started: a passive run has no energy source, a driven one does.
Finding RunFinding(const char* check, const std::string& what, const Observed& o,
                   double allowed_rise) {
  const char* L = "behaviour";
  if (o.result.diverged) {
    return Make(L, check, what, "diverged", "stays finite", CheckStatus::kFail, DivergedFix(o));
  }
  double scale = std::max(1.0, std::fabs(o.energy0));
  double rise = (o.energy_max - o.energy0) / scale;
  CheckStatus status = rise > 20 * allowed_rise ? CheckStatus::kFail
                       : rise > allowed_rise    ? CheckStatus::kWarn
                                                : CheckStatus::kPass;
  return Make(
      L, check, what,
      fmt::format("{:g} s, energy {:.4g} -> max {:.4g} J", o.duration, o.energy0, o.energy_max),
      fmt::format("no NaN; energy rise <= {:g} x max(1 J, |E0|)", allowed_rise), status,
      status == CheckStatus::kPass
          ? "stays finite and bounded"
          : "energy grows without a matching source: check contact parameters, the "
            "timestep and actuator gains");
}

void BehaviourLayer(const Model& model, const std::vector<Assignment>& sets, const Reference& ref,
                    const Observed& settle, const AuditOptions& options,
                    std::vector<Observed>* runs, std::vector<Finding>* out) {
  const mjModel* m = model.get();
  const char* L = "behaviour";
  out->push_back(
      RunFinding("behaviour.passive_settle", "zero control from " + ref.description, settle, 0.5));
  if (m->nu > 0) {
    // smoothed Halton noise within ctrlrange, as MuJoCo's testspeed and Menagerie's tests
    auto control = [m](mjData* d, double t) {
      long k = static_cast<long>(t / 0.1);
      static constexpr int kPrimes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37};
      for (int i = 0; i < m->nu; ++i) {
        double h = mju_Halton(static_cast<int>(k + 1), kPrimes[i % 12]) * 2 - 1;
        double lo = m->actuator_ctrllimited[i] ? m->actuator_ctrlrange[2 * i] : -1;
        double hi = m->actuator_ctrllimited[i] ? m->actuator_ctrlrange[2 * i + 1] : 1;
        double target = 0.5 * (lo + hi) + 0.5 * (hi - lo) * 0.5 * h;
        d->ctrl[i] += 0.05 * (target - d->ctrl[i]);  // smoothed
      }
    };
    runs->push_back(Observe(model, sets, ref, Duration(m, 2.0), control, options, "control noise"));
    // actuators feed energy in: only a runaway counts
    out->push_back(RunFinding("behaviour.control_noise",
                              "smoothed Halton noise at half of each ctrlrange", runs->back(), 50));
  }
  if (!options.scenario) return;
  const Scenario& sc = *options.scenario;
  Reference start = ref;
  if (sc.keyframe >= 0) {
    start.keyframe = sc.keyframe;
    start.description = "keyframe " + model.Name(mjOBJ_KEY, sc.keyframe);
  }
  // the user's --set first, then the scenario's initial state on top
  std::vector<Assignment> all = sets;
  all.insert(all.end(), sc.initial.begin(), sc.initial.end());
  // every assertion on every one of its paths at every step (after mj_forward, so
  // derived quantities describe the state just reached)
  struct Tally {
    bool ok = true;  // every sample so far (no reduction)
    double first_bad = NAN, first_bad_time = 0;
    double reduced = 0;  // over time
    bool seen = false;
  };
  std::vector<std::vector<Tally>> tallies(sc.assertions.size());
  for (std::size_t a = 0; a < sc.assertions.size(); ++a) {
    tallies[a].resize(sc.assertions[a].paths.size());
  }
  Model work = model.Clone();
  Data data(work);
  StartAt(work, data, start, all);
  RunSpec spec;
  spec.until = StepsToReach(sc.duration, m->opt.timestep) * m->opt.timestep;
  spec.every = m->opt.timestep;
  spec.before_step = [&](mjData* d, long) {
    for (const ControlSchedule& c : sc.controls) d->ctrl[c.id] = c.At(d->time);
  };
  auto holds = [](const std::string& op, double v, double bound) {
    return op == "<" ? v < bound : op == "<=" ? v <= bound : op == ">" ? v > bound : v >= bound;
  };
  auto check = [&](double time) {
    for (std::size_t a = 0; a < sc.assertions.size(); ++a) {
      const Assertion& as = sc.assertions[a];
      double end = as.to < 0 ? INFINITY : as.to;
      if (time < as.from - 1e-12 || time > end + 1e-12) continue;
      for (std::size_t k = 0; k < as.paths.size(); ++k) {
        Tally& t = tallies[a][k];
        double v = ReadValue(work, data, as.paths[k]);
        if (as.reduce.empty()) {
          if (!holds(as.op, v, as.bound) && t.ok) {
            t.ok = false;
            t.first_bad = v;
            t.first_bad_time = time;
          }
        } else if (as.reduce == "maxabs") {
          t.reduced = t.seen ? std::max(t.reduced, std::fabs(v)) : std::fabs(v);
        } else if (as.reduce == "max") {
          t.reduced = t.seen ? std::max(t.reduced, v) : v;
        } else if (as.reduce == "min") {
          t.reduced = t.seen ? std::min(t.reduced, v) : v;
        } else {
          t.reduced = v;  // final: the last sample in the window
        }
        t.seen = true;
      }
    }
  };
  data.Forward();
  check(data->time);
  DerivedRefresher refresh(work.get());
  spec.after_step = [&](const mjData* d, long) {
    refresh(data.get());
    check(d->time);
  };
  NullSink sink;
  Observed scenario_run;
  scenario_run.label = "scenario " + sc.name;
  scenario_run.duration = spec.until;
  scenario_run.result = Run(work, data, spec, sink);
  TakeMujocoWarnings();  // counted in the run's result, reported in the warnings layer
  scenario_run.repro = ReproOf(work, scenario_run.result, options, "scenario " + sc.file);
  runs->push_back(scenario_run);
  if (scenario_run.result.diverged) {
    out->push_back(Make(L, "behaviour.scenario", sc.name, "diverged", "stays finite",
                        CheckStatus::kFail, DivergedFix(scenario_run)));
    return;
  }
  for (std::size_t a = 0; a < sc.assertions.size(); ++a) {
    const Assertion& as = sc.assertions[a];
    // every path must satisfy it: report the first that does not, else the closest call
    bool ok = true;
    std::string measured = "no sample in the window";
    double closest = INFINITY;
    for (std::size_t k = 0; k < as.paths.size(); ++k) {
      const Tally& t = tallies[a][k];
      const std::string& name = as.paths[k].text;
      if (!t.seen) {
        ok = false;
        break;
      }
      if (as.reduce.empty()) {
        if (!t.ok) {
          ok = false;
          measured = fmt::format("{} = {:.6g} at t = {:g} s", name, t.first_bad, t.first_bad_time);
          break;
        }
        measured = as.paths.size() == 1
                       ? "holds at every step"
                       : fmt::format("holds at every step for all {} paths", as.paths.size());
        continue;
      }
      std::string value = fmt::format("{}({}) = {:.6g}", as.reduce, name, t.reduced);
      if (!holds(as.op, t.reduced, as.bound)) {
        ok = false;
        measured = value;
        break;
      }
      double margin = std::fabs(t.reduced - as.bound);
      if (margin < closest) {
        closest = margin;
        measured =
            value +
            (as.paths.size() > 1 ? fmt::format(" (closest of {} paths)", as.paths.size()) : "");
      }
    }
    out->push_back(Make(L, "behaviour.assertion", sc.name + ": " + as.text, measured,
                        fmt::format("{} {:g}", as.op, as.bound),
                        ok ? CheckStatus::kPass : CheckStatus::kFail,
                        ok ? "the scenario's assertion holds"
                           : "the scenario's assertion fails: the model does not do what the "
                             "scenario expects"));
  }
}

}  // namespace

int AuditReport::Count(CheckStatus status) const {
  return static_cast<int>(std::count_if(findings.begin(), findings.end(),
                                        [&](const Finding& f) { return f.status == status; }));
}

AuditReport Audit(const Model& model, const AuditOptions& options) {
  AuditReport report;
  report.model = model.file();
  // the reference pose: --keyframe, else keyframe home/test (or qpos0), then the user's --set,
  // state assignments included
  Model nominal = model.Clone();
  Data data(nominal);
  Reference ref = FindReference(nominal, options.keyframe);
  StartAt(nominal, data, ref, options.sets);
  TakeMujocoWarnings();

  std::vector<Observed> runs;
  StructureLayer(nominal, &report.findings);
  InertiaLayer(nominal, data, &report.findings);
  ActuatorLayer(model, nominal, data, options.sets, ref, options, &runs, &report.findings);

  const mjModel* m = nominal.get();
  // the settle goes on past 2 s (up to 10 s, within 2.5 run budgets) until at rest
  Observed settle = Observe(model, options.sets, ref, Duration(m, 2.0), nullptr, options,
                            "passive settle", Duration(m, 10.0, 2.5 * kDofStepBudget));
  runs.push_back(settle);
  ContactLayer(nominal, settle, &report.findings);
  BehaviourLayer(nominal, options.sets, ref, settle, options, &runs, &report.findings);

  // every MuJoCo warning raised on the way, with the run that raised it
  bool any = false;
  for (const Observed& o : runs) {
    for (const WarningSummary& w : o.result.warnings) {
      any = true;
      report.findings.push_back(Make(
          "warnings", "warnings.mujoco", w.kind,
          fmt::format("x{} in the {}, first at t = {:g} s", w.count, o.label, w.first_time), "none",
          CheckStatus::kWarn, w.message + (o.repro.empty() ? "" : " Repro folder: " + o.repro)));
    }
    if (!o.repro.empty()) report.repro_folders.push_back(o.repro);
  }
  if (!any) {
    report.findings.push_back(Make("warnings", "warnings.mujoco", "", "none", "none",
                                   CheckStatus::kPass, "no MuJoCo warning in any audit run"));
  }
  return report;
}

}  // namespace plumb
