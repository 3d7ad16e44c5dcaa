// Paths: one small grammar that names any element of mjModel, mjOption or mjData.
//
//   time                     simulation time (s)
//   qpos[hinge]              joint name -> its qpos address; a free joint is a block of 7
//   qpos[root][2]            element 2 of that block (the free joint's z)
//   qpos[3]                  raw row index
//   qpos                     the whole array
//   xpos[link][2]            z of a body's position (rows of xpos are bodies)
//   sensordata[imu_acc][1]   rows of sensordata are sensors, each a block of sensor_dim
//   dof_damping[hinge]       model parameters use the same grammar (rows of nv -> dofs)
//   opt.timestep, opt.gravity, opt.gravity[2], opt.integrator
//
// Which names index an array follows from its row count in MuJoCo's X-macro tables
// (mjxmacro.h): nbody -> body names, njnt -> joints, nq/nv -> joints (through
// jnt_qposadr/jnt_dofadr), nu -> actuators, nsensordata -> sensors, and so on, so every
// array of the MuJoCo version plumb is built with is reachable without hand-kept lists.
//
// Example:
//   plumb::Path q = plumb::ResolvePath(model, "qpos[hinge]");
//   double angle = plumb::ReadValue(model, data, q);          // rad
//   auto set = plumb::ParseAssignment(model, "opt.gravity=0,0,-1.62");
//   plumb::ApplyAssignments(model, data, {set});
//
// Thread-safety: the functions keep no state, and those taking a const Model (and a const Data)
// only read them: they may be called from several threads at once. WriteValues, WriteParameters,
// WriteState and ApplyAssignments write the Model and Data they get: no other thread may use
// those meanwhile (give each thread its own, e.g. with Model::Clone).

#ifndef PLUMB_INCLUDE_PLUMB_PATH_H_
#define PLUMB_INCLUDE_PLUMB_PATH_H_

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "plumb/model.h"

