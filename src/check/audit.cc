// The five layers of model acceptance, after the chapter's section 1.3.5: structure,
// inertia, actuator, contact, behaviour; plus every MuJoCo warning raised on the way.

#include "plumb/audit.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "core/mujoco_compat.h"
#include "plumb/error.h"
#include "plumb/output.h"

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
  return {layer,  std::move(check), std::move(element), std::move(measured), std::move(threshold),
          status, std::move(fix)};
}

// The subtree of every body: is `b` inside the subtree rooted at `root`?
bool InSubtree(const mjModel* m, int b, int root) {
  while (b > 0 && b != root) b = m->body_parentid[b];
  return b == root;
}

// Moving bodies: those not welded to the world.
bool Moves(const mjModel* m, int b) { return b > 0 && m->body_weldid[b] != 0; }

double GeomVolume(const mjModel* m, int g) {
  const mjtNum* s = m->geom_size + 3 * g;
  switch (m->geom_type[g]) {
    case mjGEOM_SPHERE:
      return 4.0 / 3 * M_PI * s[0] * s[0] * s[0];
    case mjGEOM_CAPSULE:
      return M_PI * s[0] * s[0] * 2 * s[1] + 4.0 / 3 * M_PI * std::pow(s[0], 3);
    case mjGEOM_CYLINDER:
      return M_PI * s[0] * s[0] * 2 * s[1];
    case mjGEOM_BOX:
      return 8 * s[0] * s[1] * s[2];
    case mjGEOM_ELLIPSOID:
      return 4.0 / 3 * M_PI * s[0] * s[1] * s[2];
    default:
      return -1;  // planes, meshes, height fields: no volume we can trust here
  }
}

// The reference pose: keyframe "home" or "test" if present, else qpos0; then --set.
struct Reference {
  int keyframe = -1;
  std::string description;
};

