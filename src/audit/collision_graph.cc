#include "audit/collision_graph.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <set>
#include <utility>

namespace plumb::audit {

bool IsFreeRoot(const mjModel* m, int root) {
  return root > 0 && m->body_jntnum[root] > 0 && m->jnt_type[m->body_jntadr[root]] == mjJNT_FREE;
}

namespace {

// Whether geoms of bodies a and b may be tested for collision by their bitmasks: MuJoCo
// skips geoms of the same body, of a body and its parent (unless the filterparent flag is
// disabled; a child of the world is always tested against the world's geoms), and excluded
// body pairs.
bool BodiesFiltered(const mjModel* m, int a, int b, const std::set<std::pair<int, int>>& excluded) {
  if (a == b) return true;
  if (excluded.count({std::min(a, b), std::max(a, b)})) return true;
  bool filter_parent = !(m->opt.disableflags & mjDSBL_FILTERPARENT);
  if (filter_parent) {
    int pa = m->body_weldid[m->body_parentid[m->body_weldid[a]]];
    int pb = m->body_weldid[m->body_parentid[m->body_weldid[b]]];
    int wa = m->body_weldid[a], wb = m->body_weldid[b];
    if ((wa == pb && wa != 0) || (wb == pa && wb != 0)) return true;
  }
  return m->body_weldid[a] == m->body_weldid[b];
}

// Which bodies' geoms can touch: contype/conaffinity, less the parent-child filter and
// <exclude>, plus every <pair>. Also whether each body can collide at all.
std::vector<std::set<int>> BodyPartners(const mjModel* m, std::vector<bool>* collides) {
  const int n = m->nbody;
  std::set<std::pair<int, int>> excluded;
  for (int e = 0; e < m->nexclude; ++e) {
    int a = m->exclude_signature[e] >> 16, b = m->exclude_signature[e] & 0xFFFF;
    excluded.insert({std::min(a, b), std::max(a, b)});
  }
  std::vector<int> contype(n, 0), conaffinity(n, 0);
  for (int i = 0; i < m->ngeom; ++i) {
    contype[m->geom_bodyid[i]] |= m->geom_contype[i];
    conaffinity[m->geom_bodyid[i]] |= m->geom_conaffinity[i];
  }
  std::vector<std::set<int>> partners(n);
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      if (!((contype[a] & conaffinity[b]) || (contype[b] & conaffinity[a]))) continue;
      if (BodiesFiltered(m, a, b, excluded)) continue;
      partners[a].insert(b);
      partners[b].insert(a);
    }
  }
  for (int p = 0; p < m->npair; ++p) {
    int a = m->geom_bodyid[m->pair_geom1[p]], b = m->geom_bodyid[m->pair_geom2[p]];
    partners[a].insert(b);
    partners[b].insert(a);
  }
  collides->assign(n, false);
  for (int b = 0; b < n; ++b) {
    (*collides)[b] = contype[b] != 0 || conaffinity[b] != 0 || !partners[b].empty();
  }
  return partners;
}

// Whether anything static (not part of a free-floating subtree) can collide.
bool HasStaticCollider(const mjModel* m) {
  for (int i = 0; i < m->ngeom; ++i) {
    int root = m->body_rootid[m->geom_bodyid[i]];
    if (!IsFreeRoot(m, root) && (m->geom_contype[i] || m->geom_conaffinity[i])) return true;
  }
  for (int p = 0; p < m->npair; ++p) {
    for (int i : {m->pair_geom1[p], m->pair_geom2[p]}) {
      if (!IsFreeRoot(m, m->body_rootid[m->geom_bodyid[i]])) return true;
    }
  }
  return false;
}

// Over the subtree graph (a node per top-level subtree; static nodes are the ground): which
// subtrees reach the ground, and through which lightest free subtree. best[r] is the heaviest
// "lightest link" over the paths of free subtrees from a static one to r (a widest path),
// infinite for a subtree touching the ground itself.
void GroundSupport(const mjModel* m, const std::vector<std::set<int>>& partners,
                   CollisionGraph* g) {
  const int n = m->nbody;
  auto node = [m](int body) { return m->body_rootid[body]; };
  std::vector<std::set<int>> touches(n);
  for (int a = 0; a < n; ++a) {
    for (int b : partners[a]) {
      if (node(a) != node(b)) touches[node(a)].insert(node(b));
    }
  }
  g->grounded.assign(n, false);
  g->support.assign(n, -1);
  g->support_mass.assign(n, 0);
  std::vector<double> best(n, -1);
  std::priority_queue<std::pair<double, int>> frontier;
  for (int r = 0; r < n; ++r) {
    if (node(r) != r || IsFreeRoot(m, r)) continue;
    g->grounded[r] = true;
    best[r] = INFINITY;
    frontier.push({best[r], r});
  }
  while (!frontier.empty()) {
    auto [width, a] = frontier.top();
    frontier.pop();
    if (width < best[a]) continue;
    for (int b : touches[a]) {
      if (!IsFreeRoot(m, b)) continue;
      // the path into b carries b's weight through a; a's own mass bounds it (the ground
      // itself does not)
      double link = IsFreeRoot(m, a) ? std::min(width, m->body_subtreemass[a]) : INFINITY;
      if (link > best[b]) {
        best[b] = link;
        g->grounded[b] = true;
        g->support[b] = std::isinf(link) ? -1 : -2;  // resolved below
        frontier.push({link, b});
      }
    }
  }
  // name the bottleneck of each subtree resting on others: the lightest subtree on its path
  for (int r = 0; r < n; ++r) {
    if (g->support[r] != -2) continue;
    int lightest = -1;
    for (int b : touches[r]) {
      if (!IsFreeRoot(m, b) || !g->grounded[b]) continue;
      double link = std::min(best[b], m->body_subtreemass[b]);
      if (link == best[r]) {
        lightest = b;
        // follow the chain down to the subtree whose mass is the bottleneck
        while (m->body_subtreemass[lightest] != best[r] && g->support[lightest] >= 0) {
          lightest = g->support[lightest];
        }
        break;
      }
    }
    g->support[r] = lightest;
    g->support_mass[r] = best[r];
  }
}

}  // namespace

CollisionGraph MakeCollisionGraph(const mjModel* m) {
  CollisionGraph g;
  std::vector<std::set<int>> partners = BodyPartners(m, &g.collides);
  for (const std::set<int>& p : partners) g.partners.emplace_back(p.begin(), p.end());
  g.static_collider = HasStaticCollider(m);
  GroundSupport(m, partners, &g);
  return g;
}

}  // namespace plumb::audit
