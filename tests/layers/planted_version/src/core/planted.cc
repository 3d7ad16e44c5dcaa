// A version comparison outside core/mujoco_compat.h: tests/mujoco_versions_in_compat.sh must
// refuse it (the test MujocoVersionsAreComparedInCompatOnly). Never compiled.
bool kNew = mjVERSION_HEADER >= 3005000;