Reference FindReference(const Model& model) {
  Reference ref;
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
    int obj;
    int count;
  } kinds[] = {{"joint", mjOBJ_JOINT, m->njnt},
               {"actuator", mjOBJ_ACTUATOR, m->nu},
               {"sensor", mjOBJ_SENSOR, m->nsensor},
               {"body", mjOBJ_BODY, m->nbody}};
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
    out->push_back(Make(L, std::string("structure.unnamed_") + k.noun + "s",
                        fmt::format("{}s {}", k.noun, list),
                        fmt::format("{} unnamed", unnamed.size()), "0", CheckStatus::kWarn,
                        fmt::format("name every {}: controllers, logs and plumb paths "
                                    "(qpos[name]) refer to {}s by name, ids shift when the "
                                    "model changes",
                                    k.noun, k.noun)));
  }

  // joints: type, axis, addresses, range
  for (int j = 0; j < m->njnt; ++j) {
    int type = m->jnt_type[j];
    std::string element = Elem(model, mjOBJ_JOINT, j, "joint");
    double lo = m->jnt_range[2 * j], hi = m->jnt_range[2 * j + 1];
    bool limited = m->jnt_limited[j];
    std::string range = limited ? fmt::format("[{:.4g}, {:.4g}]", lo, hi) : "unlimited";
    if (limited && hi <= lo) {
      out->push_back(Make(L, "structure.joint_range", element, range, "lower < upper",
                          CheckStatus::kFail,
                          "a limited joint with an empty range is locked: give range=\"lo hi\" "
                          "or drop limited"));
      continue;
    }
    bool rotational = type == mjJNT_HINGE || type == mjJNT_BALL;
    if (limited && ((rotational && hi - lo > 4 * M_PI) || (type == mjJNT_SLIDE && hi - lo > 100))) {
      out->push_back(Make(L, "structure.joint_range", element, range,
                          rotational ? "<= 4*pi rad" : "<= 100 m", CheckStatus::kWarn,
                          rotational ? "a range wider than two turns never engages: was it "
                                       "written in degrees with <compiler angle=\"radian\">?"
                                     : "a slide range this long never engages: check units"));
      continue;
    }
    // MJCF angles are degrees unless <compiler angle="radian">: radians written there
    // become a range 57 times too narrow
    if (limited && type == mjJNT_HINGE && hi - lo < 0.1) {
      out->push_back(Make(L, "structure.joint_range", element, range + " rad", ">= 0.1 rad",
                          CheckStatus::kWarn,
                          fmt::format("a hinge range of {:.2g} degrees barely moves: MJCF reads "
                                      "angles in degrees unless <compiler angle=\"radian\">; "
                                      "were radians written?",
                                      (hi - lo) * 180 / M_PI)));
      continue;
    }
    if (m->njnt <= kMaxListed) {
      const mjtNum* axis = m->jnt_axis + 3 * j;
      out->push_back(Make(L, "structure.joint", element,
                          fmt::format("{} axis ({:.3g} {:.3g} {:.3g}) qpos[{}] dof[{}] range {}",
                                      compat::NameOf(compat::kJointTypes, type), axis[0], axis[1],
                                      axis[2], m->jnt_qposadr[j], m->jnt_dofadr[j], range),
                          "", CheckStatus::kPass,
                          "type, axis (body frame), addresses and range as compiled"));
    }
  }
  if (m->njnt > kMaxListed) {
    out->push_back(Make(L, "structure.joint", "", fmt::format("{} joints", m->njnt), "",
                        CheckStatus::kPass,
                        fmt::format("too many to list; plumb inspect shows each")));
  }

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
  for (int u = 0; u < m->nu && m->nu <= kMaxListed; ++u) {
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
  for (int s = 0; s < m->nsensor && m->nsensor <= kMaxListed; ++s) {
    out->push_back(Make(L, "structure.sensor", Elem(model, mjOBJ_SENSOR, s, "sensor"),
                        fmt::format("{} sensordata[{}..{}]",
                                    compat::NameOf(compat::kSensorTypes, m->sensor_type[s]),
                                    m->sensor_adr[s], m->sensor_adr[s] + m->sensor_dim[s] - 1),
                        "", CheckStatus::kPass, "sensor type and its place in sensordata"));
  }
}

// ---- inertia -------------------------------------------------------------------------

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

