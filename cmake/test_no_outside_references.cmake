# Fails when a file of the repository refers to something outside it: a design document
# that is not part of the clone, or a path that leaves the source tree. A user's clone has
# only what is in the repository, so every reference must point into it (the method is in
# docs/statistics.md, the conventions in docs/design.md, the command line in docs/cli.md,
# the gap diagnosis in docs/gap.md, reference values in the tests that check them).
#
#   cmake -D SOURCE_DIR=/path/to/gmwm -P cmake/test_no_outside_references.cmake
#
# Registered as the test Repository.RefersToNothingOutsideItself; no compilation needed.

cmake_minimum_required(VERSION 3.20)

if(NOT DEFINED SOURCE_DIR)
  get_filename_component(SOURCE_DIR "${CMAKE_CURRENT_LIST_DIR}/.." ABSOLUTE)
endif()

# What is scanned: the sources, tests, tools, docs, data, examples, build scripts and CI.
set(scanned_dirs engine robust selection io tools tests docs data examples cmake .ci)
set(scanned_files README.md CMakeLists.txt)
# Text files only (data/ holds a gzip file; the recordings are not scanned).
set(text_globs *.cc *.h *.hpp *.cpp *.c *.md *.sh *.py *.txt *.cmake *.in *.yaml *.yml
    *.sdf *.xml *.json *.csv *.toml *.cfg)

# A reference to the outside: the external brief's document names (spelled in upper
# case as the brief spells them; the in-repository docs are lower case), and paths into
# the sibling folder that holds it.
# The sibling folder's name is assembled here so that this script itself names no path
# outside the repository.
set(sibling "sha")
string(APPEND sibling "red")
set(patterns
  "STATISTICS\\.md" "DESIGN\\.md" "CLI\\.md" "GAP\\.md" "test_vectors\\.md"
  "performance\\.md" "\\.\\./${sibling}" "${sibling}/spec" "${sibling}/reference")

# Allowed exceptions, as "path|text the line contains". Each is code, not a reference to
# read: the default location of the real IMU recordings, used only when the environment
# variable GMWM_SHARED_DATA is not set. The recordings are not shipped with the project,
# so CI and the benchmark drivers need a place to look by default; the documentation
# describes it as "the folder named by GMWM_SHARED_DATA". (tests/support/test_support.cc
# and tools/bench/bench_common.h build the same default from path components.)
set(allowed
  ".ci/run|GMWM_SHARED_DATA:-$(pwd)/../${sibling}/data"
  "tools/bench/run_all.sh|data=\${GMWM_SHARED_DATA:-$(pwd)/../${sibling}/data}"
  "tools/bench/gap_real.py|os.environ.get(\"GMWM_SHARED_DATA\", os.path.join(os.path.dirname(__file__), \"../../../${sibling}/data\"))")
# This script names the patterns it looks for.
set(skipped_files cmake/test_no_outside_references.cmake)

# A tracked symbolic link is checked before anything is read: one that leaves the
# repository (an absolute target, or a relative one climbing out of it) fails the test by
# name, whether or not its target exists on this machine (a link into /tmp once made a fresh
# clone fail here on the dangling link instead).
set(links_outside)
set(tracked_links)
find_program(GIT_EXECUTABLE git)
if(GIT_EXECUTABLE AND EXISTS "${SOURCE_DIR}/.git")
  execute_process(COMMAND "${GIT_EXECUTABLE}" -C "${SOURCE_DIR}" ls-files --stage
                  OUTPUT_VARIABLE staged RESULT_VARIABLE git_rc ERROR_QUIET)
  if(git_rc EQUAL 0)
    string(REPLACE "\n" ";" staged_lines "${staged}")
    foreach(entry IN LISTS staged_lines)
      if(entry MATCHES "^120000 [0-9a-f]+ [0-9]\t(.*)$")
        set(link "${CMAKE_MATCH_1}")
        list(APPEND tracked_links "${link}")
        file(READ_SYMLINK "${SOURCE_DIR}/${link}" target)
        if(IS_ABSOLUTE "${target}")
          set(resolved "${target}")
        else()
          get_filename_component(link_dir "${SOURCE_DIR}/${link}" DIRECTORY)
          get_filename_component(resolved "${link_dir}/${target}" ABSOLUTE)
        endif()
        file(RELATIVE_PATH inside "${SOURCE_DIR}" "${resolved}")
        if(IS_ABSOLUTE "${target}" OR inside MATCHES "^\\.\\.(/|$)")
          list(APPEND links_outside "${link} -> ${target}")
        endif()
      endif()
    endforeach()
  endif()
