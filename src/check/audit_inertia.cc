// Audit layer 2, inertia: total mass, principal moments, weld groups too light or too
// unlike their parents, densities, inertia against size, centres of mass outside the body,
// and the mass matrix's condition number.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "check/audit_layers.h"

namespace plumb::audit {
namespace {

constexpr const char* L = "inertia";

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

// Sum of the body masses.
double TotalMass(const mjModel* m, std::vector<CheckRow>* out) {
  double total = 0;
  for (int b = 1; b < m->nbody; ++b) total += m->body_mass[b];
  out->push_back(
      WithNumbers(Make(L, "inertia.total_mass", "", fmt::format("{:.6g} kg", total), "> 0 kg",
                       total > 0 || m->nv == 0 ? CheckStatus::kPass : CheckStatus::kFail,
                       total > 0 ? "sum of body masses as compiled"
                                 : "nothing has mass: give geoms a mass or density"),
                  {total, "kg"}, {0, "kg"}));
  return total;
}

// Bodies welded together (no joint between them) move as one: mass conditioning is a matter
// of these weld groups, not of the marker bodies inside them.
struct WeldGroups {
  std::vector<double> mass;  // by weld root
  std::vector<int> size;
  explicit WeldGroups(const mjModel* m) : mass(m->nbody, 0.0), size(m->nbody, 0) {
    for (int b = 1; b < m->nbody; ++b) {
      mass[m->body_weldid[b]] += m->body_mass[b];
      ++size[m->body_weldid[b]];
    }
  }
};

// What the per-body checks know of one moving body.
struct BodyInertia {
  int b;
  CheckElement element;
  const mjtNum* I;  // principal moments
  double mass;
  bool marker = false;    // massless, inertia-less and welded to its parent
  bool positive = false;  // moments > 0 (or a marker)
  bool triangle = false;  // each moment <= the sum of the other two
};

BodyInertia ReadBody(const Model& model, int b) {
  const mjModel* m = model.get();
  BodyInertia body{b, ElementOf(model, mjOBJ_BODY, b, "body"), m->body_inertia + 3 * b,
                   m->body_mass[b]};
  const mjtNum* I = body.I;
  // principal moments: positive and each no larger than the sum of the other two; a
  // massless body welded to its parent (a marker) has none and needs none
  double slack = 1e-9 * (I[0] + I[1] + I[2]);
  body.marker = m->body_weldid[b] != b && body.mass == 0 && I[0] == 0 && I[1] == 0 && I[2] == 0;
  body.positive = body.marker || (I[0] > 0 && I[1] > 0 && I[2] > 0);
  body.triangle =
      I[0] + I[1] + slack >= I[2] && I[1] + I[2] + slack >= I[0] && I[0] + I[2] + slack >= I[1];
  return body;
}

void Principal(const BodyInertia& body, std::vector<CheckRow>* out) {
  if (body.positive && body.triangle) return;
  const mjtNum* I = body.I;
  out->push_back(Make(L, "inertia.principal", body.element,
                      fmt::format("I = ({:.4g}, {:.4g}, {:.4g}) kg*m^2", I[0], I[1], I[2]),
                      "> 0, triangle inequality", CheckStatus::kFail,
                      "no rigid body has these moments: fix <inertial diaginertia>, or let "
                      "the compiler derive them from geoms (inertiafromgeom), or use "
                      "<compiler balanceinertia=\"true\">"));
}

// Tiny weld groups and extreme ratios between a group and the group it hangs from make the
// mass matrix ill-conditioned.
void WeldGroup(const Model& model, const BodyInertia& body, const WeldGroups& groups, double total,
               std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  int b = body.b;
  if (m->body_weldid[b] != b) return;
  double group = groups.mass[b];
  std::string what = groups.size[b] > 1 ? fmt::format("{:.3g} kg (with {} bodies welded to it)",
                                                      group, groups.size[b] - 1)
                                        : fmt::format("{:.3g} kg", group);
  if (total > 0 && group < 1e-4 * total) {
    out->push_back(WithNumbers(Make(L, "inertia.tiny_mass", body.element,
                                    fmt::format("{} = {:.2g} of total", what, group / total),
                                    ">= 1e-4 of total", CheckStatus::kWarn,
                                    "a moving body this light makes the dynamics stiff and slow "
                                    "or unstable: give it a realistic mass, add armature to its "
                                    "joint, or weld it to its parent"),
                               {group / total, ""}, {1e-4, ""}));
  }
  int parent = m->body_weldid[m->body_parentid[b]];
  double parent_mass = groups.mass[parent];
  if (parent <= 0 || group <= 0 || parent_mass <= 0) return;
  double ratio = std::max(group / parent_mass, parent_mass / group);
  if (ratio <= 1e3) return;
  out->push_back(
      WithNumbers(Make(L, "inertia.mass_ratio", body.element,
                       fmt::format("{} vs parent {} {:.3g} kg: ratio {:.3g}", what,
                                   Elem(model, mjOBJ_BODY, parent, "body"), parent_mass, ratio),
                       "<= 1e3", ratio > 1e6 ? CheckStatus::kFail : CheckStatus::kWarn,
                       "extreme mass ratios between a body and its parent ill-condition "
                       "the mass matrix: rebalance masses or add joint armature"),
                  {ratio, ""}, {1e3, ""}));
}

// The volume of the body's geoms when every one is a primitive, else NaN.
double PrimitiveGeomVolume(const mjModel* m, int b) {
  if (m->body_geomnum[b] == 0) return NAN;
  double volume = 0;
  for (int g = m->body_geomadr[b]; g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
    volume += GeomVolume(m, g);  // NaN for a mesh or a plane: the sum stays NaN
  }
  return volume;
}

// The density the mass implies in the volume of the body's primitive geoms.
void Density(const BodyInertia& body, double volume, std::vector<CheckRow>* out) {
  if (!(volume > 0) || !(body.mass > 0)) return;
  double density = body.mass / volume;
  if (density >= 1 && density <= 25000) return;
  out->push_back(WithNumbers(
      Make(L, "inertia.density", body.element,
           fmt::format("{:.4g} kg/m^3 ({:.4g} kg in {:.3g} m^3)", density, body.mass, volume),
           "1 .. 25000 kg/m^3", CheckStatus::kWarn,
           "no solid is this light or heavy (water 1000, steel 7850): check "
           "the mass, the geom sizes and their units"),
      {density, "kg/m^3"}, {density < 1 ? 1.0 : 25000.0, "kg/m^3"}));
}

// Inertia against mass and size: the principal moments say how far the mass lies from the
// com on average (I1 + I2 + I3 = 2 * sum m r^2); the body's geoms say how far it can lie. A
// factor kSpreadFail beyond them is no solid of this shape (a 1000 kg pole with the 0.0094
// kg*m^2 of a light one), kSpreadWarn is suspect.
void InertiaAgainstSize(const mjModel* m, const BodyInertia& body, std::vector<CheckRow>* out) {
  const mjtNum* I = body.I;
  auto [lo, hi] = GeomSpread(m, body.b, m->body_ipos + 3 * body.b);
  double implied = std::sqrt((I[0] + I[1] + I[2]) / (2 * body.mass));
  double factor = lo > 0 ? std::max(lo / implied, implied / hi) : 0;
  if (factor <= kSpreadWarn) return;
  bool low = implied < lo;
  std::string range =
      lo < hi ? fmt::format("{:.3g} .. {:.3g} m", lo, hi) : fmt::format("{:.3g} m", lo);
  // the numbers: the rms distance against the bound of the geoms' range it crossed
  double bound = low ? lo / kSpreadWarn : hi * kSpreadWarn;
  out->push_back(WithNumbers(
      Make(L, "inertia.size", body.element,
           fmt::format("I = ({:.3g}, {:.3g}, {:.3g}) kg*m^2 for {:.4g} kg puts the mass "
                       "{:.3g} m (rms) from the com; its geoms, filled uniformly: {}",
                       I[0], I[1], I[2], body.mass, implied, range),
           fmt::format("within x{:g} of {}", kSpreadWarn, range),
           factor > kSpreadFail ? CheckStatus::kFail : CheckStatus::kWarn,
           fmt::format("the inertia is {:.3g} times too {} for this mass and size: was the mass "
                       "changed without the inertia (it scales with the mass at fixed shape), or "
                       "<inertial diaginertia> given in other units? Omit <inertial> to let the "
                       "compiler derive both from the geoms",
                       factor * factor, low ? "small" : "large")),
      {implied, "m"}, {bound, "m"}));
}

// A centre of mass far outside the body's geoms.
void ComOutside(const mjModel* m, const BodyInertia& body, std::vector<CheckRow>* out) {
  int b = body.b;
  if (m->body_geomnum[b] == 0) return;
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
  if (!std::isfinite(nearest) || reach <= 0 || nearest <= reach) return;
  out->push_back(WithNumbers(Make(L, "inertia.com_outside", body.element,
                                  fmt::format("com {:.3g} m outside its geoms", nearest),
                                  fmt::format("<= {:.3g} m", reach), CheckStatus::kWarn,
                                  "the centre of mass lies far outside the body's shape: check "
                                  "<inertial pos> and the body frame"),
                             {nearest, "m"}, {reach, "m"}));
}

// The condition number of the mass matrix at the reference pose.
void MassMatrix(const mjModel* m, Data& data, std::vector<CheckRow>* out) {
  if (m->nv == 0) return;
  mj_forward(m, data.get());
  auto [lo, hi] = MassMatrixExtremes(m, data.get());
  double cond = hi / std::max(lo, 1e-300);
  out->push_back(WithNumbers(
      Make(L, "inertia.mass_matrix", "",
           fmt::format("condition number {:.3g} (eigenvalues {:.3g} .. {:.3g})", cond, lo, hi),
           "<= 1e8", cond > 1e8 ? CheckStatus::kWarn : CheckStatus::kPass,
           cond > 1e8 ? "an ill-conditioned mass matrix slows the solver and loses "
                        "digits: add armature to light joints, rebalance masses"
                      : "mass matrix at the reference pose (mj_fullM) is "
                        "well-conditioned"),
      {cond, ""}, {1e8, ""}));
}

}  // namespace

void InertiaLayer(const Model& model, Data& data, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  double total = TotalMass(m, out);
  WeldGroups groups(m);
  int listed = 0, moving = 0;
  for (int b = 1; b < m->nbody; ++b) {
    if (!Moves(m, b)) continue;
    ++moving;
    BodyInertia body = ReadBody(model, b);
    Principal(body, out);
    WeldGroup(model, body, groups, total, out);
    double volume = PrimitiveGeomVolume(m, b);
    Density(body, volume, out);
    bool sound = body.positive && body.triangle && !body.marker;
    if (!std::isnan(volume) && body.mass > 0 && sound) InertiaAgainstSize(m, body, out);
    ComOutside(m, body, out);
    if (listed < kMaxListed && sound) {
      ++listed;
      const mjtNum* I = body.I;
      out->push_back(Make(L, "inertia.body", body.element,
                          fmt::format("{:.4g} kg, I = ({:.3g}, {:.3g}, {:.3g}) kg*m^2", body.mass,
                                      I[0], I[1], I[2]),
                          "", CheckStatus::kPass, "mass and principal inertia as compiled"));
    }
  }
  ListedNote(L, "inertia.body", "moving bodies", moving, out, listed);
  MassMatrix(m, data, out);
}

}  // namespace plumb::audit
