# Installs plumb into a scratch prefix and builds a small project that uses it with
# find_package(plumb), then runs that project's program and the installed CLI.
file(REMOVE_RECURSE "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")
execute_process(COMMAND ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}"
  RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "cmake --install failed")
endif()
execute_process(
  COMMAND ${CMAKE_COMMAND} -S "${SOURCE_DIR}/tests/install/consumer" -B "${WORK_DIR}/consumer"
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc)
  message(FATAL_ERROR "configuring a find_package(plumb) project failed:\n${out}\n${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build "${WORK_DIR}/consumer"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc)
  message(FATAL_ERROR "building a find_package(plumb) project failed:\n${out}\n${err}")
endif()
execute_process(COMMAND "${WORK_DIR}/consumer/consumer" "${prefix}/share/plumb/models/pendulum.xml"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(rc OR NOT out MATCHES "q\\(0.5\\) = -0.16156")
  message(FATAL_ERROR "the consumer printed:\n${out}")
endif()
execute_process(COMMAND "${prefix}/bin/plumb" --version RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(rc OR NOT out MATCHES "plumb")
  message(FATAL_ERROR "the installed plumb CLI failed: ${out}")
endif()
