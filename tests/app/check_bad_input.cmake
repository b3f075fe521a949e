# Runs twinflow on a bad scene file and checks that it fails cleanly:
#   cmake -DTWINFLOW=<exe> -DPRM=<scene.prm> -DEXPECT=<regex> -DWORKDIR=<dir>
#         [-DPREFIX=<regex>] [-DSET=<override>] -P check_bad_input.cmake
# Before the run, WORKDIR/out/fem/previous_result.csv is written with a marker (the results
# of an earlier run). twinflow is then run as `TWINFLOW PRM -o WORKDIR/out` (with
# `--set SET` added when SET is given: a bad command-line override) from WORKDIR and
#  - its exit code must be a non-zero number (not a crash by signal),
#  - stderr must match PREFIX (default: the input-error prefix) and EXPECT: the message names
#    the entry and states what is allowed,
#  - neither stdout nor stderr may contain a stack trace or deal.II's exception banner,
#  - the marker file must be unchanged and no file or folder may appear in WORKDIR (the
#    results written so far stay intact and nothing half-written is left behind).
foreach(_var TWINFLOW PRM EXPECT WORKDIR)
  if(NOT DEFINED ${_var} OR "${${_var}}" STREQUAL "")
    message(FATAL_ERROR "check_bad_input.cmake: -D${_var}=... is required")
  endif()
endforeach()
if(NOT DEFINED PREFIX)
  set(PREFIX "twinflow: input error: ")
endif()

# A fresh work directory holding the results of an "earlier run".
file(REMOVE_RECURSE "${WORKDIR}")
set(_marker_file "${WORKDIR}/out/fem/previous_result.csv")
set(_marker "# marker written by check_bad_input.cmake: earlier results, must survive\ntime,value\n0,1\n1,2\n")
file(WRITE "${_marker_file}" "${_marker}")
file(GLOB_RECURSE _before LIST_DIRECTORIES true RELATIVE "${WORKDIR}" "${WORKDIR}/*")
list(SORT _before)

set(_command "${TWINFLOW}" "${PRM}" -o "${WORKDIR}/out")
set(_shown "${TWINFLOW} ${PRM} -o ${WORKDIR}/out")
if(DEFINED SET)
  list(APPEND _command --set "${SET}")
  string(APPEND _shown " --set '${SET}'")
endif()
execute_process(
  COMMAND ${_command}
  WORKING_DIRECTORY "${WORKDIR}"
  RESULT_VARIABLE _rc
  OUTPUT_VARIABLE _out
  ERROR_VARIABLE _err
  TIMEOUT 100)

set(_report "command: ${_shown}\nexit code: ${_rc}\n--- stdout ---\n${_out}\n--- stderr ---\n${_err}\n---")

if(NOT _rc MATCHES "^[0-9]+$")
  message(FATAL_ERROR "twinflow did not exit normally (crash, signal or timeout) on a bad input.\n${_report}")
endif()
if(_rc EQUAL 0)
  message(FATAL_ERROR "twinflow accepted a bad input: exit code 0, expected non-zero.\n${_report}")
endif()

string(REGEX MATCH "${PREFIX}" _m "${_err}")
if(_m STREQUAL "")
  message(FATAL_ERROR "stderr does not match the expected prefix <${PREFIX}>.\n${_report}")
endif()
string(REGEX MATCH "${EXPECT}" _m "${_err}")
if(_m STREQUAL "")
  message(FATAL_ERROR "the error message does not match <${EXPECT}>: it must name the entry "
                      "and state what is allowed.\n${_report}")
endif()

foreach(_noise "Stacktrace" "An error occurred in line" "Additional information:" "terminate called")
  string(FIND "${_out}${_err}" "${_noise}" _pos)
  if(NOT _pos EQUAL -1)
    message(FATAL_ERROR "the output contains '${_noise}': the message must be a clean "
                        "input error, not a raw exception.\n${_report}")
  endif()
endforeach()

if(NOT EXISTS "${_marker_file}")
  message(FATAL_ERROR "earlier result ${_marker_file} was deleted by the failed run.\n${_report}")
endif()
file(READ "${_marker_file}" _after_marker)
if(NOT _after_marker STREQUAL _marker)
  message(FATAL_ERROR "earlier result ${_marker_file} was modified by the failed run:\n"
                      "${_after_marker}\n${_report}")
endif()
file(GLOB_RECURSE _after LIST_DIRECTORIES true RELATIVE "${WORKDIR}" "${WORKDIR}/*")
list(SORT _after)
if(NOT _after STREQUAL _before)
  set(_new ${_after})
  list(REMOVE_ITEM _new ${_before})
  message(FATAL_ERROR "the failed run created files in ${WORKDIR}: ${_new}\n${_report}")
endif()

message(STATUS "ok: exit code ${_rc}, message: ${_err}")
