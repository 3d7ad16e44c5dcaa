// Audit: mirror pairs that do not mirror. Left and right limbs, fingers and legs come in
// pairs named alike ("left_knee_link" / "right_knee_link", "FL_thigh" / "FR_thigh",
// "hl_hip" / "hr_hip"); a mirror keeps masses, principal moments, range widths, gains and gear
// magnitudes, so a pair that differs beyond kMirrorTolerance was edited on one side only.
// Signs are compared only where a mirror keeps them: joint actuators on axle-like hinges (see
// SignsDisagree), and there a pair whose axes point opposite ways with mirrored ranges ([lo, hi]
// against [-hi, -lo]) follows a deliberate convention and is no finding.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "audit/audit_layers.h"
#include "core/mujoco_compat.h"
#include "core/strings.h"

namespace plumb::audit {
using internal::Lowercase;

namespace {

// How far (relative) a mirror pair's values may differ: clean robots' pairs agree to 1e-3
// (rounding in their CAD exports), a mass changed by 30% on one side does not.
constexpr double kMirrorTolerance = 0.1;

// `name` with its side swapped: the '_'-separated part left/right (any case), l/r, or a
// two-letter leg code ending in L/R (FL, RR, hl), else "".
std::string MirrorName(const std::string& name) {
  std::vector<std::string> parts;
  size_t start = 0;
  for (size_t i = 0; i <= name.size(); ++i) {
    if (i == name.size() || name[i] == '_') {
      parts.push_back(name.substr(start, i - start));
      start = i + 1;
    }
  }
  bool swapped = false;
  for (std::string& p : parts) {
    std::string lower = Lowercase(p);
    auto recase = [&](const std::string& to) {
      std::string out = to;
      for (size_t i = 0; i < out.size() && i < p.size(); ++i) {
        if (std::isupper(static_cast<unsigned char>(p[i])))
          out[i] = static_cast<char>(std::toupper(out[i]));
      }
      if (p.size() > 1 &&
          std::all_of(p.begin(), p.end(), [](unsigned char c) { return std::isupper(c); })) {
        std::transform(out.begin(), out.end(), out.begin(),
                       [](unsigned char c) { return std::toupper(c); });
      }
      return out;
    };
    if (lower == "left" || lower == "right") {
      p = recase(lower == "left" ? "right" : "left");
      swapped = true;
    } else if (lower == "l" || lower == "r") {
      p = recase(lower == "l" ? "r" : "l");
      swapped = true;
    } else if (p.size() == 2 && std::isalpha(static_cast<unsigned char>(p[0])) &&
               (lower[1] == 'l' || lower[1] == 'r')) {
      char side = lower[1] == 'l' ? 'r' : 'l';
      p[1] = std::isupper(static_cast<unsigned char>(p[1])) ? static_cast<char>(std::toupper(side))
                                                            : side;
      swapped = true;
    }
  }
  if (!swapped) return "";
  std::string out;
  for (size_t i = 0; i < parts.size(); ++i) out += (i ? "_" : "") + parts[i];
  return out;
}

// The pairs (a < b) of elements of type `obj` whose names mirror each other.
std::vector<std::pair<int, int>> Pairs(const Model& model, int obj, int count) {
  std::vector<std::pair<int, int>> out;
  for (int a = 0; a < count; ++a) {
    std::string name = model.Name(obj, a);
    if (name.empty()) continue;
    std::string mirror = MirrorName(name);
    if (mirror.empty()) continue;
    int b = mj_name2id(model.get(), obj, mirror.c_str());
    if (b > a) out.emplace_back(a, b);
  }
  return out;
}

double RelativeDifference(double a, double b) {
  double scale = std::max(std::fabs(a), std::fabs(b));
  return scale > 0 ? std::fabs(std::fabs(a) - std::fabs(b)) / scale : 0;
}

// One row for pair (a, b) of `obj` whose `what` differ: `values` as the two sides give them.
void Mismatch(const Model& model, const char* layer, const char* check, int obj, const char* noun,
              int a, int b, const std::string& what, double difference, const std::string& values,
              std::vector<CheckRow>* out) {
  CheckRow row = WithNumbers(
      Make(layer, check,
           fmt::format("{} / {}", Elem(model, obj, a, noun), Elem(model, obj, b, noun)),
           fmt::format("{} differ by {:.3g}%: {}", what, 100 * difference, values),
           fmt::format("<= {:g}% apart", 100 * kMirrorTolerance), CheckStatus::kWarn,
           fmt::format("a mirror pair should agree in {}: one side was edited without the other "
                       "(or the pair is not a mirror: accept it in an accept list)",
                       what)),
      {difference, ""}, {kMirrorTolerance, ""});
  row.element = ElementOf(model, obj, a, noun);
  out->push_back(std::move(row));
}

// One PASS row saying how many pairs agreed, when there were pairs and none differed.
void Agreed(const char* layer, const char* check, const char* nouns, int pairs, size_t before,
            std::vector<CheckRow>* out) {
  if (pairs == 0 || out->size() != before) return;
  out->push_back(WithNumbers(
      Make(layer, check, "", fmt::format("{} mirror pairs of {} agree", pairs, nouns),
           fmt::format("<= {:g}% apart", 100 * kMirrorTolerance), CheckStatus::kPass,
           "pairs named alike (left/right, FL/FR, ...) compared by magnitude; the signs of "
           "a pair on axle-like hinges by the way one ctrl turns them"),
      {static_cast<double>(pairs), ""}));
}

}  // namespace

void MirrorBodies(const Model& model, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  auto pairs = Pairs(model, mjOBJ_BODY, static_cast<int>(m->nbody));
  size_t before = out->size();
  for (auto [a, b] : pairs) {
    double mass = RelativeDifference(m->body_mass[a], m->body_mass[b]);
    if (mass > kMirrorTolerance) {
      Mismatch(model, "inertia", "inertia.mirror", mjOBJ_BODY, "body", a, b, "masses", mass,
               fmt::format("{:.4g} kg / {:.4g} kg", m->body_mass[a], m->body_mass[b]), out);
      continue;
    }
    std::array<double, 3> ia{}, ib{};
    for (int k = 0; k < 3; ++k) {
      ia[k] = m->body_inertia[3 * a + k];
      ib[k] = m->body_inertia[3 * b + k];
    }
    std::sort(ia.begin(), ia.end());
    std::sort(ib.begin(), ib.end());
    double moment = 0;
    for (int k = 0; k < 3; ++k) moment = std::max(moment, RelativeDifference(ia[k], ib[k]));
    // a moment far below the others' (a thin rod's axis) carries no weight in the comparison
    if (moment > kMirrorTolerance && ia[2] > 0) {
      double largest = 0;
      for (int k = 0; k < 3; ++k) {
        if (std::max(ia[k], ib[k]) > 0.01 * ia[2])
          largest = std::max(largest, RelativeDifference(ia[k], ib[k]));
      }
      moment = largest;
    }
    if (moment > kMirrorTolerance) {
      Mismatch(model, "inertia", "inertia.mirror", mjOBJ_BODY, "body", a, b, "principal moments",
               moment,
               fmt::format("({:.3g}, {:.3g}, {:.3g}) / ({:.3g}, {:.3g}, {:.3g}) kg*m^2", ia[0],
                           ia[1], ia[2], ib[0], ib[1], ib[2]),
               out);
    }
  }
  Agreed("inertia", "inertia.mirror", "bodies", static_cast<int>(pairs.size()), before, out);
}

void MirrorJoints(const Model& model, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  auto pairs = Pairs(model, mjOBJ_JOINT, static_cast<int>(m->njnt));
  size_t before = out->size();
  for (auto [a, b] : pairs) {
    if (m->jnt_limited[a] != m->jnt_limited[b]) {
      Mismatch(model, "structure", "structure.mirror", mjOBJ_JOINT, "joint", a, b, "limits", 1,
               fmt::format("{} / {}", m->jnt_limited[a] ? "limited" : "unlimited",
                           m->jnt_limited[b] ? "limited" : "unlimited"),
               out);
      continue;
    }
    if (!m->jnt_limited[a]) continue;
    double wa = m->jnt_range[2 * a + 1] - m->jnt_range[2 * a];
    double wb = m->jnt_range[2 * b + 1] - m->jnt_range[2 * b];
    double width = RelativeDifference(wa, wb);
    if (width > kMirrorTolerance) {
      Mismatch(model, "structure", "structure.mirror", mjOBJ_JOINT, "joint", a, b, "range widths",
               width,
               fmt::format("[{:.4g}, {:.4g}] / [{:.4g}, {:.4g}]", m->jnt_range[2 * a],
                           m->jnt_range[2 * a + 1], m->jnt_range[2 * b], m->jnt_range[2 * b + 1]),
               out);
    }
  }
  Agreed("structure", "structure.mirror", "joints", static_cast<int>(pairs.size()), before, out);
}

// Whether a mirror pair of joint actuators on axle-like joints push opposite ways: both joints'
// axes lie along the line between them (wheels, knees, hip pitch), where a rotation and its
// mirror image have the same sense, so gear x axis (in the world at `d`'s pose) should point
// the same way for both; opposite, one ctrl spins one wheel forward and the other back. Joints
// whose axes cross that line are not judged: mirrored axes there are written either way (the
// dm_control humanoid's shoulders).
bool SignsDisagree(const mjModel* m, const mjData* d, int a, int b, int ja, int jb) {
  if (m->jnt_type[ja] != mjJNT_HINGE || m->jnt_type[jb] != mjJNT_HINGE) return false;
  double ga = m->actuator_gear[6 * compat::ActuatorOutputs(m, a).first];
  double gb = m->actuator_gear[6 * compat::ActuatorOutputs(m, b).first];
  if (ga == 0 || gb == 0) return false;
  mjtNum n[3], va[3], vb[3];
  mju_sub3(n, d->xanchor + 3 * ja, d->xanchor + 3 * jb);
  if (mju_normalize3(n) < 1e-9) return false;
  mju_scl3(va, d->xaxis + 3 * ja, ga > 0 ? 1 : -1);
  mju_scl3(vb, d->xaxis + 3 * jb, gb > 0 ? 1 : -1);
  bool axles = std::fabs(mju_dot3(n, va)) > 0.9 && std::fabs(mju_dot3(n, vb)) > 0.9;
  return axles && mju_dot3(va, vb) < -0.9;
}

namespace {

// Whether joints ja and jb have mirrored ranges, [lo, hi] against [-hi, -lo] (within
// kMirrorTolerance of the width): the convention of a pair whose axes were written to point
// opposite ways on purpose, each range following its axis (Booster T1's elbows).
bool MirroredRanges(const mjModel* m, int ja, int jb) {
  if (!m->jnt_limited[ja] || !m->jnt_limited[jb]) return false;
  const mjtNum* ra = m->jnt_range + 2 * ja;
  const mjtNum* rb = m->jnt_range + 2 * jb;
  double width = std::max(ra[1] - ra[0], rb[1] - rb[0]);
  if (!(width > 0)) return false;
  bool same = std::fabs(ra[0] - rb[0]) + std::fabs(ra[1] - rb[1]) <= kMirrorTolerance * width;
  bool mirrored =
      std::fabs(ra[0] + rb[1]) + std::fabs(ra[1] + rb[0]) <= kMirrorTolerance * width;
  return mirrored && !same;
}

// The row of a pair of joint actuators whose senses disagree (SignsDisagree): what differs is
// the gears' signs when they differ, else the joints' axes.
void SenseMismatch(const Model& model, const Data& data, int a, int b, int ja, int jb,
                   std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  double ga = m->actuator_gear[6 * compat::ActuatorOutputs(m, a).first];
  double gb = m->actuator_gear[6 * compat::ActuatorOutputs(m, b).first];
  const mjtNum* xa = data->xaxis + 3 * ja;
  const mjtNum* xb = data->xaxis + 3 * jb;
  auto range = [&](int j) {
    return m->jnt_limited[j] ? fmt::format("range [{:.4g}, {:.4g}]", m->jnt_range[2 * j],
                                           m->jnt_range[2 * j + 1])
                             : std::string("unlimited");
  };
  bool gears = (ga > 0) != (gb > 0);
  Mismatch(model, "actuator", "actuator.mirror", mjOBJ_ACTUATOR, "actuator", a, b,
           gears ? "gear signs" : "axis senses", 1,
           fmt::format("gear {:g} on {} (world axis {:.2f} {:.2f} {:.2f}, {}) / gear {:g} on {} "
                       "(world axis {:.2f} {:.2f} {:.2f}, {}): their axes lie along the line "
                       "between them, and the same ctrl turns them opposite ways",
                       ga, Elem(model, mjOBJ_JOINT, ja, "joint"), xa[0], xa[1], xa[2], range(ja),
                       gb, Elem(model, mjOBJ_JOINT, jb, "joint"), xb[0], xb[1], xb[2], range(jb)),
           out);
}

}  // namespace

void MirrorActuators(const Model& model, const Data& data, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  auto pairs = Pairs(model, mjOBJ_ACTUATOR, compat::ActuatorCount(m));
  size_t before = out->size();
  for (auto [a, b] : pairs) {
    int ja = DrivenJoint(m, a), jb = DrivenJoint(m, b);
    if (ja >= 0 && jb >= 0 && SignsDisagree(m, data.get(), a, b, ja, jb)) {
      // opposite senses with mirrored ranges are a convention, not an edit on one side
      if (!MirroredRanges(m, ja, jb)) SenseMismatch(model, data, a, b, ja, jb, out);
      continue;
    }
    double ga = m->actuator_gear[6 * compat::ActuatorOutputs(m, a).first];
    double gb = m->actuator_gear[6 * compat::ActuatorOutputs(m, b).first];
    double gear = RelativeDifference(ga, gb);
    double gain =
        RelativeDifference(m->actuator_gainprm[mjNGAIN * a], m->actuator_gainprm[mjNGAIN * b]);
    double bias = std::max(RelativeDifference(m->actuator_biasprm[mjNBIAS * a + 1],
                                              m->actuator_biasprm[mjNBIAS * b + 1]),
                           RelativeDifference(m->actuator_biasprm[mjNBIAS * a + 2],
                                              m->actuator_biasprm[mjNBIAS * b + 2]));
    double worst = std::max({gear, gain, bias});
    if (worst <= kMirrorTolerance) continue;
    Mismatch(
        model, "actuator", "actuator.mirror", mjOBJ_ACTUATOR, "actuator", a, b, "gears and gains",
        worst,
        fmt::format("gear {:g} / {:g}, gain {:g} / {:g}, kp {:g} / {:g}, kv {:g} / {:g}", ga, gb,
                    m->actuator_gainprm[mjNGAIN * a], m->actuator_gainprm[mjNGAIN * b],
                    -m->actuator_biasprm[mjNBIAS * a + 1], -m->actuator_biasprm[mjNBIAS * b + 1],
                    -m->actuator_biasprm[mjNBIAS * a + 2], -m->actuator_biasprm[mjNBIAS * b + 2]),
        out);
  }
  Agreed("actuator", "actuator.mirror", "actuators", static_cast<int>(pairs.size()), before, out);
}

}  // namespace plumb::audit
