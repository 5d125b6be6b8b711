# `cmake --install` and `cpack -G DEB` (issue 16). Included from cli/CMakeLists.txt, after
# interpose/ and testapps/ have defined their targets. The layout is the one shim_path.cpp
# searches relative to the installed command, so the install runs from any prefix:
#
#   bin/glbudget                                 the command
#   bin/glbudget-demo                            the demo renderer (testapps/demo)
#   lib/<multiarch>/glbudget/libglbudget.so      the shim `glbudget run` preloads
#   lib/<multiarch>/glbudget/calibrate_load      the load `glbudget calibrate` measures
#   share/glbudget/examples/demo/                the demo's manifest (glbudget.toml, manifest/*.frag)
#
# <multiarch> is CMAKE_LIBRARY_ARCHITECTURE (x86_64-linux-gnu on Debian amd64), the same value
# cli/CMakeLists.txt compiles in as GLBUDGET_MULTIARCH; lib/glbudget/ without one. Nothing
# links against our own shared libraries, so no RPATH is needed (CMake drops the build tree's
# on install; tests/install checks that none remains).
if(CMAKE_LIBRARY_ARCHITECTURE)
  set(GLBUDGET_INSTALL_PKGLIBDIR lib/${CMAKE_LIBRARY_ARCHITECTURE}/glbudget)
else()
  set(GLBUDGET_INSTALL_PKGLIBDIR lib/glbudget)
endif()
set(GLBUDGET_INSTALL_BINDIR bin)  # fixed: shim_path.cpp looks in bin/../lib/...
set(GLBUDGET_INSTALL_EXAMPLESDIR ${CMAKE_INSTALL_DATADIR}/glbudget/examples)

install(TARGETS glbudget_cli RUNTIME DESTINATION ${GLBUDGET_INSTALL_BINDIR})
if(TARGET glbudget)
  install(TARGETS glbudget LIBRARY DESTINATION ${GLBUDGET_INSTALL_PKGLIBDIR})
endif()
if(TARGET calibrate_load)
  install(TARGETS calibrate_load RUNTIME DESTINATION ${GLBUDGET_INSTALL_PKGLIBDIR})
endif()
if(TARGET demo)
  # install(TARGETS) cannot rename. The demo links only system libraries, so its build tree
  # binary carries no RPATH to drop; `--strip` (and CPACK_STRIP_FILES) reach it through this code.
  install(PROGRAMS $<TARGET_FILE:demo> DESTINATION ${GLBUDGET_INSTALL_BINDIR} RENAME glbudget-demo)
  if(CMAKE_STRIP)
    install(CODE "if(CMAKE_INSTALL_DO_STRIP)
  execute_process(COMMAND \"${CMAKE_STRIP}\" \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/${GLBUDGET_INSTALL_BINDIR}/glbudget-demo\")
endif()")
  endif()
endif()
install(FILES ${PROJECT_SOURCE_DIR}/testapps/demo/glbudget.toml DESTINATION ${GLBUDGET_INSTALL_EXAMPLESDIR}/demo)
# The worked example for a program nobody here wrote (README, "A worked example: glmark2").
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/glmark2 DESTINATION ${GLBUDGET_INSTALL_EXAMPLESDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/testapps/demo/manifest DESTINATION ${GLBUDGET_INSTALL_EXAMPLESDIR}/demo)

# The Debian package: `cpack -G DEB` in the build directory writes glbudget_<version>_<arch>.deb.
set(GLBUDGET_PACKAGE_MAINTAINER "glbudget maintainers <glbudget@localhost>" CACHE STRING
    "Maintainer field of the Debian package")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME glbudget)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR glbudget)
set(CPACK_PACKAGE_CONTACT "${GLBUDGET_PACKAGE_MAINTAINER}")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "keep unmodified OpenGL applications inside a power budget")
set(CPACK_PACKAGE_DESCRIPTION [[glbudget is a library preloaded into unmodified OpenGL applications: it counts
each frame's work per pass, joins it with measured power and, under a power
budget, draws the configuration of best image quality that keeps the budget.
The glbudget command runs an application under it (glbudget run), calibrates
a machine (glbudget calibrate), replays frame logs and writes reports.
Includes the six-pass demo renderer (glbudget-demo) and its example manifest
in /usr/share/glbudget/examples/demo.]])
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)  # no debug info (and with it no build-tree paths) in the package
set(CPACK_DEBIAN_PACKAGE_NAME glbudget)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${GLBUDGET_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
find_program(GLBUDGET_DPKG_SHLIBDEPS dpkg-shlibdeps)
mark_as_advanced(GLBUDGET_DPKG_SHLIBDEPS)
# `glbudget report` runs share/glbudget/glbudget_report.py with python3 (standard library only).
if(GLBUDGET_DPKG_SHLIBDEPS)
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)  # the libraries' packages, added to the list below
  set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3")
else()
  # What dpkg-shlibdeps computes on Debian 12 (bookworm), amd64.
  set(CPACK_DEBIAN_PACKAGE_DEPENDS
      "python3, libc6 (>= 2.36), libegl1, libgcc-s1 (>= 3.0), libglew2.2 (>= 2.2.0), libglx0, libhwy1 (>= 0.16.0), libopengl0, libopenimageio2.4 (>= 2.4.7.1), libstdc++6 (>= 11), libx11-6")
endif()
set(CPACK_SOURCE_GENERATOR TGZ)
set(CPACK_SOURCE_IGNORE_FILES "/[.]git/" "/build[^/]*/" "/out/")
include(CPack)
