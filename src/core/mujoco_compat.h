// Every difference between the MuJoCo versions plumb builds against lives here.
//
// plumb's default is MuJoCo 4.0.1 (from its PyPI wheel); 3.11.0 and Debian's 2.2.2
// (mjVERSION_HEADER 222) are tested legs, and any 3.x/4.x release folder should work.
// mjVERSION_HEADER is three digits up to 3.4.0 (340) and major*10^6 + minor*10^3 + patch
// from 3.5.0 (3011000, 4000001). Code elsewhere uses enum names and the helpers below,
// never raw enum values or version numbers.
//
// The enumeration name tables (kSensorTypes, NameOf, EnumFieldName, ...) live in
// mujoco_compat_names.h, and what the MJCF says beyond the compiled model (ExplicitInertials,
// WrittenGeomMasses, SolrefDefaultClasses: mjSpec) in mujoco_compat_spec.h, which this header
// includes: code includes this header only, so every version difference is still reached
// through this one include.

#ifndef PLUMB_SRC_CORE_MUJOCO_COMPAT_H_
#define PLUMB_SRC_CORE_MUJOCO_COMPAT_H_

#include <mujoco/mjxmacro.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/mujoco_compat_names.h"

namespace plumb::compat {

// True for any MuJoCo 3.x release.
inline constexpr bool kMujoco3 = mjVERSION_HEADER >= 300;

// The 3.5.0 release switched to a 7-digit encoding of the version number.
inline constexpr bool kMujoco35 = mjVERSION_HEADER >= 3005000;

// 3.6.0 merged the option X-macros into MJOPTION_FIELDS.
inline constexpr bool kMujoco36 = mjVERSION_HEADER >= 3006000;

// 2.x's renderer lights the first frame drawn on a new render context differently (a few
// levels brighter) from every later frame; plumb draws and discards one frame first, so
// the same state always gives the same picture.
inline constexpr bool kRendererFirstFrameDiffers = !kMujoco3;

// MuJoCo's model-editing API (mjSpec) as plumb uses it to save fitted models: mjs_* element
// access, polynomial joint damping/stiffness arrays (mjsJoint::damping[0]). 2.x has none.
#define PLUMB_MUJOCO_HAS_SPEC (mjVERSION_HEADER >= 3010000)

// The X-macro listing the integer size fields of mjModel (nq, nv, nbody, ...).
#if mjVERSION_HEADER >= 3005000
#define PLUMB_MJMODEL_SIZES MJMODEL_SIZES
#else
#define PLUMB_MJMODEL_SIZES MJMODEL_INTS
#endif

// 2.x declares the names its MJDATA_POINTERS column counts use (nv, njmax) in a
// preamble; 3.6.0 removed it, as every column count became a literal.
#ifdef MJDATA_POINTERS_PREAMBLE
#define PLUMB_MJDATA_POINTERS_PREAMBLE(m) MJDATA_POINTERS_PREAMBLE(m)
#else
#define PLUMB_MJDATA_POINTERS_PREAMBLE(m)
#endif

// 3.x moved the constraint, contact and island arrays of mjData into the arena, listed
// by MJDATA_ARENA_POINTERS with rows MJ_M(size of mjModel) or MJ_D(size of mjData);
// 2.x lists them in MJDATA_POINTERS with njmax/nconmax rows.
#ifdef MJDATA_ARENA_POINTERS
#define PLUMB_MJDATA_ARENA_POINTERS MJDATA_ARENA_POINTERS
#endif

// Newer releases tag some rows of MJMODEL_POINTERS / MJDATA_POINTERS with other
// macro names; by default they mean the same as X.
#ifndef XMJV
#define XMJV X
#endif
#ifndef XNV
#define XNV X
#endif

// Element types of the arrays plumb reads and writes through paths.
enum class ElemType { kNum, kInt, kInt64, kByte, kBool, kFloat, kChar, kOther };

template <typename T>
constexpr ElemType ElemTypeOf() {
  if constexpr (std::is_same_v<T, mjtNum>) return ElemType::kNum;
  if constexpr (std::is_same_v<T, int>) return ElemType::kInt;
  if constexpr (std::is_same_v<T, long> || std::is_same_v<T, long long>) return ElemType::kInt64;
  if constexpr (std::is_same_v<T, bool>) return ElemType::kBool;
  if constexpr (std::is_same_v<T, mjtByte>) return ElemType::kByte;
  if constexpr (std::is_same_v<T, float>) return ElemType::kFloat;
  if constexpr (std::is_same_v<T, char>) return ElemType::kChar;
  return ElemType::kOther;
}

// One field of mjOption: its name, byte offset in mjOption, element type and length.
struct OptionField {
  const char* name;
  std::size_t offset;
  ElemType type;
  int size;
};

// Every field of mjOption, scalars and vectors, from MuJoCo's own X-macros.
inline const std::vector<OptionField>& OptionFields() {
  static const std::vector<OptionField> fields = [] {
    std::vector<OptionField> f;
#if mjVERSION_HEADER >= 3006000
#define X(type, name, n) f.push_back({#name, offsetof(mjOption, name), ElemTypeOf<type>(), n});
#define XVEC(type, name, n) X(type, name, n)
    MJOPTION_FIELDS
#undef XVEC
#undef X
#else
#define X(type, name) f.push_back({#name, offsetof(mjOption, name), ElemTypeOf<type>(), 1});
    MJOPTION_SCALARS
#undef X
#define X(name, n) f.push_back({#name, offsetof(mjOption, name), ElemType::kNum, n});
    MJOPTION_VECTORS
#undef X
#endif
    return f;
  }();
  return fields;
}

// Value above which MuJoCo's own mj_checkPos/Vel/Acc consider a number diverged.
inline constexpr double kMaxVal = mjMAXVAL;

// Address in d->act of actuator i's activation, or -1 when it has none.
inline int ActuatorActAddress(const mjModel* m, int i) {
#if mjVERSION_HEADER >= 300
  return m->actuator_actadr[i];
#else
  // 2.x keeps stateful actuators last: the final na actuators own act[0..na).
  int first_stateful = m->nu - m->na;
  return i >= first_stateful ? i - first_stateful : -1;
#endif
}

namespace detail {
template <typename M>
auto ActuatorCount(const M* m, int) -> decltype(m->nactuator, long()) {
  return m->nactuator;
}
template <typename M>
long ActuatorCount(const M* m, long) {
  return m->nu;
}
}  // namespace detail

// The number of actuators. 2.x has one control per actuator, so nu counts both; 3.x
// counts actuators by nactuator (an actuator may take several controls, nu, and give
// several force outputs, nout). The actuator_* arrays of mjModel are nactuator rows
// (a few, such as actuator_gear, nout rows: the same for single-output actuators).
inline int ActuatorCount(const mjModel* m) { return static_cast<int>(detail::ActuatorCount(m, 0)); }

namespace detail {
template <typename M>
auto ActuatorControls(const M* m, int i, int)
    -> decltype(m->actuator_ctrladr, std::pair<long, long>()) {
  return {m->actuator_ctrladr[i], m->actuator_ctrlnum[i]};
}
template <typename M>
std::pair<long, long> ActuatorControls(const M*, int i, long) {
  return {i, 1};
}
template <typename M>
auto ActuatorOutputs(const M* m, int i, int)
    -> decltype(m->actuator_outadr, std::pair<long, long>()) {
  return {m->actuator_outadr[i], m->actuator_outnum[i]};
}
template <typename M>
std::pair<long, long> ActuatorOutputs(const M*, int i, long) {
  return {i, 1};
}
}  // namespace detail

// The first row and the count of actuator i's controls in d->ctrl (and in the nu-row
// arrays such as actuator_ctrlrange), and of its force outputs in the nout-row arrays
// (actuator_force, actuator_gear, ...). 2.x: one of each, at row i.
inline std::pair<long, long> ActuatorControls(const mjModel* m, int i) {
  return detail::ActuatorControls(m, i, 0);
}
inline std::pair<long, long> ActuatorOutputs(const mjModel* m, int i) {
  return detail::ActuatorOutputs(m, i, 0);
}

// The actuator that takes control row `row` of d->ctrl, or -1 for none.
inline int ControlActuator(const mjModel* m, long row) {
  for (int u = 0; u < ActuatorCount(m); ++u) {
    auto [first, count] = ActuatorControls(m, u);
    if (row >= first && row < first + count) return u;
  }
  return -1;
}

// Whether MuJoCo raises a standard solref time constant (solref[0] > 0) to two timesteps:
// unless the refsafe flag is disabled (mjDSBL_REFSAFE: bit 11 on 2.x, bit 12 from 3.x, where
// mjDSBL_ACTUATION took bit 11; the enumerator names it on every version).
inline bool ReferenceTimeconstClamped(const mjModel* m) {
  return !(m->opt.disableflags & mjDSBL_REFSAFE);
}

// One solref array of mjModel, by its field name: `rows` rows of mjNREF numbers.
struct SolrefArray {
  const char* name;
  const mjtNum* data;
  long rows;  // mjtSize on 4.x, int before
};

// Every solref array whose standard time constant MuJoCo raises to two timesteps (see
// ReferenceTimeconstClamped): contacts (geom_solref, pair_solref; pair_solreffriction and
// flex_solref from 3.x, which 2.x lacks), joint limits (jnt_solref), dof friction loss
// (dof_solref), equalities (eq_solref), tendon limits and friction (tendon_solref_lim,
// tendon_solref_fri), and opt.o_solref, which replaces the contacts' under the override flag.
inline std::vector<SolrefArray> ClampedSolrefArrays(const mjModel* m) {
  std::vector<SolrefArray> arrays = {
      {"geom_solref", m->geom_solref, m->ngeom},
      {"pair_solref", m->pair_solref, m->npair},
      {"jnt_solref", m->jnt_solref, m->njnt},
      {"dof_solref", m->dof_solref, m->nv},
      {"eq_solref", m->eq_solref, m->neq},
      {"tendon_solref_lim", m->tendon_solref_lim, m->ntendon},
      {"tendon_solref_fri", m->tendon_solref_fri, m->ntendon},
      {"opt.o_solref", m->opt.o_solref, 1},
  };
#if mjVERSION_HEADER >= 300
  arrays.push_back({"pair_solreffriction", m->pair_solreffriction, m->npair});
  arrays.push_back({"flex_solref", m->flex_solref, m->nflex});
#endif
  return arrays;
}

// MuJoCo's object type of flexes (mjOBJ_FLEX, 3.x); 2.x has no flexes: mjOBJ_UNKNOWN.
#if mjVERSION_HEADER >= 300
inline constexpr int kObjFlex = mjOBJ_FLEX;
#else
inline constexpr int kObjFlex = mjOBJ_UNKNOWN;
#endif

// Whether flex f can make contacts (its contype/conaffinity, or self-collision); 2.x has no
// flexes.
inline bool FlexMakesContacts(const mjModel* m, long f) {
#if mjVERSION_HEADER >= 300
  return m->flex_contype[f] != 0 || m->flex_conaffinity[f] != 0 || m->flex_selfcollide[f] != 0;
#else
  (void)m;
  (void)f;
  return false;
#endif
}

// Solver iterations used by the last step (summed over islands on 3.x).
inline int SolverIterations(const mjData* d) {
#if mjVERSION_HEADER >= 300
  int total = 0;
  for (int i = 0; i < mjNISLAND; ++i) total += d->solver_niter[i];
  return total;
#else
  return d->solver_iter;
#endif
}

// Sleeping kinematic trees: with the sleep flag on, MuJoCo freezes a tree whose speed stays
// below opt.sleep_tolerance, and <body sleep="init"> makes a tree start asleep. The feature
// came before 3.5; plumb reads it from 3.5 on. 2.x has none.
#if mjVERSION_HEADER >= 3005000
inline constexpr int kEnableSleep = mjENBL_SLEEP;  // its bit in opt.enableflags
#else
inline constexpr int kEnableSleep = 0;
#endif
inline bool SleepEnabled(const mjModel* m) { return m->opt.enableflags & kEnableSleep; }

// Turns sleep off in `m`: Data made or reset afterwards has every tree awake.
inline void DisableSleep(mjModel* m) { m->opt.enableflags &= ~kEnableSleep; }

// The root bodies of the trees asleep in `d`.
inline std::vector<int> AsleepTreeRoots(const mjModel* m, const mjData* d) {
  std::vector<int> roots;
#if mjVERSION_HEADER >= 3005000
  if (!SleepEnabled(m)) return roots;
  for (int t = 0; t < m->ntree; ++t) {
    if (d->tree_asleep[t] >= 0) roots.push_back(m->tree_bodyadr[t]);
  }
#else
  (void)m;
  (void)d;
#endif
  return roots;
}

// The full nv x nv joint-space inertia matrix M of the state in `d` into `dst`
// (mj_forward or mj_step must have run). 3.10.0 changed mj_fullM to take the data;
// 3.11.0 removed d->qM.
inline void FullInertia(const mjModel* m, const mjData* d, mjtNum* dst) {
#if mjVERSION_HEADER >= 3010000
  mj_fullM(m, d, dst);
#else
  mj_fullM(m, dst, d->qM);
#endif
}

// An mjVERSION_HEADER-style number in the encoding of 3.5.0 on (major*10^6 + minor*10^3 +
// patch), so versions from either side of the switch compare: 222 -> 2002002, 340 ->
// 3004000, 3011000 as it is.
constexpr int VersionNumber(int v) {
  return v >= 1000000 ? v : v / 100 * 1000000 + v / 10 % 10 * 1000 + v % 10;
}

// True when the MuJoCo plumb is compiled against is `version` (major*10^6 + minor*10^3 +
// patch: 3003006 for 3.3.6) or later.
constexpr bool CompiledAtLeast(int version) { return VersionNumber(mjVERSION_HEADER) >= version; }

// True when the MuJoCo library loaded at run time is the release plumb was compiled against
// (MuJoCo changes its binary interface between releases).
inline bool LoadedMujocoIsCompiledOne() { return mj_version() == mjVERSION_HEADER; }

// "2.2.2", "3.11.0", "4.0.1" for an mjVERSION_HEADER-style number (either encoding).
inline std::string VersionText(int v) {
  const int n = VersionNumber(v);
  return std::to_string(n / 1000000) + "." + std::to_string(n / 1000 % 1000) + "." +
         std::to_string(n % 1000);
}

// The MuJoCo plumb is compiled against, as VersionText says it.
inline std::string CompiledVersionText() { return VersionText(mjVERSION_HEADER); }

// Loads every plugin library (mujoco.pid, elasticity, SDF, sensor plugins, ...) in `dir`,
// so models that use them compile. MuJoCo 2.x has no plugins: nothing to do.
inline void LoadPluginLibraries(const std::string& dir) {
#if mjVERSION_HEADER >= 300
  mj_loadAllPluginLibraries(dir.c_str(), nullptr);
#else
  (void)dir;
#endif
}

// Installs process-wide error and warning handlers (deprecated but working on 3.10+).
inline void SetMujocoHandlers(void (*error)(const char*), void (*warning)(const char*)) {
  mju_user_error = error;
  mju_user_warning = warning;
}

// MuJoCo's structured log handler (mju_setLogHandler), which every error, warning and info
// message goes through and which another user of MuJoCo in the process (the `mujoco` Python
// package) installs; plumb chains to it (MujocoHandlerMode::kAroundCalls). Tested from 3.11.
#define PLUMB_MUJOCO_HAS_LOG_HANDLER (mjVERSION_HEADER >= 3011000)

// mj_resetData for what a rollout reads: state, inputs and statistics. On MuJoCo 2.x
// mj_resetData also clears the whole stack arena (megabytes for a humanoid), which costs
// as much as several steps; everything else in mjData is recomputed by mj_forward.
inline void ResetState(const mjModel* m, mjData* d) {
#if mjVERSION_HEADER >= 300
  mj_resetData(m, d);
#else
  d->time = 0;
  mju_copy(d->qpos, m->qpos0, m->nq);
  mju_zero(d->qvel, m->nv);
  mju_zero(d->act, m->na);
  mju_zero(d->ctrl, m->nu);
  mju_zero(d->qacc_warmstart, m->nv);
  mju_zero(d->qfrc_applied, m->nv);
  mju_zero(d->xfrc_applied, 6 * m->nbody);
  mju_zero(d->qacc, m->nv);
  mju_zero(d->act_dot, m->na);
  mju_zero(d->userdata, m->nuserdata);
  for (int b = 0; b < m->nbody; ++b) {
    int id = m->body_mocapid[b];
    if (id < 0) continue;
    mju_copy3(d->mocap_pos + 3 * id, m->body_pos + 3 * b);
    mju_copy4(d->mocap_quat + 4 * id, m->body_quat + 4 * b);
  }
  std::memset(d->warning, 0, sizeof(d->warning));
  std::memset(d->timer, 0, sizeof(d->timer));
  std::memset(d->solver, 0, sizeof(d->solver));
  d->solver_iter = 0;
  d->solver_nnz = 0;
  mju_zero(d->solver_fwdinv, 2);
  mju_zero(d->energy, 2);
  d->pstack = 0;
#endif
}

// The bound a joint puts on the total actuator force at its dofs (actuatorfrcrange, 3.x);
// nullopt when it has none (and always on 2.x, which has no such attribute).
inline std::optional<std::pair<double, double>> JointActuatorForceRange(const mjModel* m, int j) {
#if mjVERSION_HEADER >= 300
  if (!m->jnt_actfrclimited[j]) return std::nullopt;
  return std::make_pair(m->jnt_actfrcrange[2 * j], m->jnt_actfrcrange[2 * j + 1]);
#else
  (void)m;
  (void)j;
  return std::nullopt;
#endif
}

// Whether the implicit integrators leave an actuator's velocity derivative (a servo's kv) out of
// qDeriv while its joint's actuatorfrcrange holds the force, as they do for every version while
// the actuator's own forcerange holds it (mjd_actuator_vel). Measured on one clamped hinge's
// first implicitfast step: MuJoCo 3.11 keeps kv implicit (it moves h^2 F / (I + h kv)), 4.0.0 and
// 4.0.1 drop it (h^2 F / I); the versions between are not measured.
inline constexpr bool kJointClampDropsActuatorDerivative = mjVERSION_HEADER >= 4000000;

namespace detail {
template <typename D>
auto MomentRow(const mjModel* m, const D* d, int out, std::vector<mjtNum>* row, int)
    -> decltype(d->moment_rownnz, void()) {
  for (int k = 0; k < d->moment_rownnz[out]; ++k) {
    int adr = d->moment_rowadr[out] + k;
    (*row)[d->moment_colind[adr]] = d->actuator_moment[adr];
  }
  (void)m;
}
template <typename D>
void MomentRow(const mjModel* m, const D* d, int out, std::vector<mjtNum>* row, long) {
  for (int i = 0; i < m->nv; ++i) (*row)[i] = d->actuator_moment[out * m->nv + i];
}
}  // namespace detail

// Row `out` of the actuator moment (the generalized force of a unit actuator force), dense,
// after mj_forward: sparse on 3.x, dense nu x nv on 2.x.
inline std::vector<mjtNum> ActuatorMomentRow(const mjModel* m, const mjData* d, int out) {
  std::vector<mjtNum> row(m->nv, 0.0);
  detail::MomentRow(m, d, out, &row, 0);
  return row;
}

namespace detail {
// 3.x keeps the sparse structure of ten_J in mjModel
template <typename M, typename D>
auto TendonRow(const M* m, const D* d, int t, std::vector<mjtNum>* row, int)
    -> decltype(m->ten_J_rownnz, void()) {
  for (int k = 0; k < m->ten_J_rownnz[t]; ++k) {
    int adr = m->ten_J_rowadr[t] + k;
    (*row)[m->ten_J_colind[adr]] = d->ten_J[adr];
  }
}
// 2.x: ntendon x nv, sparse (structure in mjData) when the model is
template <typename M, typename D>
void TendonRow(const M* m, const D* d, int t, std::vector<mjtNum>* row, long) {
  if (!mj_isSparse(m)) {
    for (int i = 0; i < m->nv; ++i) (*row)[i] = d->ten_J[t * m->nv + i];
    return;
  }
  for (int k = 0; k < d->ten_J_rownnz[t]; ++k) {
    int adr = d->ten_J_rowadr[t] + k;
    (*row)[d->ten_J_colind[adr]] = d->ten_J[adr];
  }
}
}  // namespace detail

// Row `t` of the tendon Jacobian (d length / d qvel), dense, after mj_forward.
inline std::vector<mjtNum> TendonJacobianRow(const mjModel* m, const mjData* d, int t) {
  std::vector<mjtNum> row(m->nv, 0.0);
  detail::TendonRow(m, d, t, &row, 0);
  return row;
}

namespace detail {
template <typename M>
auto ActuatorPlugin(const M* m, int u, int) -> decltype(m->actuator_plugin, int()) {
  return m->actuator_plugin[u];
}
template <typename M>
int ActuatorPlugin(const M*, int, long) {
  return -1;
}
}  // namespace detail

// The plugin instance that computes actuator u's force (mujoco.pid, ...), -1 for none (always on
// 2.x, which has no plugins).
inline int ActuatorPlugin(const mjModel* m, int u) { return detail::ActuatorPlugin(m, u, 0); }

namespace detail {
template <typename M>
auto PluginCount(const M* m, int) -> decltype(m->nplugin, int()) {
  return m->nplugin;
}
template <typename M>
int PluginCount(const M*, long) {
  return 0;
}
}  // namespace detail

// Plugin instances of the model (0 on 2.x, which has no plugins).
inline int PluginCount(const mjModel* m) { return detail::PluginCount(m, 0); }

namespace detail {
template <typename M>
auto KeyPlastic(const M* m, int) -> decltype(m->key_plastic, std::pair<const double*, long>()) {
  return {m->key_plastic, static_cast<long>(m->nplastic)};
}
template <typename M>
std::pair<const double*, long> KeyPlastic(const M*, long) {
  return {nullptr, 0};
}
template <typename M>
auto HistorySize(const M* m, int) -> decltype(m->nhistory, long()) {
  return static_cast<long>(m->nhistory);
}
template <typename M>
long HistorySize(const M*, long) {
  return 0;
}
}  // namespace detail

// The plastic state (4.0's plastic springs: each yielded spring's rest offset, d->plastic) as
// the keyframes hold it: key_plastic (nkey rows) and its row length nplastic; {nullptr, 0}
// before 4.0.
inline std::pair<const double*, long> KeyPlastic(const mjModel* m) {
  return detail::KeyPlastic(m, 0);
}
inline long PlasticSize(const mjModel* m) { return KeyPlastic(m).second; }

// The length of d->history, MuJoCo's ring buffer of past controls and sensor values for
// actuator and sensor delays (3.5+), or 0.
inline long HistorySize(const mjModel* m) { return detail::HistorySize(m, 0); }

// Actuator groups the model disables (opt.disableactuator bits; 0 before 3.x had them).
inline int DisabledActuatorGroups(const mjModel* m) {
#if mjVERSION_HEADER >= 3002000
  return m->opt.disableactuator;
#else
  (void)m;
  return 0;
#endif
}

// Whether MuJoCo's own box-box and convex collision code (nativeccd) is switched off.
inline bool NativeCcdDisabled(const mjModel* m) {
#if mjVERSION_HEADER >= 3003000
  return (m->opt.disableflags & mjDSBL_NATIVECCD) != 0;
#else
  (void)m;
  return true;  // 2.x has no nativeccd: its box-box is the classic one
#endif
}

// The option flags set in `m` that MJX accepts and never reads: disable flags MIDPHASE,
// NATIVECCD, ISLAND, AUTORESET and the enable flag SLEEP, by their MJCF names.
inline std::vector<std::string> FlagsMjxIgnores(const mjModel* m) {
  std::vector<std::string> out;
#if mjVERSION_HEADER >= 3011000
  const int d = m->opt.disableflags, e = m->opt.enableflags;
  if (d & mjDSBL_MIDPHASE) out.push_back("midphase");
  if (d & mjDSBL_NATIVECCD) out.push_back("nativeccd");
  if (d & mjDSBL_ISLAND) out.push_back("island");
  if (d & mjDSBL_AUTORESET) out.push_back("autoreset");
  if (e & mjENBL_SLEEP) out.push_back("sleep");
#else
  (void)m;
#endif
  return out;
}

// An actuator's or sensor's delay (3.5+: delay="..." nsample="..."): the delay as written, s,
// and the samples of history kept for it, which bound the delay MuJoCo can apply to
// nsample x timestep. {0, 0} for none, and always before 3.5.
struct Delay {
  double seconds = 0;
  long nsample = 0;
};
namespace detail {
template <typename M>
auto ActuatorDelay(const M* m, int u, int) -> decltype(m->actuator_delay, Delay()) {
  return {m->actuator_delay[u], m->actuator_history[2 * u]};
}
template <typename M>
Delay ActuatorDelay(const M*, int, long) {
  return {};
}
template <typename M>
auto SensorDelay(const M* m, int s, int) -> decltype(m->sensor_delay, Delay()) {
  return {m->sensor_delay[s], m->sensor_history[2 * s]};
}
template <typename M>
Delay SensorDelay(const M*, int, long) {
  return {};
}
}  // namespace detail
inline Delay ActuatorDelay(const mjModel* m, int u) { return detail::ActuatorDelay(m, u, 0); }
inline Delay SensorDelay(const mjModel* m, int s) { return detail::SensorDelay(m, s, 0); }

// The whole state a step starts from, as one vector: on 3.5+ mj_getState's
// mjSTATE_INTEGRATION (time, qpos, qvel, act, history, plastic, plugin state, warm start,
// ctrl, applied forces, eq_active, mocap and userdata, in MuJoCo's order, for mj_setState);
// 2.x has no mj_getState, and the vector holds time, qpos, qvel, act, warm start, ctrl,
// qfrc_applied, xfrc_applied, mocap_pos and mocap_quat, in that order.
#if mjVERSION_HEADER >= 3005000
inline constexpr const char* kIntegrationStateName = "mjSTATE_INTEGRATION";
inline long IntegrationStateSize(const mjModel* m) { return mj_stateSize(m, mjSTATE_INTEGRATION); }
inline void GetIntegrationState(const mjModel* m, const mjData* d, double* state) {
  mj_getState(m, d, state, mjSTATE_INTEGRATION);
}
inline void SetIntegrationState(const mjModel* m, mjData* d, const double* state) {
  mj_setState(m, d, state, mjSTATE_INTEGRATION);
}
#else
namespace detail {
// Each part of 2.x's state vector: where it lives in mjData and its length.
template <typename Visit>
void StateParts(const mjModel* m, mjData* d, Visit visit) {
  visit(&d->time, 1L);
  visit(d->qpos, static_cast<long>(m->nq));
  visit(d->qvel, static_cast<long>(m->nv));
  visit(d->act, static_cast<long>(m->na));
  visit(d->qacc_warmstart, static_cast<long>(m->nv));
  visit(d->ctrl, static_cast<long>(m->nu));
  visit(d->qfrc_applied, static_cast<long>(m->nv));
  visit(d->xfrc_applied, 6L * m->nbody);
  visit(d->mocap_pos, 3L * m->nmocap);
  visit(d->mocap_quat, 4L * m->nmocap);
}
}  // namespace detail
inline constexpr const char* kIntegrationStateName =
    "time, qpos, qvel, act, qacc_warmstart, ctrl, qfrc_applied, xfrc_applied, mocap_pos, "
    "mocap_quat";
inline long IntegrationStateSize(const mjModel* m) {
  return 1L + m->nq + 3L * m->nv + m->na + m->nu + 6L * m->nbody + 7L * m->nmocap;
}
inline void GetIntegrationState(const mjModel* m, const mjData* d, double* state) {
  detail::StateParts(m, const_cast<mjData*>(d), [&](const double* part, long size) {
    std::copy(part, part + size, state);
    state += size;
  });
}
inline void SetIntegrationState(const mjModel* m, mjData* d, const double* state) {
  detail::StateParts(m, d, [&](double* part, long size) {
    std::copy(state, state + size, part);
    state += size;
  });
}
#endif

namespace detail {
template <typename M>
auto ArenaBytes(const M* m, int) -> decltype(m->narena, long()) {
  return static_cast<long>(m->narena);
}
template <typename M>
long ArenaBytes(const M* m, long) {
  return static_cast<long>(m->nstack) * static_cast<long>(sizeof(mjtNum));
}
}  // namespace detail

// The bytes of mjData's arena (3.x: <size memory>) or 2.x's stack (<size nstack>), which
// contacts and constraints fill at each step.
inline long ArenaBytes(const mjModel* m) { return detail::ArenaBytes(m, 0); }

namespace detail {
template <class M>
auto EqualityBody(const M* m, int e, int id, int) -> decltype(m->eq_objtype, int()) {
  return m->eq_objtype[e] == mjOBJ_SITE ? m->site_bodyid[id] : id;
}
template <class M>
int EqualityBody(const M*, int, int id, long) {
  return id;
}
template <class D>
auto EqualityActive(const mjModel*, const D* d, int e, int) -> decltype(d->eq_active, bool()) {
  return d->eq_active[e];
}
template <class M, class D>
bool EqualityActive(const M* m, const D*, int e, long) {
  return m->eq_active[e];
}
}  // namespace detail

// The body that object `id` of connect or weld equality e names: 3.x may name sites
// (eq_objtype), 2.x names bodies only.
inline int EqualityBody(const mjModel* m, int e, int id) {
  return detail::EqualityBody(m, e, id, 0);
}

// Whether equality e is on: 3.x keeps the flag in mjData (eq_active), 2.x in the model.
inline bool EqualityActive(const mjModel* m, const mjData* d, int e) {
  return detail::EqualityActive(m, d, e, 0);
}

// Whether the Euler integrator treats joint damping (dof_damping) implicitly, as (M + h D):
// always on 2.x; on 3.x unless <flag eulerdamp="disable"/>.
inline bool EulerDampsImplicitly(const mjModel* m) {
#if mjVERSION_HEADER >= 3005000
  return !(m->opt.disableflags & mjDSBL_EULERDAMP);
#else
  (void)m;
  return true;
#endif
}

// The registered name of plugin instance `instance` ("mujoco.pid"), or "" when unknown.
inline std::string PluginName(const mjModel* m, int instance) {
#if mjVERSION_HEADER >= 300
  if (instance < 0 || instance >= m->nplugin) return "";
  const mjpPlugin* plugin = mjp_getPluginAtSlot(m->plugin[instance]);
  return plugin && plugin->name ? plugin->name : "";
#else
  (void)m;
  (void)instance;
  return "";
#endif
}

// Whether <flag spring="disable"/> (3.x) or passive="disable" (2.x) switches joint and tendon
// springs off.
inline bool SpringsDisabled(const mjModel* m) {
#if mjVERSION_HEADER >= 300
  return m->opt.disableflags & mjDSBL_SPRING;
#else
  return m->opt.disableflags & mjDSBL_PASSIVE;
#endif
}

// The value of config attribute `key` of plugin instance `instance` (a mujoco.pid's "kp"), ""
// when it has none (always on 2.x, which has no plugins).
inline std::string PluginConfig(const mjModel* m, int instance, const char* key) {
#if mjVERSION_HEADER >= 300
  if (instance < 0 || instance >= m->nplugin) return "";
  const char* value = mj_getPluginConfig(m, instance, key);
  return value ? value : "";
#else
  (void)m;
  (void)instance;
  (void)key;
  return "";
#endif
}

}  // namespace plumb::compat

// What the MJCF says beyond the compiled model (mjSpec, 3.10+), by compiled id.
#include "core/mujoco_compat_spec.h"  // IWYU pragma: export

#endif  // PLUMB_SRC_CORE_MUJOCO_COMPAT_H_
