# cmake -DMODE=prefix|deb -DBINARY_DIR=... -DSOURCE_DIR=... -DWORK=... -DVERSION=...
#       -DMULTIARCH=... -DCPACK=... -DSTRIP=... -DPROFILE=... -P install_test.cmake
#
# prefix: `cmake --install BINARY_DIR --prefix WORK/prefix`, checked from WORK/prefix.
# deb:    `cpack -G DEB` into WORK/package, `dpkg -x` into WORK/root, checked from WORK/root/usr.
# Checks: the layout; no RPATH/RUNPATH but $ORIGIN-relative ones and no build-tree path in the
# binaries; the installed `glbudget run` preloads the installed shim and runs the installed demo
# (exit 0, rows in the log), under `--power 50%` with the installed example manifest (a `select` or `explore`
# decision or a configuration other than the best in the log); `glbudget calibrate --quick`
# finds the installed calibration load and writes a profile. Writes only under WORK.
cmake_minimum_required(VERSION 3.20)

foreach(v MODE BINARY_DIR SOURCE_DIR WORK VERSION PROFILE)
  if(NOT DEFINED ${v} OR "${${v}}" STREQUAL "")
    message(FATAL_ERROR "install_test: -D${v}=... is required")
  endif()
endforeach()
if(MULTIARCH)
  set(pkglibdir lib/${MULTIARCH}/glbudget)
else()
  set(pkglibdir lib/glbudget)
endif()

function(fail)
  string(JOIN "" text ${ARGN})
  message(FATAL_ERROR "install_test: FAILED: ${text}")
endfunction()

function(skip)
  string(JOIN "" text ${ARGN})
  message("install_test: SKIPPED: ${text}")
endfunction()

# run(<name> <command...>): runs it, output to WORK/<name>.out, fails unless it exits 0.
function(run name)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out
                  TIMEOUT 75 WORKING_DIRECTORY ${WORK})
  file(WRITE ${WORK}/${name}.out "${out}")
  string(JOIN " " command ${ARGN})
  if(NOT rc STREQUAL "0")
    fail("${name}: exit ${rc}: ${command}\n${out}")
  endif()
  message(STATUS "${name}: ok: ${command}")
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

# Nothing from the caller's environment may point glbudget elsewhere or change what it does.
foreach(v GLBUDGET_SHIM GLBUDGET_CALIBRATE_LOAD GLBUDGET_PROFILE GLBUDGET_CONFIG GLBUDGET_POWER
          GLBUDGET_ERROR GLBUDGET_FORCE GLBUDGET_FORCE_EVERY GLBUDGET_FPS GLBUDGET_DUMP
          GLBUDGET_INSTRUMENT GLBUDGET_LOG GLBUDGET_SENSOR GLBUDGET_SELECT_FRAMES
          GLBUDGET_TRANSITION_S LD_PRELOAD)
  unset(ENV{${v}})
endforeach()
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/config ${WORK}/cache)
set(ENV{XDG_CONFIG_HOME} ${WORK}/config)  # no default manifest from the user's config
set(ENV{XDG_CACHE_HOME} ${WORK}/cache)    # no default profile from the user's cache