void InertiaLayer(const Model& model, Data& data, std::vector<Finding>* out) {
  const mjModel* m = model.get();
  const char* L = "inertia";
  double total = 0;
  for (int b = 1; b < m->nbody; ++b) total += m->body_mass[b];
  out->push_back(Make(L, "inertia.total_mass", "", fmt::format("{:.6g} kg", total), "> 0 kg",
                      total > 0 || m->nv == 0 ? CheckStatus::kPass : CheckStatus::kFail,
                      total > 0 ? "sum of body masses as compiled"
                                : "nothing has mass: give geoms a mass or density"));
  int listed = 0, bad = 0;
  for (int b = 1; b < m->nbody; ++b) {
    if (!Moves(m, b)) continue;
    std::string element = Elem(model, mjOBJ_BODY, b, "body");
    const mjtNum* I = m->body_inertia + 3 * b;
    double mass = m->body_mass[b];
    // principal moments: positive and each no larger than the sum of the other two
    double slack = 1e-9 * (I[0] + I[1] + I[2]);
    bool positive = I[0] > 0 && I[1] > 0 && I[2] > 0;
    bool triangle =
        I[0] + I[1] + slack >= I[2] && I[1] + I[2] + slack >= I[0] && I[0] + I[2] + slack >= I[1];
    if (!positive || !triangle) {
      ++bad;
      out->push_back(Make(L, "inertia.principal", element,
                          fmt::format("I = ({:.4g}, {:.4g}, {:.4g}) kg*m^2", I[0], I[1], I[2]),
                          "> 0, triangle inequality", CheckStatus::kFail,
                          "no rigid body has these moments: fix <inertial diaginertia>, or let "
                          "the compiler derive them from geoms (inertiafromgeom), or use "
                          "<compiler balanceinertia=\"true\">"));
    }
    // tiny bodies and extreme ratios make the mass matrix ill-conditioned
    int parent = m->body_parentid[b];
    double parent_mass = m->body_mass[parent];
    if (total > 0 && mass < 1e-4 * total) {
      ++bad;
      out->push_back(Make(L, "inertia.tiny_mass", element,
                          fmt::format("{:.3g} kg = {:.2g} of total", mass, mass / total),
                          ">= 1e-4 of total", CheckStatus::kWarn,
                          "a moving body this light makes the dynamics stiff and slow or "
                          "unstable: give it a realistic mass, add armature to its joint, or "
                          "weld it to its parent"));
    }
    if (parent > 0 && mass > 0 && parent_mass > 0) {
      double ratio = std::max(mass / parent_mass, parent_mass / mass);
      if (ratio > 1e3) {
        ++bad;
        out->push_back(
            Make(L, "inertia.mass_ratio", element,
                 fmt::format("{:.3g} kg vs parent {} {:.3g} kg: ratio {:.3g}", mass,
                             Elem(model, mjOBJ_BODY, parent, "body"), parent_mass, ratio),
                 "<= 1e3", ratio > 1e6 ? CheckStatus::kFail : CheckStatus::kWarn,
                 "extreme mass ratios between a body and its parent ill-condition "
                 "the mass matrix: rebalance masses or add joint armature"));
      }
    }
    // implied density from the volume of the body's primitive geoms
    double volume = 0;
    bool all_primitive = m->body_geomnum[b] > 0;
    for (int g = m->body_geomadr[b]; g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
      double v = GeomVolume(m, g);
      if (v < 0) all_primitive = false;
      volume += std::max(0.0, v);
    }
    if (all_primitive && volume > 0 && mass > 0) {
      double density = mass / volume;
      if (density < 1 || density > 25000) {
        ++bad;
        out->push_back(
            Make(L, "inertia.density", element,
                 fmt::format("{:.4g} kg/m^3 ({:.4g} kg in {:.3g} m^3)", density, mass, volume),
                 "1 .. 25000 kg/m^3", CheckStatus::kWarn,
                 "no solid is this light or heavy (water 1000, steel 7850): check "
                 "the mass, the geom sizes and their units"));
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
        ++bad;
        out->push_back(Make(L, "inertia.com_outside", element,
                            fmt::format("com {:.3g} m outside its geoms", nearest),
                            fmt::format("<= {:.3g} m", reach), CheckStatus::kWarn,
                            "the centre of mass lies far outside the body's shape: check "
                            "<inertial pos> and the body frame"));
      }
    }
    if (listed < kMaxListed && (positive && triangle)) {
      ++listed;
      out->push_back(Make(
          L, "inertia.body", element,
          fmt::format("{:.4g} kg, I = ({:.3g}, {:.3g}, {:.3g}) kg*m^2", mass, I[0], I[1], I[2]), "",
          CheckStatus::kPass, "mass and principal inertia as compiled"));
    }
  }
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
  (void)bad;
}

// ---- actuators -----------------------------------------------------------------------

// Largest |force| actuator u can produce, or infinity when nothing bounds it.
double ForceBound(const mjModel* m, int u) {
  double bound = INFINITY;
  if (m->actuator_forcelimited[u]) {
    bound = std::max(std::fabs(m->actuator_forcerange[2 * u]),
                     std::fabs(m->actuator_forcerange[2 * u + 1]));
  }
  // a fixed-gain, bias-free actuator with limited control: |force| <= gain * |ctrl|
  if (m->actuator_ctrllimited[u] && m->actuator_gaintype[u] == mjGAIN_FIXED &&
      m->actuator_biastype[u] == mjBIAS_NONE && m->actuator_dyntype[u] == mjDYN_NONE) {
    double c = std::max(std::fabs(m->actuator_ctrlrange[2 * u]),
                        std::fabs(m->actuator_ctrlrange[2 * u + 1]));
    bound = std::min(bound, std::fabs(m->actuator_gainprm[mjNGAIN * u]) * c);
  }
  return bound;
}

