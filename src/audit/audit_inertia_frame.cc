// Audit layer 2, inertia: the inertial frame against the body's shape (`inertia.frame`). A
// link exported from CAD can carry the right mass and principal moments with its <inertial pos>
// and quat written in another frame (the parent's, the joint's, the next link's, the mirrored
// link's): its centre of mass lands off the link's material, yet often inside its box, and its
// principal axes point the wrong way. Held against the shape filled uniformly: the centre of
// mass against the shape's centroid, the principal axes against the shape's own.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "audit/audit_layers.h"
#include "audit/body_shape.h"

namespace plumb::audit {
namespace {

constexpr const char* L = "inertia";

// How far the centre of mass may lie from the centroid of the uniformly filled shape, in shape
// radii (the shape's radius of gyration about its centroid, sqrt(trace(second moment) /
// volume)), and how far a principal axis may turn from the shape's, in degrees, before audit
// warns. A real link is not uniform (a motor at one end, a casting, cables) and its geoms show
// only part of it, so both are set above what the clean robot corpus shows (docs/audit.md,
// "Inertial frame against shape"): a closed visual mesh shows the link, and clean links' centres
// of mass lie within 1.51 radii of its centroid (Panda's fingers); collision primitives are often
// a few spheres or capsules away from the motor that carries the mass, up to 3.09 radii
// (Pegasus' hips). Clean axes lie within 35 deg of their shape's where both are determined
// (Spot's arm_link_el0), but for Panda's link2 (90 deg: its identified inertia has its smallest
// moment across the link, see docs).
constexpr double kOffsetWarnMesh = 2, kOffsetWarn = 4;
constexpr double kAngleWarn = 45;

// Two neighbouring principal moments closer than this, relative to the largest moment, leave
// the axes between them undetermined: a density unevenness of a fraction e of the largest
// moment turns them by an angle of the order e / gap, and real links are uneven by tens of
// per cent (Booster T1's upper arms: moments 0.61 : 0.93 : 1 filled uniformly, 0.44 : 0.86 : 1
// from CAD, smallest axes 74 deg apart). So an axis is compared only where its moment lies
// this far from its neighbours' in both the body and the shape: a long link's axis along its
// length (moments e : 1 : 1), a flat one's across it. A nearly symmetric link (a cylinder, a
// cube, a sphere) has no axis to compare about its symmetry; its distinct axis (a cylinder's
// long one) still is.
constexpr double kDistinctGap = 0.4;

using Vec = std::array<double, 3>;

// Principal moments ascending, each with its axis (a unit vector in the body frame).
struct Principal {
  Vec moment{};
  std::array<Vec, 3> axis{};
};

// From moments and the rotation whose columns are their axes, sorted by moment.
Principal Sorted(const mjtNum* moments, const mjtNum* R) {
  std::array<int, 3> order{0, 1, 2};
  std::sort(order.begin(), order.end(), [&](int a, int b) { return moments[a] < moments[b]; });
  Principal p;
  for (int k = 0; k < 3; ++k) {
    p.moment[k] = moments[order[k]];
    for (int i = 0; i < 3; ++i) p.axis[k][i] = R[3 * i + order[k]];
  }
  return p;
}

// Whether principal axis k (0 smallest .. 2 largest) is determined: its moment apart from its
// neighbours' by more than kDistinctGap of the largest.
bool Distinct(const Principal& p, int k) {
  double scale = p.moment[2];
  if (!(scale > 0)) return false;
  bool below = k == 0 || p.moment[k] - p.moment[k - 1] > kDistinctGap * scale;
  bool above = k == 2 || p.moment[k + 1] - p.moment[k] > kDistinctGap * scale;
  return below && above;
}

// How the body's inertial frame sits against its shape's.
struct FrameFit {
  double radius = NAN;  // the shape's radius of gyration about its centroid, m
  double offset = NAN;  // centre of mass to the shape's centroid, m
  double angle = NAN;   // the largest angle between a compared axis and the shape's, deg
  int axis = -1;        // which (0 smallest moment .. 2 largest) gave `angle`; -1 none compared
  Vec body_axis{}, shape_axis{};  // that axis, the body's and the shape's
};

FrameFit FitFrame(const mjModel* m, int b, const Solid& shape) {
  FrameFit fit;
  const std::array<double, 9>& S = shape.second;
  double trace = S[0] + S[4] + S[8];
  fit.radius = std::sqrt(trace / shape.volume);
  const mjtNum* com = m->body_ipos + 3 * b;
  double d[3] = {com[0] - shape.centroid[0], com[1] - shape.centroid[1],
                 com[2] - shape.centroid[2]};
  fit.offset = mju_norm3(d);
  // the shape's inertia tensor per unit density, trace(S) 1 - S, and its principal axes
  mjtNum J[9], value[3], vector[9], quat[4], R[9];
  for (int i = 0; i < 9; ++i) J[i] = (i % 4 == 0 ? trace : 0) - S[i];
  mju_eig3(value, vector, quat, J);
  Principal own = Sorted(value, vector);
  mju_quat2Mat(R, m->body_iquat + 4 * b);
  Principal body = Sorted(m->body_inertia + 3 * b, R);
  for (int k = 0; k < 3; ++k) {
    if (!Distinct(own, k) || !Distinct(body, k)) continue;
    double cosine = std::fabs(mju_dot3(own.axis[k].data(), body.axis[k].data()));
    double angle = std::acos(std::min(1.0, cosine)) * 180 / M_PI;
    if (fit.axis < 0 || angle > fit.angle) {
      fit.angle = angle;
      fit.axis = k;
      fit.body_axis = body.axis[k];
      fit.shape_axis = own.axis[k];
    }
  }
  return fit;
}

const char* MomentWord(int k) { return k == 0 ? "smallest" : k == 1 ? "middle" : "largest"; }

std::string Measured(const mjModel* m, int b, const Solid& shape, const FrameFit& fit,
                     bool com_flagged) {
  const mjtNum* com = m->body_ipos + 3 * b;
  std::string offset = fmt::format(
      "com ({:.3g}, {:.3g}, {:.3g}) m lies {:.3g} mm from its shape's centroid ({:.3g}, {:.3g}, "
      "{:.3g}) m, {:.3g} shape radii ({:.3g} mm){}",
      com[0], com[1], com[2], 1e3 * fit.offset, shape.centroid[0], shape.centroid[1],
      shape.centroid[2], fit.offset / fit.radius, 1e3 * fit.radius,
      com_flagged ? " (inertia.com flags it)" : "");
  std::string axes =
      fit.axis < 0
          ? "principal axes not compared (no moment apart from its neighbours in both)"
          : fmt::format(
                "principal axes {:.3g} deg off the shape's (the {} moment's: ({:.2f}, {:.2f}, "
                "{:.2f}) vs ({:.2f}, {:.2f}, {:.2f}))",
                fit.angle, MomentWord(fit.axis), fit.body_axis[0], fit.body_axis[1],
                fit.body_axis[2], fit.shape_axis[0], fit.shape_axis[1], fit.shape_axis[2]);
  return fmt::format("{}; {}; shape: {}", offset, axes, ShapeWords(shape));
}

// The solid to hold the inertial frame against: the body's shape, or where that has open meshes
// (taken as their boxes, which say nothing of where the material is) the other of its visual
// and colliding sets when that one is closed (Menagerie's UR5e: visual meshes split by
// material, each open, and colliding capsules); nullptr when neither is closed.
const Solid* ClosedShape(const BodySolids& solids) {
  if (solids.shape.volume > 0 && !solids.shape.approximate) return &solids.shape;
  // BodySolid's choice: the visual set when it holds more volume
  const Solid& other =
      solids.visual.volume > solids.colliding.volume ? solids.colliding : solids.visual;
  return other.volume > 0 && !other.approximate ? &other : nullptr;
}

}  // namespace

void InertialFrameAgainstShape(const Model& model, int b, const BodySolids& solids,
                               bool com_flagged, std::vector<CheckRow>* out) {
  const mjModel* m = model.get();
  const Solid* closed = ClosedShape(solids);
  if (!closed) return;
  const Solid& shape = *closed;
  FrameFit fit = FitFrame(m, b, shape);
  if (!(fit.radius > 0)) return;
  double radii = fit.offset / fit.radius;
  double offset_warn = shape.meshes > 0 ? kOffsetWarnMesh : kOffsetWarn;
  bool off = !com_flagged && radii > offset_warn;
  bool turned = fit.axis >= 0 && fit.angle > kAngleWarn;
  if (!off && !turned) return;
  // the row's number: the figure furthest past its threshold
  bool by_angle = turned && (!off || fit.angle / kAngleWarn > radii / offset_warn);
  Quantity measured = by_angle ? Quantity{fit.angle, "deg"} : Quantity{radii, ""};
  Quantity reference = by_angle ? Quantity{kAngleWarn, "deg"} : Quantity{offset_warn, ""};
  out->push_back(WithNumbers(
      Make(L, "inertia.frame", ElementOf(model, mjOBJ_BODY, b, "body"),
           Measured(m, b, shape, fit, com_flagged),
           fmt::format("com within {:g} shape radii of the centroid, principal axes within {:g} "
                       "deg of the shape's",
                       offset_warn, kAngleWarn),
           CheckStatus::kWarn,
           fmt::format("the <inertial> pos or quat look written in another frame (the parent's, "
                       "the joint's, the next link's, a mirrored link's): filled uniformly, the "
                       "body's geoms put the centre of mass at ({:.3g}, {:.3g}, {:.3g}) m in the "
                       "body frame. Take pos and quat from CAD in this body's frame, or omit "
                       "<inertial> to let the compiler derive them from the geoms",
                       shape.centroid[0], shape.centroid[1], shape.centroid[2])),
      measured, reference));
}

}  // namespace plumb::audit
