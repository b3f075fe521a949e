# Runs twinflow and checks that it succeeds. Two forms:
#   cmake -DTWINFLOW=<exe> -DPRM=<scene.prm> -DWORKDIR=<dir> -P check_good_input.cmake
#     runs the scene with `-o WORKDIR/out` (from WORKDIR) and requires exit code 0 and a
#     non-empty WORKDIR/out/fem/summary.json; -DSET=<override> [-DSET2=<override>] add
#     `--set SET --set SET2`, and the summary must match every one of the optional regexes
#     SUMMARY_EXPECT, SUMMARY_EXPECT2;
#   cmake -DTWINFLOW=<exe> -DARGS=<option> -DWORKDIR=<dir> -P check_good_input.cmake
#     runs `TWINFLOW ARGS` (e.g. --help) and requires exit code 0.
# In both forms stdout must match every one of the optional regexes EXPECT, EXPECT2, ...,
# EXPECT5, and the output may not contain a stack trace.
foreach(_var TWINFLOW WORKDIR)
  if(NOT DEFINED ${_var} OR "${${_var}}" STREQUAL "")
    message(FATAL_ERROR "check_good_input.cmake: -D${_var}=... is required")
  endif()
endforeach()
if(DEFINED PRM AND NOT PRM STREQUAL "")
  set(_command "${TWINFLOW}" "${PRM}" -o "${WORKDIR}/out")
  foreach(_var SET SET2)
    if(DEFINED ${_var})
      list(APPEND _command --set "${${_var}}")
    endif()
  endforeach()
elseif(DEFINED ARGS AND NOT ARGS STREQUAL "")
  set(_command "${TWINFLOW}" ${ARGS})
else()
  message(FATAL_ERROR "check_good_input.cmake: -DPRM=... or -DARGS=... is required")
endif()

file(REMOVE_RECURSE "${WORKDIR}")
file(MAKE_DIRECTORY "${WORKDIR}")
execute_process(
  COMMAND ${_command}
  WORKING_DIRECTORY "${WORKDIR}"
  RESULT_VARIABLE _rc
  OUTPUT_VARIABLE _out
  ERROR_VARIABLE _err
  TIMEOUT 100)
string(REPLACE ";" " " _shown "${_command}")
set(_report "command: ${_shown}\nexit code: ${_rc}\n--- stdout ---\n${_out}\n--- stderr ---\n${_err}\n---")

if(NOT _rc STREQUAL "0")
  message(FATAL_ERROR "twinflow failed: exit code ${_rc}, expected 0.\n${_report}")
endif()
string(FIND "${_out}${_err}" "Stacktrace" _pos)
if(NOT _pos EQUAL -1)
  message(FATAL_ERROR "the output contains a stack trace.\n${_report}")
endif()
foreach(_var EXPECT EXPECT2 EXPECT3 EXPECT4 EXPECT5)
  if(DEFINED ${_var} AND NOT "${${_var}}" STREQUAL "")
    string(REGEX MATCH "${${_var}}" _m "${_out}")
    if(_m STREQUAL "")
      message(FATAL_ERROR "stdout does not match <${${_var}}>.\n${_report}")
    endif()
  endif()
endforeach()
if(DEFINED PRM AND NOT PRM STREQUAL "")
  set(_summary "${WORKDIR}/out/fem/summary.json")
  if(NOT EXISTS "${_summary}")
    message(FATAL_ERROR "the run did not write ${_summary}.\n${_report}")
  endif()
  file(SIZE "${_summary}" _size)
  if(_size EQUAL 0)
    message(FATAL_ERROR "${_summary} is empty.\n${_report}")
  endif()
  file(READ "${_summary}" _summary_text)
  foreach(_var SUMMARY_EXPECT SUMMARY_EXPECT2)
    if(DEFINED ${_var} AND NOT "${${_var}}" STREQUAL "")
      string(REGEX MATCH "${${_var}}" _m "${_summary_text}")
      if(_m STREQUAL "")
        message(FATAL_ERROR "${_summary} does not match <${${_var}}>:\n${_summary_text}\n${_report}")
      endif()
    endif()
  endforeach()
endif()
message(STATUS "ok: ${_shown}")
