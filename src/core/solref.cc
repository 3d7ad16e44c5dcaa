#include "core/solref.h"

#include <algorithm>
#include <cmath>

#include "core/mujoco_compat.h"

namespace plumb::internal {

namespace {

bool Disabled(const mjModel* m, int flag) { return (m->opt.disableflags & flag) != 0; }

bool Override(const mjModel* m) { return (m->opt.enableflags & mjENBL_OVERRIDE) != 0; }

// Whether MuJoCo's collision filter lets geoms g and h of different bodies make a dynamic
// contact: their bitmasks meet, they are not in one weld group, not welded parent and child
// (under the filterparent flag, the world's children excepted), their bodies are not an
// <exclude>d pair and no explicit <pair> names the two.
bool MayTouch(const mjModel* m, int g, int h) {
  if (!(m->geom_contype[g] & m->geom_conaffinity[h]) &&
      !(m->geom_contype[h] & m->geom_conaffinity[g])) {
    return false;
  }
  int a = m->geom_bodyid[g], b = m->geom_bodyid[h];
  int wa = m->body_weldid[a], wb = m->body_weldid[b];
  if (wa == wb) return false;
  if (!Disabled(m, mjDSBL_FILTERPARENT) && wa != 0 && wb != 0) {
    if (wa == m->body_weldid[m->body_parentid[wb]] || wb == m->body_weldid[m->body_parentid[wa]]) {
      return false;
    }
  }
  for (int e = 0; e < m->nexclude; ++e) {
    int s = m->exclude_signature[e];
    if (s == (a << 16) + b || s == (b << 16) + a) return false;
  }
  for (int p = 0; p < m->npair; ++p) {
    int p1 = m->pair_geom1[p], p2 = m->pair_geom2[p];
    if ((p1 == g && p2 == h) || (p1 == h && p2 == g)) return false;
  }
  return true;
}

// Whether the model can make contacts at all.
bool Contacts(const mjModel* m) { return !Disabled(m, mjDSBL_CONTACT); }

// Whether some contact can happen: an explicit pair, or two geoms that may touch.
bool AnyContact(const mjModel* m) {
  if (m->npair > 0) return true;
  for (int g = 0; g < m->ngeom; ++g) {
    for (int h = g + 1; h < m->ngeom; ++h) {
      if (MayTouch(m, g, h)) return true;
    }
  }
  return false;
}

// The time constant a dynamic contact between geoms g and h starts from, before the clamp, as
// mj_contactParam chooses it: the higher priority geom's own, else the two mixed by their
// solmix weights (standard format), or the smaller (a direct one: negative, never clamped).
double ContactTimeconst(const mjModel* m, int g, int h) {
  const mjtNum* a = m->geom_solref + mjNREF * g;
  const mjtNum* b = m->geom_solref + mjNREF * h;
  if (m->geom_priority[g] != m->geom_priority[h]) {
    return m->geom_priority[g] > m->geom_priority[h] ? a[0] : b[0];
  }
  if (a[0] <= 0 || b[0] <= 0) return std::min(a[0], b[0]);
  double wa = m->geom_solmix[g], wb = m->geom_solmix[h];
  double mix = 0.5;
  if (wa >= mjMINVAL && wb >= mjMINVAL) {
    mix = wa / (wa + wb);
  } else if (wa >= mjMINVAL || wb >= mjMINVAL) {
    mix = wa >= mjMINVAL ? 1.0 : 0.0;
  }
  return mix * a[0] + (1 - mix) * b[0];
}

// The lowest ContactTimeconst of geom g's dynamic contacts, over the geoms it may touch;
// +infinity when it touches none.
double LowestContactTimeconst(const mjModel* m, int g) {
  double lowest = INFINITY;
  for (int h = 0; h < m->ngeom; ++h) {
    if (h == g || !MayTouch(m, g, h)) continue;
    double timeconst = ContactTimeconst(m, g, h);
    if (timeconst > 0) lowest = std::min(lowest, timeconst);
  }
  return lowest;
}

// Whether row `row` of the solref array `array` makes a constraint whose time constant starts
// below `floor` (ActingSolrefsBelow says which); a geom's row sets `contact` to the lowest time
// constant its contacts start from.
bool RowActs(const mjModel* m, const std::string& array, long row, double floor,
             double* contact) {
  if (Disabled(m, mjDSBL_CONSTRAINT)) return false;
  // the contacts' own solrefs, which <flag override="enable"/> replaces with opt.o_solref
  bool own_contact = !Override(m) && Contacts(m);
  if (array == "geom_solref") {
    if (!own_contact) return false;
    *contact = LowestContactTimeconst(m, static_cast<int>(row));
    return *contact < floor;
  }
  if (array == "pair_solref") return own_contact;
  if (array == "pair_solreffriction") {
    return own_contact && m->opt.cone == mjCONE_ELLIPTIC && m->pair_dim[row] > 1;
  }
  if (array == "flex_solref") return own_contact && compat::FlexMakesContacts(m, row);
  if (array == "opt.o_solref") return Override(m) && Contacts(m) && AnyContact(m);
  if (array == "jnt_solref") return !Disabled(m, mjDSBL_LIMIT) && m->jnt_limited[row] != 0;
  if (array == "tendon_solref_lim") return !Disabled(m, mjDSBL_LIMIT) && m->tendon_limited[row] != 0;
  if (array == "dof_solref") return !Disabled(m, mjDSBL_FRICTIONLOSS) && m->dof_frictionloss[row] > 0;
  if (array == "tendon_solref_fri") {
    return !Disabled(m, mjDSBL_FRICTIONLOSS) && m->tendon_frictionloss[row] > 0;
  }
  if (array == "eq_solref") return !Disabled(m, mjDSBL_EQUALITY);
  return true;
}

}  // namespace

std::vector<SolrefBelow> ActingSolrefsBelow(const mjModel* m, double floor) {
  std::vector<SolrefBelow> out;
  for (const compat::SolrefArray& a : compat::ClampedSolrefArrays(m)) {
    for (long i = 0; i < a.rows; ++i) {
      const mjtNum* solref = a.data + i * mjNREF;
      // standard format only: a direct (negative) solref is never clamped, and a mixed one
      // MuJoCo replaces with its default
      if (!(solref[0] > 0 && solref[1] > 0 && solref[0] < floor)) continue;
      double contact = NAN;
      if (RowActs(m, a.name, i, floor, &contact)) {
        out.push_back({a.name, i, solref[0], solref[1], contact});
      }
    }
  }
  return out;
}

std::vector<SolrefBelow> SolrefsBelow(const mjModel* m, double floor) {
  if (!compat::ReferenceTimeconstClamped(m)) return {};  // refsafe off: MuJoCo clamps nothing
  return ActingSolrefsBelow(m, floor);
}

}  // namespace plumb::internal