struct StepResponse {
  bool measured = false;
  std::string quantity;
  double rise = NAN, overshoot = NAN, error = NAN;
};

// A step of ctrl from its middle to 10% of its range above (0 -> 0.1 when unlimited),
// gravity and contacts off so only the actuator acts, for 1 s.
StepResponse MeasureStep(const Model& model, const std::vector<Assignment>& sets,
                         const Reference& ref, int u) {
  StepResponse out;
  Model work = model.Clone();
  mjModel* m = work.get_mutable();
  m->opt.disableflags |= mjDSBL_GRAVITY | mjDSBL_CONTACT;
  Data data(work);
  StartAt(work, data, ref, sets);
  double lo = m->actuator_ctrllimited[u] ? m->actuator_ctrlrange[2 * u] : 0;
  double hi = m->actuator_ctrllimited[u] ? m->actuator_ctrlrange[2 * u + 1] : 0;
  double mid = m->actuator_ctrllimited[u] ? 0.5 * (lo + hi) : 0;
  double step = m->actuator_ctrllimited[u] ? 0.1 * (hi - lo) : 0.1;
  bool servo =
      m->actuator_biastype[u] == mjBIAS_AFFINE && m->actuator_biasprm[mjNBIAS * u + 1] != 0;
  std::vector<double> t, y;
  // servos: the actuator length tracks the target; others: the force follows ctrl
  out.quantity = servo ? "length" : "force";
  for (int i = 0; i < m->nu; ++i) {
    data->ctrl[i] = m->actuator_ctrllimited[i]
                        ? 0.5 * (m->actuator_ctrlrange[2 * i] + m->actuator_ctrlrange[2 * i + 1])
                        : 0;
  }
  data.Forward();
  double y0 = servo ? data->actuator_length[u] : data->actuator_force[u];
  double target = servo ? mid + step : NAN;
  if (servo) {
    // a position servo holds ctrl = its target length; start from where it is
    data->ctrl[u] = y0;
    target = y0 + step;
  }
  RunSpec spec;
  spec.until = std::ceil(1.0 / m->opt.timestep) * m->opt.timestep;
  spec.every = m->opt.timestep;
  spec.before_step = [&](mjData* d, long) { d->ctrl[u] = servo ? target : mid + step; };
  spec.after_step = [&](const mjData* d, long) {
    t.push_back(d->time);
    y.push_back(servo ? d->actuator_length[u] : d->actuator_force[u]);
  };
  NullSink sink;
  RunResult r = Run(work, data, spec, sink);
  TakeMujocoWarnings();
  if (r.diverged || y.size() < 3) return out;
  double final = y.back();
  double goal = servo ? target : final;
  double change = goal - y0;
  if (std::fabs(change) < 1e-12) return out;
  out.measured = true;
  for (std::size_t i = 0; i < y.size(); ++i) {
    if ((y[i] - y0) / change >= 0.63) {
      out.rise = t[i] - t.front() + m->opt.timestep;
      break;
    }
  }
  double peak = 0;
  for (double v : y) peak = std::max(peak, (v - y0) / change);
  out.overshoot = std::max(0.0, peak - 1);
  out.error = std::fabs(goal - final) / std::fabs(change);
  return out;
}

