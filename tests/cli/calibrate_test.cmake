# Runs `glbudget calibrate --sensor cpu --output OUTPUT [ARGS]` and checks the profile it writes
# as load_platform_profile would accept it whole (p_min_w >= 0, p_max_w > p_min_w, every
# saturation count > 0). Its duration is printed, not asserted (a benchmark's figure, not a
# test's: the README gives the measured times).
# cmake -DGLBUDGET=... -DOUTPUT=... [-DARGS=--quick] -P calibrate_test.cmake
file(REMOVE ${OUTPUT})
string(TIMESTAMP started "%s" UTC)
execute_process(COMMAND ${GLBUDGET} calibrate --sensor cpu --output ${OUTPUT} ${ARGS}
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(TIMESTAMP finished "%s" UTC)
math(EXPR seconds "${finished} - ${started}")
message(STATUS "glbudget calibrate ${ARGS}: ${seconds} s\n${out}")
if(NOT status EQUAL 0)
  message(FATAL_ERROR "glbudget calibrate exited with ${status}:\n${err}")
endif()
if(NOT out MATCHES "profile written to ${OUTPUT}")
  message(FATAL_ERROR "glbudget calibrate did not say where the profile went")
endif()
file(READ ${OUTPUT} profile)
string(JSON p_min GET "${profile}" p_min_w)
string(JSON p_max GET "${profile}" p_max_w)
if(NOT p_min GREATER_EQUAL 0 OR NOT p_max GREATER p_min)
  message(FATAL_ERROR "need 0 <= p_min_w < p_max_w, got ${p_min}, ${p_max}")
endif()
foreach(count batches vertices fragments)
  string(JSON value GET "${profile}" saturation ${count})
  if(NOT value GREATER 0)
    message(FATAL_ERROR "saturation.${count} must be > 0, got ${value}")
  endif()
endforeach()