# --- Install -----------------------------------------------------------------------------
if(MODE STREQUAL "prefix")
  run(install ${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${WORK}/prefix)
  set(root ${WORK}/prefix)
elseif(MODE STREQUAL "deb")
  find_program(DPKG dpkg)
  find_program(DPKG_DEB dpkg-deb)
  if(NOT CPACK OR NOT EXISTS "${CPACK}")
    skip("no cpack (CMAKE_CPACK_COMMAND '${CPACK}'): the Debian package is not built or checked")
    return()
  endif()
  if(NOT DPKG OR NOT DPKG_DEB)
    skip("no dpkg/dpkg-deb on this machine: the Debian package is not built or checked")
    return()
  endif()
  execute_process(COMMAND ${CPACK} --config ${BINARY_DIR}/CPackConfig.cmake -G DEB -B ${WORK}/package
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out TIMEOUT 75 WORKING_DIRECTORY ${WORK})
  file(WRITE ${WORK}/cpack.out "${out}")
  if(NOT rc STREQUAL "0")
    # dpkg-shlibdeps fails for libraries that no installed package provides (a locally built
    # OpenImageIO or GLEW): the machine's, not the package's, problem. Anything else fails.
    if(out MATCHES "dpkg-shlibdeps: error|no dependency information found|couldn't find library")
      skip("cpack -G DEB failed for an environmental reason (dpkg-shlibdeps cannot map a library "
           "to a package here); output:\n${out}")
      return()
    endif()
    fail("cpack -G DEB: exit ${rc}\n${out}")
  endif()
  message(STATUS "cpack: ok")
  file(GLOB debs ${WORK}/package/glbudget_*.deb)
  list(LENGTH debs n)
  if(NOT n EQUAL 1)
    fail("expected one glbudget_*.deb in ${WORK}/package, found ${n}: ${debs}\n${out}")
  endif()
  file(SIZE ${debs} deb_size)
  run(deb_info ${DPKG_DEB} --info ${debs})
  set(info "${run_output}")
  foreach(field "Package: glbudget" "Version: ${VERSION}" "Maintainer: " "Description: " "Depends: ")
    string(FIND "${info}" " ${field}" at)
    if(at LESS 0)
      fail("the package's control has no '${field}':\n${info}")
    endif()
  endforeach()
  run(deb_contents ${DPKG_DEB} --contents ${debs})
  message(STATUS "${debs}: ${deb_size} bytes\n${info}${run_output}")
  run(deb_extract ${DPKG} -x ${debs} ${WORK}/root)
  set(root ${WORK}/root/usr)
else()
  message(FATAL_ERROR "install_test: MODE must be prefix or deb, not '${MODE}'")
endif()

# --- Layout ------------------------------------------------------------------------------
set(cli ${root}/bin/glbudget)
set(demo ${root}/bin/glbudget-demo)
set(shim ${root}/${pkglibdir}/libglbudget.so)
set(load ${root}/${pkglibdir}/calibrate_load)
set(examples ${root}/share/glbudget/examples/demo)
foreach(f ${cli} ${demo} ${shim} ${load} ${examples}/glbudget.toml ${examples}/manifest/ssr_off.frag
          ${examples}/manifest/fxaa_off.frag ${root}/share/glbudget/examples/glmark2/glmark2.toml
          ${root}/share/glbudget/examples/glmark2/shaders/gouraud4.vert)
  if(NOT EXISTS ${f})
    file(GLOB_RECURSE present RELATIVE ${root} ${root}/*)
    string(JOIN "\n  " present ${present})
    fail("not installed: ${f}; under ${root}:\n  ${present}")
  endif()
endforeach()

# --- Relocatable binaries ----------------------------------------------------------------
# RPATH/RUNPATH: none, or only $ORIGIN-relative entries.
find_program(READELF readelf)
if(READELF)
  foreach(f ${cli} ${demo} ${shim} ${load})
    execute_process(COMMAND ${READELF} -d ${f} OUTPUT_VARIABLE dyn RESULT_VARIABLE rc)
    string(REGEX MATCHALL "\\((RPATH|RUNPATH)\\)[^\n]*\\[[^]\n]*\\]" paths "${dyn}")
    foreach(p ${paths})
      string(REGEX REPLACE ".*\\[([^]]*)\\]" "\\1" p "${p}")
      string(REPLACE ":" ";" entries "${p}")
      foreach(e ${entries})
        if(NOT e MATCHES "^\\$ORIGIN")
          fail("${f} has RPATH/RUNPATH entry '${e}' (only $ORIGIN-relative ones would be relocatable)")
        endif()
      endforeach()
    endforeach()
  endforeach()
  message(STATUS "rpath: none but $ORIGIN-relative")
else()
  message("install_test: no readelf: RPATH/RUNPATH not checked")
endif()
# No build-tree path in what the binaries load (debug info, which names the build directory, is
# stripped from a copy first). Source-tree paths may be compiled in as fallbacks that the
# installed program looks past: listed here, and each must start with one of `allowed` (the
# compiler may store a literal in pieces, so a hit can hold part of a path and other text).
set(allowed "/cli/report/")  # glbudget_report.py: report_command.cpp tries bin/../share/glbudget/ first
string(REGEX REPLACE "([][+.*()^$?|\\\\])" "\\\\\\1" binary_re "${BINARY_DIR}")
string(REGEX REPLACE "([][+.*()^$?|\\\\])" "\\\\\\1" source_re "${SOURCE_DIR}")
foreach(f ${cli} ${demo} ${shim} ${load})
  get_filename_component(name ${f} NAME)
  set(scan ${f})
  if(STRIP)
    set(scan ${WORK}/stripped-${name})
    execute_process(COMMAND ${STRIP} --strip-debug -o ${scan} ${f} RESULT_VARIABLE rc)
    if(NOT rc STREQUAL "0")
      fail("${STRIP} --strip-debug ${f}: exit ${rc}")
    endif()
  endif()
  file(STRINGS ${scan} hits REGEX "${binary_re}|${source_re}")
  foreach(h ${hits})
    string(FIND "${h}" "${BINARY_DIR}" in_binary)
    if(in_binary GREATER_EQUAL 0)
      fail("${f} names the build directory: '${h}'")
    endif()
    set(ok FALSE)
    string(FIND "${h}" "${SOURCE_DIR}" at)
    string(SUBSTRING "${h}" ${at} -1 tail)
    foreach(a ${allowed})
      string(FIND "${tail}" "${SOURCE_DIR}${a}" start)
      if(start EQUAL 0)
        set(ok TRUE)
      endif()
    endforeach()
    if(NOT ok)
      fail("${f} names the source tree: '${h}' (not a known fallback: ${allowed})")
    endif()
    message(STATUS "${name}: source-tree fallback compiled in, not used when installed: ${h}")
  endforeach()
endforeach()

# --- Running from the installed tree -------------------------------------------------------
# The installed command preloads the installed shim (found relative to itself), and
# GLBUDGET_SHIM overrides it.
file(REAL_PATH ${shim} shim_real)
run(run_preload ${cli} run -- sh -c "echo preload=\$LD_PRELOAD")
if(NOT run_output MATCHES "preload=([^\n]*)")
  fail("`glbudget run -- sh` printed no preload line:\n${run_output}")
endif()
if(NOT CMAKE_MATCH_1 STREQUAL shim_real)
  fail("the installed glbudget preloads '${CMAKE_MATCH_1}', not the installed shim ${shim_real}")
endif()
set(ENV{GLBUDGET_SHIM} ${WORK}/elsewhere/libglbudget.so)
run(run_shim_override ${cli} run -- sh -c "echo preload=\$LD_PRELOAD")
unset(ENV{GLBUDGET_SHIM})
string(FIND "${run_output}" "preload=${WORK}/elsewhere/libglbudget.so" at)
if(at LESS 0)
  fail("GLBUDGET_SHIM did not override the shim's path:\n${run_output}")
endif()

# log_rows(<log> <rows_var> <header_var>): the log's data rows and its header as lists.
function(log_rows log rows_var header_var)
  if(NOT EXISTS ${log})
    fail("no log written: ${log}")
  endif()
  file(STRINGS ${log} lines)
  list(LENGTH lines n)
  if(n LESS 2)
    fail("${log} has no rows")
  endif()
  list(GET lines 0 header)
  if(NOT header MATCHES "^frame,")
    fail("${log}: not a frame log: ${header}")
  endif()
  string(REPLACE "," ";" header "${header}")
  list(REMOVE_AT lines 0)
  set(${rows_var} "${lines}" PARENT_SCOPE)
  set(${header_var} "${header}" PARENT_SCOPE)
endfunction()

set(size --width 160 --height 90 --detail 0.05)
run(demo_plain ${cli} run --log ${WORK}/plain.csv -- ${demo} --frames 20 ${size})
log_rows(${WORK}/plain.csv rows header)
list(LENGTH rows n)
if(n LESS 20)
  fail("plain run: ${n} rows for 20 frames")
endif()
message(STATUS "plain run: ${n} rows")

# Governed: fitted after about 30 frames with power; the first selection waits for a 1-s window
# of measured power at the best configuration (at this size 20-40 frames, fewer on a loaded
# machine), so 120 frames leave room for it.
run(demo_governed ${cli} run --log ${WORK}/governed.csv --config ${examples}/glbudget.toml --power 50%
    --profile ${PROFILE} --sensor cpu -- ${demo} --frames 120 ${size})
log_rows(${WORK}/governed.csv rows header)
list(FIND header decision decision_at)
list(FIND header configuration configuration_at)
if(decision_at LESS 0 OR configuration_at LESS 0)
  fail("governed run: no decision/configuration column: ${header}")
endif()
set(selects 0)
set(cheaper 0)
set(configurations "")
foreach(row ${rows})
  string(REPLACE "," ";" fields "${row}")
  list(GET fields ${decision_at} decision)
  list(GET fields ${configuration_at} configuration)
  if(decision STREQUAL "select" OR decision STREQUAL "explore")
    math(EXPR selects "${selects} + 1")
  endif()
  if(configuration MATCHES "[1-9]")
    math(EXPR cheaper "${cheaper} + 1")
  endif()
  list(APPEND configurations ${configuration})
endforeach()
list(REMOVE_DUPLICATES configurations)
string(JOIN " " configurations ${configurations})
list(LENGTH rows n)
# Six levels a configuration: the installed example manifest (all six passes) was read.
if(NOT configurations MATCHES "(^| )[0-9]+:[0-9]+:[0-9]+:[0-9]+:[0-9]+:[0-9]+( |$)")
  fail("governed run: configurations ${configurations} are not the demo manifest's six passes")
endif()
if(selects EQUAL 0 AND cheaper EQUAL 0)
  fail("governed run: no `select` or `explore` decision and no configuration but the best in ${n} rows "
       "(configurations ${configurations})\n${run_output}")
endif()
message(STATUS "governed run: ${n} rows, ${selects} with decision select, ${cheaper} drawn cheaper; "
               "configurations ${configurations}")

# `glbudget calibrate` finds calibrate_load in the installed tree.
run(calibrate ${cli} calibrate --quick --sensor cpu --output ${WORK}/cpu.profile.json)
if(NOT EXISTS ${WORK}/cpu.profile.json)
  fail("calibrate wrote no profile:\n${run_output}")
endif()
file(READ ${WORK}/cpu.profile.json profile)
if(NOT profile MATCHES "\"p_max_w\"")
  fail("calibrate's profile has no p_max_w:\n${profile}")
endif()
message(STATUS "calibrate: profile written by the installed command")
message("install_test: PASSED (${MODE}, from ${root})")