void ActuatorLayer(const Model& original, const Model& model, Data& data,
                   const std::vector<Assignment>& sets, const Reference& ref,
                   std::vector<Finding>* out) {
  const mjModel* m = model.get();
  const char* L = "actuator";
  if (m->nu == 0) {
    out->push_back(Make(L, "actuator.none", "", "no actuators", "", CheckStatus::kSkip,
                        "a passive model: nothing to check in this layer"));
    return;
  }
  // the gravity torque each joint must hold at the reference pose (qvel = 0)
  mju_zero(data->qvel, m->nv);
  data.Forward();
  for (int u = 0; u < m->nu; ++u) {
    std::string element = Elem(model, mjOBJ_ACTUATOR, u, "actuator");
    double gear = m->actuator_gear[6 * u];
    double bound = ForceBound(m, u);
    if (!std::isfinite(bound)) {
      out->push_back(Make(L, "actuator.limits", element,
                          fmt::format("ctrl {}, force unlimited, gear {:g}",
                                      m->actuator_ctrllimited[u] ? "limited" : "unlimited", gear),
                          "a force bound", CheckStatus::kWarn,
                          "a real motor saturates: set ctrllimited/ctrlrange (and forcerange) "
                          "from the motor's datasheet, torque = gear x force"));
    }
    int trn = m->actuator_trntype[u];
    int joint = m->actuator_trnid[2 * u];
    bool servo =
        m->actuator_biastype[u] == mjBIAS_AFFINE && m->actuator_biasprm[mjNBIAS * u + 1] != 0;
    if (servo && (trn == mjTRN_JOINT || trn == mjTRN_JOINTINPARENT) && m->jnt_limited[joint] &&
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
    if ((trn == mjTRN_JOINT || trn == mjTRN_JOINTINPARENT) &&
        (m->jnt_type[joint] == mjJNT_HINGE || m->jnt_type[joint] == mjJNT_SLIDE)) {
      int dof = m->jnt_dofadr[joint];
      double hold = std::fabs(data->qfrc_bias[dof]);
      double deliver = std::fabs(gear) * bound;
      if (std::isfinite(deliver)) {
        bool weak = deliver < hold;
        out->push_back(
            Make(L, "actuator.holding", element,
                 fmt::format("max {:.4g} vs gravity {:.4g} at {}", deliver, hold,
                             Elem(model, mjOBJ_JOINT, joint, "joint")),
                 fmt::format(">= {:.4g}", hold), weak ? CheckStatus::kWarn : CheckStatus::kPass,
                 weak ? "it cannot hold its limb against gravity at the reference pose: raise the "
                        "gear or the force/ctrl range, or lighten the limb"
                      : "gear x force bound exceeds the gravity torque at the reference pose"));
      }
    }
  }
  // step responses (the first kMaxListed actuators)
  for (int u = 0; u < m->nu && u < kMaxListed; ++u) {
    StepResponse r = MeasureStep(original, sets, ref, u);
    std::string element = Elem(model, mjOBJ_ACTUATOR, u, "actuator");
    if (!r.measured) {
      out->push_back(Make(L, "actuator.step_response", element, "no response", "",
                          CheckStatus::kWarn,
                          "a step in ctrl moved nothing in 1 s (gravity and contacts off): "
                          "check the transmission, gain and ctrl range"));
      continue;
    }
    out->push_back(Make(L, "actuator.step_response", element,
                        fmt::format("{}: rise {} s, overshoot {:.1f}%, error {:.1f}%", r.quantity,
                                    std::isfinite(r.rise) ? fmt::format("{:.3g}", r.rise) : "> 1",
                                    100 * r.overshoot, 100 * r.error),
                        "", CheckStatus::kPass,
                        "step of 10% of ctrlrange, gravity and contacts off: rise time to 63%, "
                        "overshoot, steady-state error after 1 s"));
  }
}

// ---- runs shared by the contact and behaviour layers --------------------------------

struct Observed {
  RunResult result;
  double duration = 0;
  double deepest = 0;  // deepest penetration relative to the smaller geom size
  std::string deepest_pair;
  double deepest_late = 0;  // the same over the last quarter, once impacts are over
  std::string deepest_late_pair;
  int max_iterations = 0;
  long steps_at_limit = 0;
  double energy0 = 0, energy_max = -INFINITY, energy_end = 0;
  double max_speed_end = 0;    // max |qvel| at the end
  double support_ratio = NAN;  // contact normal force / weight at the end
  double max_slip = 0;         // tangential speed at contacts at the end
  std::string slip_pair;
  std::vector<std::string> warnings_text;
  std::string repro;
};

double Duration(const mjModel* m, double wanted) {
  double steps =
      std::max(20.0, std::min(wanted / m->opt.timestep, 1e5 / std::max(1.0, (double)m->nv)));
  return std::ceil(steps) * m->opt.timestep;
}

Observed Observe(const Model& model, const std::vector<Assignment>& sets, const Reference& ref,
                 double duration, const std::function<void(mjData*, double)>& control,
                 const AuditOptions& options, const std::string& label) {
  Observed o;
  Model work = model.Clone();
  work.get_mutable()->opt.enableflags |= mjENBL_ENERGY;
  const mjModel* m = work.get();
  Data data(work);
  StartAt(work, data, ref, sets);
  o.duration = duration;
  o.energy0 = data->energy[0] + data->energy[1];
  RunSpec spec;
  spec.until = duration;
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
        o.deepest_pair = Elem(work, mjOBJ_GEOM, c.geom1, "geom") + " / " +
                         Elem(work, mjOBJ_GEOM, c.geom2, "geom");
      }
      if (d->time >= 0.75 * duration && depth > o.deepest_late) {
        o.deepest_late = depth;
        o.deepest_late_pair = Elem(work, mjOBJ_GEOM, c.geom1, "geom") + " / " +
                              Elem(work, mjOBJ_GEOM, c.geom2, "geom");
      }
    }
  };
  NullSink sink;
  o.result = Run(work, data, spec, sink);
  o.warnings_text = TakeMujocoWarnings();
  if (o.result.diverged && !options.repro_dir.empty()) {
    std::vector<std::string> argv = options.argv;
    argv.push_back("# audit run: " + label);
    o.repro = WriteRepro(work, o.result, argv, options.repro_dir);
  }
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
    if (b1 == 0 || b2 == 0) normal += force[0];
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
  double weight = floating * mju_norm3(m->opt.gravity);
  if (weight > 0) o.support_ratio = normal / weight;
  return o;
}