endif()
if(links_outside)
  list(LENGTH links_outside n)
  string(REPLACE ";" "\n  " listing "${links_outside}")
  message(FATAL_ERROR
    "${n} tracked symbolic link(s) leaving the repository (a clone elsewhere has nothing there; "
    "remove them from git and ignore the path instead):\n  ${listing}")
endif()

set(files)
foreach(d IN LISTS scanned_dirs)
  if(IS_DIRECTORY "${SOURCE_DIR}/${d}")
    set(globs)
    foreach(g IN LISTS text_globs)
      list(APPEND globs "${SOURCE_DIR}/${d}/${g}")
    endforeach()
    file(GLOB_RECURSE found RELATIVE "${SOURCE_DIR}" ${globs})
    list(APPEND files ${found})
    # Extension-less scripts (.ci/run).
    file(GLOB_RECURSE all RELATIVE "${SOURCE_DIR}" "${SOURCE_DIR}/${d}/*")
    foreach(f IN LISTS all)
      get_filename_component(name "${f}" NAME)
      if(NOT name MATCHES "\\.")
        list(APPEND files "${f}")
      endif()
    endforeach()
  endif()
endforeach()
foreach(f IN LISTS scanned_files)
  if(EXISTS "${SOURCE_DIR}/${f}")
    list(APPEND files "${f}")
  endif()
endforeach()
list(REMOVE_DUPLICATES files)
list(REMOVE_ITEM files ${skipped_files})
# Links are not read (those inside the repository point at files scanned in their own
# place), nor is anything that is not a regular file (an untracked dangling link, say).
set(readable)
foreach(f IN LISTS files)
  if(NOT IS_SYMLINK "${SOURCE_DIR}/${f}" AND NOT IS_DIRECTORY "${SOURCE_DIR}/${f}" AND EXISTS "${SOURCE_DIR}/${f}")
    list(APPEND readable "${f}")
  endif()
endforeach()
set(files ${readable})
list(SORT files)

string(JOIN "|" pattern_regex ${patterns})
set(hits)
set(used_allowances)
list(LENGTH files n_files)
foreach(f IN LISTS files)
  file(READ "${SOURCE_DIR}/${f}" content)
  if(NOT content MATCHES "${pattern_regex}")
    continue()
  endif()
  # One line at a time. Semicolons, backslashes and square brackets have a meaning in
  # CMake lists (they would split or join lines), so they are masked first.
  string(REPLACE "\\" "<backslash>" content "${content}")
  string(REPLACE ";" "<semicolon>" content "${content}")
  string(REPLACE "[" "<lbracket>" content "${content}")
  string(REPLACE "]" "<rbracket>" content "${content}")
  string(REPLACE "\n" ";" lines "${content}")
  set(line_no 0)
  foreach(line IN LISTS lines)
    math(EXPR line_no "${line_no} + 1")
    if(NOT line MATCHES "${pattern_regex}")
      continue()
    endif()
    string(REPLACE "<semicolon>" ";" line "${line}")
    string(REPLACE "<lbracket>" "[" line "${line}")
    string(REPLACE "<rbracket>" "]" line "${line}")
    string(REPLACE "<backslash>" "\\" line "${line}")
    set(is_allowed FALSE)
    foreach(a IN LISTS allowed)
      string(FIND "${a}" "|" bar)
      string(SUBSTRING "${a}" 0 ${bar} a_file)
      math(EXPR text_start "${bar} + 1")
      string(SUBSTRING "${a}" ${text_start} -1 a_text)
      string(FIND "${line}" "${a_text}" at)
      if(f STREQUAL a_file AND NOT at EQUAL -1)
        set(is_allowed TRUE)
        list(APPEND used_allowances "${a}")
      endif()
    endforeach()
    if(NOT is_allowed)
      string(STRIP "${line}" shown)
      list(APPEND hits "${f}:${line_no}: ${shown}")
    endif()
  endforeach()
endforeach()

if(n_files LESS 50)
  message(FATAL_ERROR "only ${n_files} files found under ${SOURCE_DIR}: is SOURCE_DIR the source tree?")
endif()

# An exception that no longer matches anything is stale: remove it from `allowed`, so the
# list says exactly what is allowed.
set(stale)
foreach(a IN LISTS allowed)
  if(NOT a IN_LIST used_allowances)
    list(APPEND stale "${a}")
  endif()
endforeach()
if(stale)
  string(REPLACE ";" "\n  " listing "${stale}")
  message(FATAL_ERROR "allowed exception(s) matching no line any more; remove them:\n  ${listing}")
endif()

if(hits)
  list(LENGTH hits n)
  string(REPLACE ";" "\n  " listing "${hits}")
  message(FATAL_ERROR
    "${n} reference(s) to something outside the repository (point them at docs/ or at the "
    "tests instead):\n  ${listing}")
endif()
message(STATUS "no references outside the repository in ${n_files} files")