namespace plumb {

// The chapter's classification of every quantity in a simulation.
enum class Role {
  kParameter,  // mjModel / mjOption: fixed during a run (body_mass, opt.timestep)
  kState,      // mjData state the integrator advances (time, qpos, qvel, act)
  kInput,      // mjData inputs the user or controller writes (ctrl, qfrc_applied, mocap_pos)
  kDerived,    // mjData outputs MuJoCo computes (xpos, qacc, sensordata, contact)
};

// "parameter", "state", "input" or "derived".
const char* RoleName(Role role);

// A resolved reference to a block of consecutive elements of one field.
struct Path {
  std::string text;   // canonical text, e.g. "qpos[hinge]" or "xpos[link][2]"
  std::string field;  // the field: "qpos", "body_mass", "opt.gravity", "time"
  Role role = Role::kDerived;
  bool writable = false;  // whether WriteValues accepts it
  int field_index = -1;   // internal: which field
  long first = 0;         // flat index of the first element within the field
  long count = 1;         // number of elements in the block (1 for a single element)
  // One flag of a bitmask, by MuJoCo's name for it: "opt.enableflags.sleep" reads 0 or 1 and
  // writes that bit alone, the other flags kept; -1 for a whole field.
  int bit = -1;
};

// Resolves `text` against `model`.
// @throws PathError naming the unknown field or name, with the nearest valid ones,
//         or the index that is out of bounds; and for the data arrays that no state
//         plumb samples has computed (qfrc_inverse is mj_inverse's, qH the Euler
//         integrator's, qDeriv the implicit one's), which would read as 0, and for
//         efc_AR and efc_JT, packed by the current nefc where [row][element] assumes njmax.
Path ResolvePath(const Model& model, std::string_view text);

// Splits a block into one path per element ("qpos[root]" -> "qpos[root][0]" ... [6]);
// a single-element path is returned as it is.
// @throws PathError for a block of more than kMostScalarPaths elements (a whole constraint
//         array, sized by MuJoCo's arena, holds millions of rows), naming it.
constexpr long kMostScalarPaths = 100000;
std::vector<Path> ScalarPaths(const Path& path);

// Resolves `text`, where the row index may be `*` (every object that has a row, named
// or not, except the world body: "body_mass[*]", "geom_friction[*][0]"), into one path
// per match. Unnamed objects are written by id, "body_mass[#2]", which ResolvePath
// also accepts.
// @throws PathError as ResolvePath does.
std::vector<Path> ExpandPath(const Model& model, std::string_view text);

// The default columns of `plumb run`: time, qpos and qvel of every joint (one column
// per coordinate), ctrl of every actuator (one column per control), then sensordata of every
// sensor (one column per dimension).
std::vector<Path> DefaultColumns(const Model& model);

// Reads element `k` (0 <= k < path.count) as a double.
// @throws PathError when the element lies beyond the rows the data holds now: the
//         constraint arrays (efc_force, efc_pos, ...) have nefc rows, which change from
//         step to step, although ResolvePath checks them against their room (njmax).
double ReadValue(const Model& model, const Data& data, const Path& path, long k = 0);

// Writes `values` (exactly path.count of them) into the block. Integer fields take
// integral values only. A new body_mass keeps the body's shape and mass distribution:
// its body_inertia scales by new mass / old mass (a massless body keeps its inertia);
// to change the mass alone, write body_inertia after it.
// @throws ValueError for a wrong count, NaN/Inf, non-integral or out-of-range values;
//         PathError when the path is not writable (derived quantities, structure).
void WriteValues(Model& model, Data& data, const Path& path, const std::vector<double>& values);

// `PATH=VALUE` as typed on the command line: `qpos[hinge]=0.7`,
// `opt.gravity=0,0,-1.62`, `opt.integrator=RK4` (enumerations by MJCF name).
struct Assignment {
  std::string text;  // as typed
  Path path;
  std::vector<double> values;  // path.count values
  // What MuJoCo will silently do differently from what was asked, one sentence each
  // (a ctrl or act outside its actuator's range, which MuJoCo clamps; a free or ball
  // joint's quaternion whose norm is not 1, which MuJoCo normalises), about this
  // assignment (they do not repeat its text). The command-line tool prints them to stderr as
  // "plumb: warning: --set 'TEXT': ...".
  std::vector<std::string> warnings;
};

// Parses and validates `text`. A block takes exactly as many values as it has elements
// (`qpos[root]` of a free joint takes 7); set a single element by its index
// (`qpos[root][2]=1`).
// @throws PathError for an unknown path; ArgumentError (argument "set", `text` quoted) for a
//         value the path cannot take, naming the block's size; ValueError for a path that
//         cannot be set.
Assignment ParseAssignment(const Model& model, std::string_view text);

// Throws ValueError unless `value` may be written to `path`: finite, fits the element
// type, and within what MuJoCo accepts (see ParseAssignment). For values computed at run
// time, such as randomized draws.
void CheckAssignable(const Path& path, double value);

// The two halves of PATH=VALUE text: the path and the value, split at the first '='.
// @throws ArgumentError for `argument` ("set", "vary", "randomize"), quoting `text` and
//         `example`, when there is no '='.
std::pair<std::string_view, std::string_view> SplitAssignment(std::string_view text,
                                                              const char* argument,
                                                              const char* example);

// The compiled model's parameters (mjModel arrays and options, floating point) that are NaN
// or infinite: the first `max` as "PATH = VALUE" ("dof_damping[hinge] = nan"), and how many
// there are in all. MuJoCo's compiler accepts such values with at most a warning.
struct NonFiniteValues {
  std::vector<std::string> first;
  long total = 0;
};
NonFiniteValues NonFiniteParameters(const Model& model, std::size_t max = 6);

// Whether writing `path` changes a model array (body_mass, dof_damping, ...; not an option
// such as opt.timestep), after which the constants mj_setConst derives must be recomputed.
bool ChangesModelArrays(const Path& path);

// Writes the parameter edits among `assignments` (mjModel, mjOption) to the model, in their
// order with body_inertia last, so that a given inertia overrides the rescaling that a new
// body_mass implies (see WriteValues). Returns whether a model array changed
// (ChangesModelArrays): the caller then runs mj_setConst. Rollout workers call this
// directly (they restore parameters between rollouts); every other run goes through
// ApplyAssignments. @throws ValueError / PathError as WriteValues does.
bool WriteParameters(Model& model, Data& data, const std::vector<Assignment>& assignments);

// Writes the state and input edits among `assignments` in their order (no reset, no
// mj_forward). @throws ValueError / PathError as WriteValues does.
void WriteState(Model& model, Data& data, const std::vector<Assignment>& assignments);

// Applies assignments in the order a run needs them: parameter edits to the model
// first (body_inertia last, so a given inertia overrides the rescaling that a new
// body_mass implies, see WriteValues), then mj_setConst when any model array changed (derived
// constants such as body_subtreemass stay right), then mj_resetData, then state and input edits,
// then mj_forward so derived quantities (xpos, sensordata) are consistent with the state.
// @throws ValueError / PathError as WriteValues does; MujocoError.
void ApplyAssignments(Model& model, Data& data, const std::vector<Assignment>& assignments);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_PATH_H_
