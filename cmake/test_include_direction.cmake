# One floor per module: a module includes only the public headers of the modules below it
# (docs/library.md, "Modules"). Run as a test:
#   cmake -D SOURCE_DIR=... -P cmake/test_include_direction.cmake
# Fails listing every file:line whose #include "gmwm/<module>/..." climbs a floor.
#
#   engine                              (Eigen, TBB, spdlog, Boost.Math, NLopt)
#   robust -> engine
#   selection, gap -> robust, engine    (beside each other, never including each other)
#   nav -> engine
#   stability -> engine                 (the frequency-stability deviations)
#   io (readers and writers) -> engine  (file formats in both directions)
#   pipeline -> io, selection, gap, nav, stability, robust, engine
#   fleet -> pipeline and below         (many recordings of many units: tasks, records, cache)
#   report -> fleet and below           (JSON, HTML, terminal: every rendering)
#   serve -> report and below           (the web app: an HTTP face over the studies and renderings)
#   tools/gmwm, python -> anything      (the faces)
cmake_minimum_required(VERSION 3.22)
if(NOT SOURCE_DIR)
  message(FATAL_ERROR "give -D SOURCE_DIR=<the repository>")
endif()

set(_allowed_engine engine)
set(_allowed_robust engine robust)
set(_allowed_selection engine robust selection)
set(_allowed_gap engine robust gap)
set(_allowed_nav engine nav)
set(_allowed_stability engine stability)
set(_allowed_io engine io)
set(_allowed_pipeline engine robust selection gap nav stability io pipeline)
set(_allowed_fleet engine robust selection gap nav stability io pipeline fleet)
set(_allowed_report engine robust selection gap nav stability io pipeline fleet report)
set(_allowed_serve engine robust selection gap nav stability io pipeline fleet report serve)
set(_modules engine robust selection gap nav stability io pipeline fleet report serve)

set(_violations "")
set(_checked 0)
foreach(_mod IN LISTS _modules)
  file(GLOB_RECURSE _files ${SOURCE_DIR}/${_mod}/*.h ${SOURCE_DIR}/${_mod}/*.cc)
  foreach(_f IN LISTS _files)
    math(EXPR _checked "${_checked} + 1")
    file(STRINGS ${_f} _lines REGEX "^[ \t]*#[ \t]*include[ \t]*[\"<]gmwm/[a-z_]+/")
    foreach(_l IN LISTS _lines)
      string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*[\"<]gmwm/([a-z_]+)/.*" "\\1" _target "${_l}")
      if(NOT _target IN_LIST _allowed_${_mod})
        file(RELATIVE_PATH _rel ${SOURCE_DIR} ${_f})
        string(APPEND _violations "  ${_rel} (module ${_mod}): ${_l}\n")
      endif()
    endforeach()
  endforeach()
endforeach()

if(_checked LESS 50)
  message(FATAL_ERROR "include direction: only ${_checked} files found under ${SOURCE_DIR}; wrong SOURCE_DIR?")
endif()
if(_violations)
  message(FATAL_ERROR "include direction: these includes climb a floor (a lower module includes a higher one):\n${_violations}")
endif()
message(STATUS "include direction: ${_checked} files, every include on its floor or below")
