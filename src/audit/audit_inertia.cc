// Audit layer 2, inertia: total mass, principal moments, weld groups too light or too
// unlike their parents, densities, inertia against size, centres of mass outside the body,
// and the mass matrix's condition number.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "audit/audit_layers.h"
#include "audit/body_shape.h"
#include "core/mujoco_compat.h"
#include "plumb/error.h"

namespace plumb::audit {
namespace {

constexpr const char* L = "inertia";

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

// How far, as a factor, a body's radius of gyration (or the square root of a principal moment)
// may lie from its shape's before audit warns and fails. On the clean robot corpus every body
// lies within x4.1 (Spot's body: its smallest moment is 0.06 of its mesh's), on dm_control and
// MuJoCo's samples within x1.8 (see docs/audit.md, "Calibration").
constexpr double kShapeWarn = 5;
constexpr double kShapeFail = 10;

// How far outside the box of a body's geoms its centre of mass may lie, in half-diagonals of
// that box, before audit warns and fails. A body with a mesh shows its link: on the clean
// corpus every mesh body's centre of mass lies within 0.21 of its box (the racecar's
// differential), and a G1 wrist's moved by 5 cm lies 0.38 out. A body of primitives often has
// only collision spheres or capsules, away from the motor that carries its mass: up to 1.15
// (Pegasus' hips).
constexpr double kComWarnMesh = 0.25, kComFailMesh = 1;
constexpr double kComWarn = 1.5, kComFail = 4;

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
  // by weld root: the group's inertia about its centre of mass is positive definite, so it
  // moves as a rigid body whatever its parts' own moments (a massless root carrying welded
  // children, or point masses welded on)
  std::vector<char> rigid;
  // `d` after mj_forward (body poses and inertial frames)
  WeldGroups(const mjModel* m, const mjData* d)
      : mass(m->nbody, 0.0), size(m->nbody, 0), rigid(m->nbody, 0) {
    std::vector<double> first(3 * m->nbody, 0.0), second(9 * m->nbody, 0.0);  // about the origin
    for (int b = 1; b < m->nbody; ++b) {
      int r = m->body_weldid[b];
      double mb = m->body_mass[b];
      mass[r] += mb;
      ++size[r];
      const mjtNum* p = d->xipos + 3 * b;
      const mjtNum* R = d->ximat + 9 * b;
      const mjtNum* I = m->body_inertia + 3 * b;
      for (int i = 0; i < 3; ++i) {
        first[3 * r + i] += mb * p[i];
        for (int j = 0; j < 3; ++j) {
          double rotated = 0;
          for (int k = 0; k < 3; ++k) rotated += R[3 * i + k] * I[k] * R[3 * j + k];
          second[9 * r + 3 * i + j] += rotated + mb * ((i == j ? mju_dot3(p, p) : 0) - p[i] * p[j]);
        }
      }
    }
    for (int r = 1; r < m->nbody; ++r) {
      if (size[r] == 0 || !(mass[r] > 0)) continue;
      double c[3], J[9];
      for (int i = 0; i < 3; ++i) c[i] = first[3 * r + i] / mass[r];
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          J[3 * i + j] =
              second[9 * r + 3 * i + j] - mass[r] * ((i == j ? mju_dot3(c, c) : 0) - c[i] * c[j]);
        }
      }
      // Sylvester: every leading minor positive, against the trace's scale
      double scale = J[0] + J[4] + J[8], eps = 1e-9 * scale;
      double minor2 = J[0] * J[4] - J[1] * J[3];
      double det = J[0] * (J[4] * J[8] - J[5] * J[7]) - J[1] * (J[3] * J[8] - J[5] * J[6]) +
                   J[2] * (J[3] * J[7] - J[4] * J[6]);
      rigid[r] = scale > 0 && J[0] > eps && minor2 > eps * eps && det > eps * eps * eps;
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

BodyInertia ReadBody(const Model& model, int b, const WeldGroups& groups) {
  const mjModel* m = model.get();
  BodyInertia body{b, ElementOf(model, mjOBJ_BODY, b, "body"), m->body_inertia + 3 * b,
                   m->body_mass[b]};
  const mjtNum* I = body.I;
  // principal moments: positive and each no larger than the sum of the other two; a
  // massless body welded to its parent (a marker) has none and needs none
  double slack = 1e-9 * (I[0] + I[1] + I[2]);
  bool welded = m->body_weldid[b] != b;
  bool zero = I[0] == 0 && I[1] == 0 && I[2] == 0;
  body.marker = welded && body.mass == 0 && zero;
  // zero moments are fine where the weld group is a rigid body anyway: a point mass welded on
  // (a fingertip's 1 g), or a massless jointed root whose welded children carry the mass
  bool carried = (welded || groups.rigid[b]) && I[0] >= 0 && I[1] >= 0 && I[2] >= 0;
  body.positive = body.marker || carried || (I[0] > 0 && I[1] > 0 && I[2] > 0);
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

// How the body's inertia compares with its shape's at the body's mass.
struct ShapeFit {
  std::array<double, 3> body{}, shape{};  // principal moments, ascending, kg*m^2
  double gyration = NAN;                  // the body's radius of gyration over its shape's
  double factor = NAN;  // how far off, >= 1: the radius, or a moment's square root
  int decider = -1;     // the principal moment (0..2) whose root gave `factor`; -1: the radius
};

ShapeFit FitToShape(const BodyInertia& body, const Solid& shape) {
  ShapeFit fit;
  fit.shape = shape.PrincipalMoments(body.mass);
  fit.body = {body.I[0], body.I[1], body.I[2]};
  std::sort(fit.body.begin(), fit.body.end());
  double shape_sum = fit.shape[0] + fit.shape[1] + fit.shape[2];
  if (!(shape_sum > 0)) return fit;
  fit.gyration = std::sqrt((fit.body[0] + fit.body[1] + fit.body[2]) / shape_sum);
  fit.factor = std::max(fit.gyration, 1 / fit.gyration);
  for (int k = 0; k < 3; ++k) {
    if (!(fit.shape[k] > 0) || !(fit.body[k] > 0)) continue;
    double r = std::sqrt(fit.body[k] / fit.shape[k]);
    if (std::max(r, 1 / r) > fit.factor) {
      fit.factor = std::max(r, 1 / r);
      fit.decider = k;
    }
  }
  return fit;
}

// A body's geoms at unlike densities (a geom's own mass or density) give the compiler another
// inertia than the uniform fill: dm_control's pendulum carries its 1 kg in the sphere at the
// tip of a massless rod, and its derived inertia is that sphere's, x0.17 of the fill's. Where
// the fill does not fit, one geom alone whose centroid is the body's centre of mass may: the
// compiler's result when that geom carries the mass. A placeholder's centre of mass seldom lies
// on a geom's centroid, nor fits that geom alone.
ShapeFit FitToOneGeom(const mjModel* m, const BodyInertia& body, const BodySolids& solids,
                      ShapeFit fit) {
  if (!(fit.factor > kShapeWarn)) return fit;
  const mjtNum* com = m->body_ipos + 3 * body.b;
  double near = 1e-3 * solids.all.HalfDiagonal();
  for (int g = m->body_geomadr[body.b]; g < m->body_geomadr[body.b] + m->body_geomnum[body.b];
       ++g) {
    Solid one = GeomSolid(m, g);
    if (!(one.volume > 0)) continue;
    double d[3] = {one.centroid[0] - com[0], one.centroid[1] - com[1], one.centroid[2] - com[2]};
    if (!(mju_norm3(d) <= near)) continue;
    ShapeFit alone = FitToShape(body, one);
    if (alone.factor <= kShapeWarn) return alone;
  }
  return fit;
}

// Whether the body's inertia is too small for its shape, by the figure that decided.
bool ShapeTooSmall(const ShapeFit& fit) {
  return fit.decider < 0 ? fit.gyration < 1 : fit.body[fit.decider] < fit.shape[fit.decider];
}

// The row's measured text, leading with the figure that decided it: a principal moment's ratio
// (its root is what the threshold bounds), or the radius of gyration's.
std::string ShapeMeasured(const BodyInertia& body, const BodySolids& solids, const ShapeFit& fit) {
  const int k = fit.decider;
  std::string decided = fmt::format("radius of gyration x{:.3g}", fit.gyration);
  if (k >= 0) {
    const double moment = fit.body[k] / fit.shape[k];
    decided = fmt::format("{} principal moment x{:.3g} (root x{:.3g}; {})",
                          k == 0 ? "smallest" : k == 1 ? "middle" : "largest", moment,
                          std::sqrt(moment), decided);
  }
  return fmt::format(
      "I = ({:.3g}, {:.3g}, {:.3g}) kg*m^2 for {:.4g} kg: {} of {}, filled uniformly (I = "
      "({:.3g}, {:.3g}, {:.3g}))",
      fit.body[0], fit.body[1], fit.body[2], body.mass, decided, ShapeWords(solids.shape), fit.shape[0],
      fit.shape[1], fit.shape[2]);
}

// Inertia against the body's shape: the inertia its geoms would have, filled uniformly at the
// body's mass. A factor kShapeFail off is no solid of this shape (a 60 kg base with a
// placeholder 0.001 kg*m^2 on every axis), kShapeWarn is suspect. Every body is judged, from
// the compiled model alone, so a model and its file get one verdict: an inertia the compiler
// derived from geoms of one density fits them by construction. `derived` (the MJCF says the
// compiler derived it; unknown without the MJCF) only changes the advice.
void InertiaAgainstShape(const BodyInertia& body, const BodySolids& solids, const ShapeFit& fit,
                         std::optional<bool> derived, std::vector<CheckRow>* out) {
  if (!(fit.factor > kShapeWarn)) return;
  bool low = ShapeTooSmall(fit);
  std::string fix =
      derived.value_or(false)
          ? "the compiler derived this inertia from geoms of unlike densities (a geom's own "
            "mass or density), or the shape plumb sees is not the one that carries the mass: "
            "check the geoms' mass and density, or give the body an <inertial> from CAD"
          : fmt::format("the inertia does not fit the body's shape ({:.3g} times too {}): a "
                        "placeholder (0.001 on every axis?), other units (g*mm^2?), or a mass "
                        "changed without its inertia. Take it from CAD, or omit <inertial> to "
                        "let the compiler derive both from the geoms",
                        fit.factor * fit.factor, low ? "small" : "large");
  out->push_back(WithNumbers(
      Make(L, "inertia.shape", body.element,
           ShapeMeasured(body, solids, fit),
           fmt::format("within x{:g} of the shape's (radius and each principal moment's root)",
                       kShapeWarn),
           fit.factor > kShapeFail ? CheckStatus::kFail : CheckStatus::kWarn, fix),
      {fit.factor, ""}, {kShapeWarn, ""}));
}

// A centre of mass outside the box of the body's geoms, relative to that box's size.
void ComAgainstShape(const mjModel* m, const BodyInertia& body, const BodySolids& solids,
                     std::vector<CheckRow>* out) {
  const Solid& all = solids.all;
  if (!(all.volume > 0) || !(body.mass > 0) || body.marker) return;
  bool mesh = solids.meshes > 0;
  double warn = mesh ? kComWarnMesh : kComWarn, fail = mesh ? kComFailMesh : kComFail;
  const mjtNum* com = m->body_ipos + 3 * body.b;
  double outside = all.OutsideBox(com), size = all.HalfDiagonal();
  double ratio = outside / size;
  if (!(ratio > warn)) return;
  out->push_back(WithNumbers(
      Make(L, "inertia.com", body.element,
           fmt::format("com ({:.3g}, {:.3g}, {:.3g}) m lies {:.3g} m outside the box of its "
                       "geoms{}, {:.3g} x its half-diagonal ({:.3g} m)",
                       com[0], com[1], com[2], outside, mesh ? " (meshes included)" : "", ratio,
                       size),
           fmt::format("<= {:g} half-diagonals", warn),
           ratio > fail ? CheckStatus::kFail : CheckStatus::kWarn,
           "the centre of mass is not where the body is: an <inertial pos> pasted with another "
           "origin (the joint's, the parent's, the CAD file's)? Check it against CAD"),
      {ratio, ""}, {warn, ""}));
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

void InertiaLayer(const Model& original, const Model& model, Data& data,
                  std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  double total = TotalMass(m, out);
  WeldGroups groups(m, data.get());
  // which inertias were written by hand, where the MJCF says (mjSpec, 3.x and later): context
  // for the advice only, never the verdict (a model without its MJCF gets the same rows)
  std::optional<std::vector<bool>> written;
  // the masses geoms write (mjSpec too): the density check judges them where the compiler used them
  std::optional<std::vector<double>> geom_masses;
  try {
    written = compat::ExplicitInertials(original.xml_text(), original.file(), original.get());
    geom_masses = compat::WrittenGeomMasses(original.xml_text(), original.file(), original.get());
  } catch (const MujocoError&) {
    written = std::nullopt;  // the source no longer parses
    geom_masses = std::nullopt;
  }
  // each moving body's solids, once: a weld group's density reads its bodies' too
  std::vector<BodySolids> shapes(m->nbody);
  for (int b = 1; b < m->nbody; ++b) {
    if (Moves(m, b)) shapes[b] = BodySolid(m, b);
  }
  int listed = 0, moving = 0;
  for (int b = 1; b < m->nbody; ++b) {
    if (!Moves(m, b)) continue;
    ++moving;
    BodyInertia body = ReadBody(model, b, groups);
    Principal(body, out);
    WeldGroup(model, body, groups, total, out);
    const BodySolids& solids = shapes[b];
    WeldGroupDensity(model, b, shapes, geom_masses ? &*geom_masses : nullptr,
                     written ? &*written : nullptr, out);
    // a point mass (zero moments, welded on or carried by its group) has no shape to fit
    bool point = body.I[0] == 0 && body.I[1] == 0 && body.I[2] == 0;
    bool sound = body.positive && body.triangle && !body.marker && !point && body.mass > 0;
    // derived by the compiler from the geoms, as the MJCF says, and not changed by --set since
    bool changed = m->body_mass[b] != original->body_mass[b] ||
                   !std::equal(body.I, body.I + 3, original->body_inertia + 3 * b);
    std::optional<bool> derived;
    if (written) derived = !(*written)[b] && !changed;
    ShapeFit fit;
    if (sound && solids.shape.volume > 0) {
      fit = FitToOneGeom(m, body, solids, FitToShape(body, solids.shape));
    }
    if (!std::isnan(fit.factor)) InertiaAgainstShape(body, solids, fit, derived, out);
    if (sound) {
      size_t before = out->size();
      ComAgainstShape(m, body, solids, out);
      InertialFrameAgainstShape(model, b, solids, out->size() > before, out);
    }
    if (listed < kMaxListed && sound) {
      ++listed;
      const mjtNum* I = body.I;
      std::string against =
          std::isnan(fit.gyration)
              ? ""
              : fmt::format("; radius of gyration x{:.3g} of its shape's{}", fit.gyration,
                            derived.value_or(false) ? " (derived from its geoms)" : "");
      out->push_back(
          WithNumbers(Make(L, "inertia.body", body.element,
                           fmt::format("{:.4g} kg, I = ({:.3g}, {:.3g}, {:.3g}) kg*m^2{}",
                                       body.mass, I[0], I[1], I[2], against),
                           "", CheckStatus::kPass, "mass and principal inertia as compiled"),
                      {body.mass, "kg"}));
    }
  }
  ListedNote(L, "inertia.body", "moving bodies", moving, out, listed);
  MirrorBodies(model, out);
  MassMatrix(m, data, out);
}

}  // namespace plumb::audit
