# Test: install gmwm into a fresh prefix, build examples/ against it with find_package(gmwm)
# and with pkg-config, and run both programs. Arguments (-D): BUILD_DIR, SOURCE_DIR, WORK_DIR,
# and the build's GENERATOR, MAKE_PROGRAM and CXX_COMPILER (the example is built with them: a
# machine set up by tools/setup.sh has ninja and no make).
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(f include/gmwm/version.h include/gmwm/engine/fit.h include/gmwm/report/html_report.h include/gmwm/gap/gap.h
          lib/cmake/gmwm/gmwmConfig.cmake lib/cmake/gmwm/gmwmConfigVersion.cmake lib/cmake/gmwm/gmwmTargets.cmake
          lib/pkgconfig/gmwm.pc bin/gmwm share/doc/gmwm/LICENSE share/man/man1/gmwm.1
          share/bash-completion/completions/gmwm)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()
file(GLOB sonames ${prefix}/lib/libgmwm_engine.so.*)
if(NOT sonames)
  message(FATAL_ERROR "no versioned libgmwm_engine.so.* installed")
endif()

# find_package(gmwm): the imported targets carry their include folders and dependencies.
set(generator_args)
if(GENERATOR)
  list(APPEND generator_args -G ${GENERATOR})
endif()
if(MAKE_PROGRAM)
  list(APPEND generator_args -DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM})
endif()
if(CXX_COMPILER)
  list(APPEND generator_args -DCMAKE_CXX_COMPILER=${CXX_COMPILER})
endif()
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples -B ${WORK_DIR}/build ${generator_args} -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_BUILD_TYPE=Release)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/fit_example)
message(STATUS "${run_output}")

# pkg-config: the same program from the .pc file alone.
find_program(PKG_CONFIG pkg-config)
if(PKG_CONFIG)
  set(ENV{PKG_CONFIG_PATH} ${prefix}/lib/pkgconfig)
  run(${PKG_CONFIG} --cflags --libs gmwm)
  string(STRIP "${run_output}" flags)
  separate_arguments(flags UNIX_COMMAND "${flags}")
  if(NOT CXX_COMPILER)
    set(CXX_COMPILER c++)
  endif()
  run(${CXX_COMPILER} -std=c++20 -O1 ${SOURCE_DIR}/examples/fit_example.cc -o ${WORK_DIR}/fit_example_pc ${flags}
      -Wl,-rpath,${prefix}/lib)
  run(${WORK_DIR}/fit_example_pc)
endif()

# The installed program runs from its prefix (its RPATH finds the installed libraries).
run(${prefix}/bin/gmwm --version)
