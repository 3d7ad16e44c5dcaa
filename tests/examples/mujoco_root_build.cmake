# Builds examples/01_hello against a MuJoCo "release folder" (include/mujoco/*.h,
# lib/libmujoco.so) given with -DMUJOCO_ROOT, the way a MuJoCo 3.x user builds: here the
# folder is assembled from the files of the MuJoCo plumb is built with (a copy of the
# library, so the system path cannot stand in for it). Checks the RPATH points into the
# folder and the loader takes MuJoCo from there, without LD_LIBRARY_PATH.
file(REMOVE_RECURSE "${WORK_DIR}")
set(root "${WORK_DIR}/mujoco-release")
file(MAKE_DIRECTORY "${root}/include" "${root}/lib")
file(CREATE_LINK "${MUJOCO_INCLUDE}/mujoco" "${root}/include/mujoco" SYMBOLIC)
# the library under its real (SONAME) name, as a release folder has it, and the link
# the linker looks for
file(REAL_PATH "${MUJOCO_LIBRARY}" real_library)
get_filename_component(real_name "${real_library}" NAME)
file(COPY "${real_library}" DESTINATION "${root}/lib")
file(CREATE_LINK "${real_name}" "${root}/lib/libmujoco.so" SYMBOLIC)
execute_process(
  COMMAND ${CMAKE_COMMAND} -S "${SOURCE_DIR}/examples/01_hello" -B "${WORK_DIR}/build"
    -DCMAKE_BUILD_TYPE=Release -DMUJOCO_ROOT=${root}
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc OR NOT out MATCHES "MuJoCo from MUJOCO_ROOT")
  message(FATAL_ERROR "configuring with MUJOCO_ROOT failed:\n${out}\n${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build "${WORK_DIR}/build" RESULT_VARIABLE rc
  OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "building with MUJOCO_ROOT failed")
endif()
execute_process(COMMAND readelf -d "${WORK_DIR}/build/hello" OUTPUT_VARIABLE dynamic)
if(NOT dynamic MATCHES "${root}/lib")
  message(FATAL_ERROR "hello has no RPATH into ${root}/lib:\n${dynamic}")
endif()
# the loader finds MuJoCo in the folder itself, not on the system path
execute_process(COMMAND ldd "${WORK_DIR}/build/hello" OUTPUT_VARIABLE linked)
if(NOT linked MATCHES "libmujoco[^\n]*=> ${root}/lib/")
  message(FATAL_ERROR "hello does not load MuJoCo from ${root}/lib:\n${linked}")
endif()
execute_process(COMMAND "${WORK_DIR}/build/hello" "${SOURCE_DIR}/models/pendulum.xml"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(rc OR NOT out MATCHES "^t= 0.10 q=0.65403 dq=-0.89118\n")
  message(FATAL_ERROR "hello built with MUJOCO_ROOT printed:\n${out}")
endif()
# a folder that is not a release is refused with a clear message
execute_process(
  COMMAND ${CMAKE_COMMAND} -S "${SOURCE_DIR}/examples/01_hello" -B "${WORK_DIR}/bad"
    -DMUJOCO_ROOT=${WORK_DIR}/nowhere
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
# CMake wraps a FATAL_ERROR message at a width that depends on the path in it: compare the
# text with every run of white space folded to one space
string(REGEX REPLACE "[ \t\r\n]+" " " err_flat "${err}")
if(NOT rc OR NOT err_flat MATCHES "does not look like a MuJoCo release folder")
  message(FATAL_ERROR "a bad MUJOCO_ROOT was not refused clearly:\n${err}")
endif()
# plumb's own build finds the same folder and puts it in the RPATH
execute_process(
  COMMAND ${CMAKE_COMMAND} -S "${SOURCE_DIR}" -B "${WORK_DIR}/plumb" -DMUJOCO_ROOT=${root}
    -DPLUMB_BUILD_TESTS=OFF -DPLUMB_BUILD_BENCHMARKS=OFF -DPLUMB_BUILD_EXAMPLES=OFF
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc OR NOT out MATCHES "MuJoCo from MUJOCO_ROOT")
  message(FATAL_ERROR "configuring plumb with MUJOCO_ROOT failed:\n${out}\n${err}")
endif()
file(READ "${WORK_DIR}/plumb/CMakeCache.txt" cache)
if(NOT cache MATCHES "PLUMB_MUJOCO_LIBDIR:INTERNAL=${root}/lib")
  message(FATAL_ERROR "plumb's RPATH folder is not the MUJOCO_ROOT library folder")
endif()