// Can any geom of the subtree at `root` collide with anything outside it?
bool CanTouchOutside(const mjModel* m, int root) {
  for (int g = 0; g < m->ngeom; ++g) {
    if (!InSubtree(m, m->geom_bodyid[g], root)) continue;
    for (int h = 0; h < m->ngeom; ++h) {
      if (InSubtree(m, m->geom_bodyid[h], root)) continue;
      if ((m->geom_contype[g] & m->geom_conaffinity[h]) ||
          (m->geom_contype[h] & m->geom_conaffinity[g])) {
        return true;
      }
    }
  }
  for (int p = 0; p < m->npair; ++p) {
    bool in1 = InSubtree(m, m->geom_bodyid[m->pair_geom1[p]], root);
    bool in2 = InSubtree(m, m->geom_bodyid[m->pair_geom2[p]], root);
    if (in1 != in2) return true;
  }
  return false;
}

void ContactLayer(const Model& model, const Observed& settle, std::vector<Finding>* out) {
  const mjModel* m = model.get();
  const char* L = "contact";
  bool gravity = mju_norm3(m->opt.gravity) > 0;
  // a free body that can touch nothing falls forever
  for (int b = 1; b < m->nbody; ++b) {
    if (m->body_parentid[b] != 0 || m->body_jntnum[b] == 0 ||
        m->jnt_type[m->body_jntadr[b]] != mjJNT_FREE) {
      continue;
    }
    bool touches = CanTouchOutside(m, b);
    if (!touches && gravity) {
      out->push_back(Make(L, "contact.free_fall", Elem(model, mjOBJ_BODY, b, "body"),
                          "no geom can collide with the world", "at least one colliding geom",
                          CheckStatus::kFail,
                          "a free body under gravity that collides with nothing falls forever: "
                          "give one of its geoms contype/conaffinity that match the floor's, or "
                          "add a <contact><pair>"));
    }
  }
  if (settle.result.diverged) {
    out->push_back(Make(L, "contact.settle", "", "the settle run diverged", "", CheckStatus::kFail,
                        settle.result.divergence->reason));
    return;
  }
  bool any_contact =
      settle.deepest > 0 || !settle.deepest_pair.empty() || settle.max_iterations > 0;
  // judged once impacts are over (the last quarter of the settle); the peak during
  // impacts alone is a warning
  double late = settle.deepest_late;
  CheckStatus status = late > 0.5                           ? CheckStatus::kFail
                       : late > 0.1 || settle.deepest > 0.5 ? CheckStatus::kWarn
                                                            : CheckStatus::kPass;
  out->push_back(Make(
      L, "contact.penetration", late > 0.1 ? settle.deepest_late_pair : settle.deepest_pair,
      fmt::format("{:.3g} of the smaller geom's size at the end, {:.3g} at the worst impact", late,
                  settle.deepest),
      "<= 0.1 at the end (FAIL > 0.5); <= 0.5 at impacts", status,
      status != CheckStatus::kPass
          ? "geoms sink deep into each other: stiffen solref (smaller time constant, at least 2 "
            "timesteps), raise solimp, or shrink the timestep"
          : fmt::format("deepest contact penetration during a {:g} s settle", settle.duration)));
  bool at_rest = settle.max_speed_end < 0.05;
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
                        fmt::format("max |qvel| {:.3g} at the end", settle.max_speed_end),
                        "< 0.05 to judge", CheckStatus::kSkip,
                        "the model does not come to rest in the settle run"));
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

