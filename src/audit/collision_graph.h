// Who can collide with whom, read from the compiled model alone (contype/conaffinity,
// explicit <pair>s, <exclude>s and the parent-child filter): per body, and per top-level
// subtree for the question "can this free body come to rest on something the world holds,
// and through what?". The contact layer of plumb audit is built on it.

#ifndef PLUMB_SRC_AUDIT_COLLISION_GRAPH_H_
#define PLUMB_SRC_AUDIT_COLLISION_GRAPH_H_

#include <mujoco/mujoco.h>

#include <vector>

namespace plumb::audit {

struct CollisionGraph {
  // Per body: the bodies its collision geoms can meet (sorted; 0 is the world), and whether
  // it has any geom that takes part in collisions at all (false: visual geoms only).
  std::vector<std::vector<int>> partners;
  std::vector<bool> collides;

  // Per top-level subtree, indexed by its root body (0: the world and everything welded to
  // it). `grounded`: it can come to rest on a static subtree, directly or through other free
  // subtrees. `support`: for a grounded free subtree that touches nothing static itself, the
  // root of the lightest subtree on the best path to the ground (the path whose lightest link
  // is heaviest), else -1; `support_mass` its subtree mass.
  std::vector<bool> grounded;
  std::vector<int> support;
  std::vector<double> support_mass;

  // Whether any static geom (of the world or a subtree without a free joint) takes part in
  // collisions at all: a robot description without a floor has none.
  bool static_collider = false;
};

// Whether body `root` is a top-level body on a free joint: its subtree's weight reaches the
// ground only through contacts (for any body b, ask about m->body_rootid[b]).
bool IsFreeRoot(const mjModel* m, int root);

// Reads the graph from `m` (body_subtreemass must be current: after mj_setConst or a load).
CollisionGraph MakeCollisionGraph(const mjModel* m);

}  // namespace plumb::audit

#endif  // PLUMB_SRC_AUDIT_COLLISION_GRAPH_H_
