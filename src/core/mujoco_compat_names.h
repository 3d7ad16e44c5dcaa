// MuJoCo's enumerations by their MJCF names: the integrator, cone, solver, joint, sensor,
// geom, equality and actuator type tables, and the name of a value of an enumerated model
// array. Part of src/core/mujoco_compat.h, which includes it: include that header, never
// this one, so every version difference still lives behind the one include.

#ifndef PLUMB_SRC_CORE_MUJOCO_COMPAT_NAMES_H_
#define PLUMB_SRC_CORE_MUJOCO_COMPAT_NAMES_H_

#include <mujoco/mujoco.h>

#include <cstddef>
#include <optional>
#include <string>

namespace plumb::compat {

// Integrator values and their MJCF names, in enum order.
struct EnumName {
  int value;
  const char* name;
};
inline constexpr EnumName kIntegrators[] = {
    {mjINT_EULER, "Euler"},
    {mjINT_RK4, "RK4"},
    {mjINT_IMPLICIT, "implicit"},
#if mjVERSION_HEADER >= 233
    {mjINT_IMPLICITFAST, "implicitfast"},
#endif
};

// Friction cone, solver and Jacobian types by their MJCF names.
inline constexpr EnumName kCones[] = {{mjCONE_PYRAMIDAL, "pyramidal"},
                                      {mjCONE_ELLIPTIC, "elliptic"}};
inline constexpr EnumName kSolvers[] = {
    {mjSOL_PGS, "PGS"}, {mjSOL_CG, "CG"}, {mjSOL_NEWTON, "Newton"}};
inline constexpr EnumName kJacobians[] = {
    {mjJAC_DENSE, "dense"}, {mjJAC_SPARSE, "sparse"}, {mjJAC_AUTO, "auto"}};

// Warning kinds by enum name. Values shift between releases (VGEOMFULL was removed in
// 3.7.0), so the table is built from the names that exist in this header.
inline constexpr EnumName kWarnings[] = {
    {mjWARN_INERTIA, "INERTIA"},     {mjWARN_CONTACTFULL, "CONTACTFULL"},
    {mjWARN_CNSTRFULL, "CNSTRFULL"},
#if mjVERSION_HEADER < 3007000
    {mjWARN_VGEOMFULL, "VGEOMFULL"},
#endif
    {mjWARN_BADQPOS, "BADQPOS"},     {mjWARN_BADQVEL, "BADQVEL"},
    {mjWARN_BADQACC, "BADQACC"},     {mjWARN_BADCTRL, "BADCTRL"},
};

// Joint, transmission and sensor types by their MJCF names.
inline constexpr EnumName kJointTypes[] = {
    {mjJNT_FREE, "free"}, {mjJNT_BALL, "ball"}, {mjJNT_SLIDE, "slide"}, {mjJNT_HINGE, "hinge"}};
inline constexpr EnumName kTransmissions[] = {{mjTRN_JOINT, "joint"},
                                              {mjTRN_JOINTINPARENT, "jointinparent"},
                                              {mjTRN_SLIDERCRANK, "slidercrank"},
                                              {mjTRN_TENDON, "tendon"},
                                              {mjTRN_SITE, "site"},
                                              {mjTRN_BODY, "body"}};
inline constexpr EnumName kSensorTypes[] = {
    {mjSENS_TOUCH, "touch"},
    {mjSENS_ACCELEROMETER, "accelerometer"},
    {mjSENS_VELOCIMETER, "velocimeter"},
    {mjSENS_GYRO, "gyro"},
    {mjSENS_FORCE, "force"},
    {mjSENS_TORQUE, "torque"},
    {mjSENS_MAGNETOMETER, "magnetometer"},
    {mjSENS_RANGEFINDER, "rangefinder"},
    {mjSENS_JOINTPOS, "jointpos"},
    {mjSENS_JOINTVEL, "jointvel"},
    {mjSENS_TENDONPOS, "tendonpos"},
    {mjSENS_TENDONVEL, "tendonvel"},
    {mjSENS_ACTUATORPOS, "actuatorpos"},
    {mjSENS_ACTUATORVEL, "actuatorvel"},
    {mjSENS_ACTUATORFRC, "actuatorfrc"},
    {mjSENS_BALLQUAT, "ballquat"},
    {mjSENS_BALLANGVEL, "ballangvel"},
    {mjSENS_JOINTLIMITPOS, "jointlimitpos"},
    {mjSENS_JOINTLIMITVEL, "jointlimitvel"},
    {mjSENS_JOINTLIMITFRC, "jointlimitfrc"},
    {mjSENS_TENDONLIMITPOS, "tendonlimitpos"},
    {mjSENS_TENDONLIMITVEL, "tendonlimitvel"},
    {mjSENS_TENDONLIMITFRC, "tendonlimitfrc"},
    {mjSENS_FRAMEPOS, "framepos"},
    {mjSENS_FRAMEQUAT, "framequat"},
    {mjSENS_FRAMEXAXIS, "framexaxis"},
    {mjSENS_FRAMEYAXIS, "frameyaxis"},
    {mjSENS_FRAMEZAXIS, "framezaxis"},
    {mjSENS_FRAMELINVEL, "framelinvel"},
    {mjSENS_FRAMEANGVEL, "frameangvel"},
    {mjSENS_FRAMELINACC, "framelinacc"},
    {mjSENS_FRAMEANGACC, "frameangacc"},
    {mjSENS_SUBTREECOM, "subtreecom"},
    {mjSENS_SUBTREELINVEL, "subtreelinvel"},
    {mjSENS_SUBTREEANGMOM, "subtreeangmom"},
    {mjSENS_CLOCK, "clock"},
    {mjSENS_USER, "user"},
// 3.11 has these (when each came is not pinned here: a release between 2.3 and 3.11 that
// lacks one fails to compile this table, so they are gated at 3.11 and older releases print
// them as "type N"); 4.0.1 has the same set
#if mjVERSION_HEADER >= 3011000
    {mjSENS_CAMPROJECTION, "camprojection"},
    {mjSENS_JOINTACTFRC, "jointactuatorfrc"},
    {mjSENS_TENDONACTFRC, "tendonactuatorfrc"},
    {mjSENS_INSIDESITE, "insidesite"},
    {mjSENS_GEOMDIST, "distance"},
    {mjSENS_GEOMNORMAL, "normal"},
    {mjSENS_GEOMFROMTO, "fromto"},
    {mjSENS_CONTACT, "contact"},
    {mjSENS_E_POTENTIAL, "e_potential"},
    {mjSENS_E_KINETIC, "e_kinetic"},
    {mjSENS_TACTILE, "tactile"},
    {mjSENS_PLUGIN, "plugin"},
#endif
};
// The sensor that measures an actuator's force at its joint (jointactuatorfrc), or -1 in a
// MuJoCo without it.
#if mjVERSION_HEADER >= 3011000
inline constexpr int kSensorJointActuatorFrc = mjSENS_JOINTACTFRC;
#else
inline constexpr int kSensorJointActuatorFrc = -1;
#endif

// Geom, equality, actuator dynamics/gain/bias types by their MJCF names (the types both
// 2.x and 3.x have; a newer type reads as "type N", see NameOf).
inline constexpr EnumName kGeomTypes[] = {{mjGEOM_PLANE, "plane"},
                                          {mjGEOM_HFIELD, "hfield"},
                                          {mjGEOM_SPHERE, "sphere"},
                                          {mjGEOM_CAPSULE, "capsule"},
                                          {mjGEOM_ELLIPSOID, "ellipsoid"},
                                          {mjGEOM_CYLINDER, "cylinder"},
                                          {mjGEOM_BOX, "box"},
                                          {mjGEOM_MESH, "mesh"}};
inline constexpr EnumName kEqualityTypes[] = {{mjEQ_CONNECT, "connect"},
                                              {mjEQ_WELD, "weld"},
                                              {mjEQ_JOINT, "joint"},
                                              {mjEQ_TENDON, "tendon"},
                                              {mjEQ_DISTANCE, "distance"}};
inline constexpr EnumName kDynamicsTypes[] = {{mjDYN_NONE, "none"},
                                              {mjDYN_INTEGRATOR, "integrator"},
                                              {mjDYN_FILTER, "filter"},
                                              {mjDYN_MUSCLE, "muscle"},
                                              {mjDYN_USER, "user"}};
// 3.11 has the dcmotor and so3 gains (when they came is not pinned here: releases before
// 3.11 print them as "type N"); 3.12 added the pid gain, whose actuator takes two controls (a
// position and a velocity setpoint).
#if mjVERSION_HEADER >= 3012000
inline constexpr int kGainPid = mjGAIN_PID;
#else
inline constexpr int kGainPid = -1;
#endif
inline constexpr EnumName kGainTypes[] = {{mjGAIN_FIXED, "fixed"},     {mjGAIN_AFFINE, "affine"},
                                          {mjGAIN_MUSCLE, "muscle"},
#if mjVERSION_HEADER >= 3011000
                                          {mjGAIN_DCMOTOR, "dcmotor"}, {mjGAIN_SO3, "so3"},
#endif
#if mjVERSION_HEADER >= 3012000
                                          {mjGAIN_PID, "pid"},
#endif
                                          {mjGAIN_USER, "user"}};
inline constexpr EnumName kBiasTypes[] = {{mjBIAS_NONE, "none"},
                                          {mjBIAS_AFFINE, "affine"},
                                          {mjBIAS_MUSCLE, "muscle"},
                                          {mjBIAS_USER, "user"}};

// The name of `value` in `table`, or "type <value>" when the table lacks it.
template <std::size_t N>
std::string NameOf(const EnumName (&table)[N], int value) {
  for (const EnumName& e : table) {
    if (e.value == value) return e.name;
  }
  return "type " + std::to_string(value);
}

// The MJCF name of value `value` of the enumerated model array `field` ("sensor_type",
// "jnt_type", ...), or nullopt when `field` holds no enumeration. MuJoCo renumbers some
// enumerations between releases (mjtSensor did), so files store these names, never numbers.
inline std::optional<std::string> EnumFieldName(const std::string& field, int value) {
  if (field == "jnt_type") return NameOf(kJointTypes, value);
  if (field == "geom_type") return NameOf(kGeomTypes, value);
  if (field == "sensor_type") return NameOf(kSensorTypes, value);
  if (field == "eq_type") return NameOf(kEqualityTypes, value);
  if (field == "actuator_trntype") return NameOf(kTransmissions, value);
  if (field == "actuator_dyntype") return NameOf(kDynamicsTypes, value);
  if (field == "actuator_gaintype") return NameOf(kGainTypes, value);
  if (field == "actuator_biastype") return NameOf(kBiasTypes, value);
  if (field == "sensor_objtype" || field == "sensor_reftype") {
    const char* name = mju_type2Str(value);
    return name ? std::string(name) : "type " + std::to_string(value);
  }
  return std::nullopt;
}

}  // namespace plumb::compat

#endif  // PLUMB_SRC_CORE_MUJOCO_COMPAT_NAMES_H_