// The i-th element of the Halton sequence in `base`, in [0, 1).
double Halton(long i, int base) {
  double f = 1, r = 0;
  for (long n = i + 1; n > 0; n /= base) {
    f /= base;
    r += f * (n % base);
  }
  return r;
}

// A run is bounded when its total energy stays within `allowed_rise` x max(1 J, |E0|)
// above where it started: a passive run has no energy source, a driven one does.
Finding RunFinding(const char* check, const std::string& what, const Observed& o,
                   double allowed_rise) {
  const char* L = "behaviour";
  if (o.result.diverged) {
    return Make(
        L, check, what, "diverged", "stays finite", CheckStatus::kFail,
        o.result.divergence->reason + (o.repro.empty() ? "" : " Repro folder: " + o.repro + "."));
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
        double h = Halton(k, kPrimes[i % 12]) * 2 - 1;
        double lo = m->actuator_ctrllimited[i] ? m->actuator_ctrlrange[2 * i] : -1;
        double hi = m->actuator_ctrllimited[i] ? m->actuator_ctrlrange[2 * i + 1] : 1;
        double target = 0.5 * (lo + hi) + 0.5 * (hi - lo) * 0.5 * h;
        d->ctrl[i] += 0.05 * (target - d->ctrl[i]);  // smoothed
      }
    };
    runs->push_back(Observe(model, sets, ref, Duration(m, 2.0), control, options, "control noise"));
    // actuators feed energy in: only a runaway counts
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
  std::vector<Assignment> all = sets;
  all.insert(all.end(), sc.initial.begin(), sc.initial.end());
  // evaluate every assertion at every step
  struct Tally {
    bool ok = true;
    double worst = NAN, worst_time = 0, reduced = 0;
    bool seen = false;
  };
  std::vector<Tally> tallies(sc.assertions.size());
  Model work = model.Clone();
  Data data(work);
  StartAt(work, data, start, all);
  RunSpec spec;
  spec.until = std::ceil(sc.duration / m->opt.timestep) * m->opt.timestep;
  spec.every = m->opt.timestep;
  spec.before_step = [&](mjData* d, long) {
    for (const ControlSchedule& c : sc.controls) d->ctrl[c.id] = c.At(d->time);
  };
  auto holds = [](const std::string& op, double v, double bound) {
    return op == "<" ? v < bound : op == "<=" ? v <= bound : op == ">" ? v > bound : v >= bound;
  };
  auto check = [&](const mjData* d) {
    for (std::size_t a = 0; a < sc.assertions.size(); ++a) {
      const Assertion& as = sc.assertions[a];
      double end = as.to < 0 ? INFINITY : as.to;
      if (d->time < as.from - 1e-12 || d->time > end + 1e-12) continue;
      Tally& t = tallies[a];
      for (const Path& p : as.paths) {
        double v = ReadValue(work, data, p);
        if (as.reduce.empty()) {
          bool ok = holds(as.op, v, as.bound);
          if (!ok && t.ok) {
            t.ok = false;
            t.worst = v;
            t.worst_time = d->time;
          }
        } else if (as.reduce == "maxabs") {
          t.reduced = t.seen ? std::max(t.reduced, std::fabs(v)) : std::fabs(v);
        } else if (as.reduce == "max") {
          t.reduced = t.seen ? std::max(t.reduced, v) : v;
        } else if (as.reduce == "min") {
          t.reduced = t.seen ? std::min(t.reduced, v) : v;
        } else {
          t.reduced = v;  // final
        }
        t.seen = true;
      }
    }
  };
  check(data.get());
  spec.after_step = [&](const mjData* d, long) { check(d); };
  NullSink sink;
  RunResult r = Run(work, data, spec, sink);
  std::vector<std::string> warnings = TakeMujocoWarnings();
  Observed scenario_run;
  scenario_run.result = r;
  scenario_run.duration = spec.until;
  if (r.diverged && !options.repro_dir.empty()) {
    std::vector<std::string> argv = options.argv;
    argv.push_back("# audit scenario: " + sc.file);
    scenario_run.repro = WriteRepro(work, r, argv, options.repro_dir);
  }
  runs->push_back(scenario_run);
  if (r.diverged) {
    out->push_back(Make(L, "behaviour.scenario", sc.name, "diverged", "stays finite",
                        CheckStatus::kFail, r.divergence->reason));
    return;
  }
  for (std::size_t a = 0; a < sc.assertions.size(); ++a) {
    const Assertion& as = sc.assertions[a];
    const Tally& t = tallies[a];
    std::string measured;
    bool ok = t.seen;
    if (!t.seen) {
      measured = "no sample in the window";
    } else if (as.reduce.empty()) {
      ok = t.ok;
      measured =
          t.ok ? "holds at every step" : fmt::format("{:.6g} at t = {:g} s", t.worst, t.worst_time);
    } else {
      ok = holds(as.op, t.reduced, as.bound);
      measured = fmt::format("{} = {:.6g}", as.reduce, t.reduced);
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
  Model nominal = model.Clone();
  Data data(nominal);
  ApplyAssignments(nominal, data, options.sets);
  Reference ref = FindReference(nominal);
  StartAt(nominal, data, ref, {});
  TakeMujocoWarnings();

  StructureLayer(nominal, &report.findings);
  InertiaLayer(nominal, data, &report.findings);
  ActuatorLayer(model, nominal, data, options.sets, ref, &report.findings);

  std::vector<Observed> runs;
  const mjModel* m = nominal.get();
  runs.push_back(
      Observe(model, options.sets, ref, Duration(m, 2.0), nullptr, options, "passive settle"));
  const Observed& settle = runs.front();
  ContactLayer(nominal, settle, &report.findings);
  BehaviourLayer(nominal, options.sets, ref, settle, options, &runs, &report.findings);

  // every MuJoCo warning raised on the way
  bool any = false;
  for (const Observed& o : runs) {
    for (const WarningSummary& w : o.result.warnings) {
      any = true;
      report.findings.push_back(Make(
          "warnings", "warnings.mujoco", w.kind,
          fmt::format("x{}, first at t = {:g} s", w.count, w.first_time), "none",
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
