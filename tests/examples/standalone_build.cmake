# Builds examples/01_hello on its own, as a reader of the chapter would, runs it on the
# chapter's pendulum and checks its first printed line.
file(REMOVE_RECURSE "${WORK_DIR}")
execute_process(
  COMMAND ${CMAKE_COMMAND} -S "${SOURCE_DIR}/examples/01_hello" -B "${WORK_DIR}"
    -DCMAKE_BUILD_TYPE=Release -DMUJOCO_ROOT=${MUJOCO_ROOT}
  RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "configuring examples/01_hello on its own failed")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build "${WORK_DIR}" RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "building examples/01_hello on its own failed")
endif()
execute_process(COMMAND "${WORK_DIR}/hello" "${SOURCE_DIR}/models/pendulum.xml"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(rc OR NOT out MATCHES "^t= 0.10 q=0.65403 dq=-0.89118\n")
  message(FATAL_ERROR "the standalone hello printed:\n${out}")
endif()
