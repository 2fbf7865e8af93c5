# Steps of the package test (run with cmake -P), chosen by STEP:
#   install:   fresh install of the build tree into PREFIX (the client library's headers and
#              fq.proto too, and, when PYTHON is set, an `import fq` from the installed module)
#   cmake:     configure and build tests/package/consumer against PREFIX with find_package(fq)
#   pkgconfig: compile the same consumer with `pkg-config --cflags --libs fq`
#   producer_cmake, producer_pkgconfig: the same two ways for tests/package/producer, which
#              uses the wire format alone (fq::wire, fq-wire.pc): its link line and its shared
#              libraries must name neither the engines, OpenMP nor the CUDA runtime
#   client_cmake: configure and build clients/examples against PREFIX with
#              find_package(fq COMPONENTS client); their link line must name no engine either
#   client_pkgconfig: compile clients/examples/consumer.cpp with `pkg-config --cflags --libs
#              fq-client` (client_examples.sh runs both against the installed fqd)
#   no_component: find_package(fq COMPONENTS nosuch) fails, naming the component
# The cmake and pkgconfig steps then run the consumer on MESH and check that it printed the
# vertex count of MESH's PLY header and moved the vertices; the producer steps run the
# producer, which encodes a frame, reads it back and checks it.
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    list(JOIN ARGN " " cmd)
    message(FATAL_ERROR "'${cmd}' failed (${rc}):\n${out}\n${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

function(check_consumer exe)
  run("${exe}" "${MESH}")
  file(STRINGS "${MESH}" header REGEX "^element vertex [0-9]+" LIMIT_COUNT 1)
  string(REGEX REPLACE "^element vertex " "" expected "${header}")
  if(NOT out MATCHES "\nvertices ${expected}\n" OR out MATCHES "\nmoved 0\n")
    message(FATAL_ERROR "consumer printed:\n${out}\nexpected ${expected} vertices, moved")
  endif()
  message(STATUS "${out}")
endfunction()

# Fails when `text` (what `what` is) names a library that a wire-only program must not link.
function(check_wire_only what text)
  foreach(forbidden fq_kernels fq_io fq_eval cudart gomp fopenmp assimp)
    if(text MATCHES "${forbidden}")
      message(FATAL_ERROR "the producer's ${what} names '${forbidden}':\n${text}")
    endif()
  endforeach()
endfunction()

function(check_producer exe)
  run(ldd "${exe}")
  check_wire_only("shared libraries" "${out}")
  run("${exe}")
  if(NOT out MATCHES "round trip ok")
    message(FATAL_ERROR "producer printed:\n${out}")
  endif()
  message(STATUS "${out}")
endfunction()

# pkg-config finds the .pc files of the fresh install.
function(use_installed_pc_files)
  file(GLOB_RECURSE pc "${PREFIX}/fq.pc")
  get_filename_component(pc_dir "${pc}" DIRECTORY)
  set(ENV{PKG_CONFIG_PATH} "${pc_dir}")
endfunction()

# Configures and builds the project in `dir` against PREFIX into `work`: the link line of its
# program `exe` must name lib<lib>.a and nothing a wire-only program must not link.
function(build_wire_only dir exe lib)
  file(REMOVE_RECURSE "${work}")
  run("${CMAKE_COMMAND}" -S "${dir}" -B "${work}" -G "${GENERATOR}"
      -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${PREFIX}" "-DCMAKE_CXX_COMPILER=${CXX}")
  run("${CMAKE_COMMAND}" --build "${work}" --verbose)
  string(REGEX MATCH "[^\n]*-o ${exe} [^\n]*" link_line "${out}")
  if(NOT link_line MATCHES "lib${lib}\\.a")
    message(FATAL_ERROR "no link line of ${exe} with lib${lib}.a in:\n${out}")
  endif()
  check_wire_only("link line" "${link_line}")
endfunction()

# Compiles `source` into `work`/`exe` with the flags of `pkg-config --cflags --libs <module>`,
# which must name nothing a wire-only program must not link.
function(compile_wire_only module source exe)
  file(REMOVE_RECURSE "${work}")
  file(MAKE_DIRECTORY "${work}")
  use_installed_pc_files()
  run(pkg-config --cflags --libs ${module})
  check_wire_only("pkg-config flags" "${out}")
  separate_arguments(flags UNIX_COMMAND "${out}")
  run("${CXX}" "${source}" -o "${work}/${exe}" ${flags})
endfunction()

set(work "${WORK}/${STEP}")
if(STEP STREQUAL "install")
  file(REMOVE_RECURSE "${PREFIX}")
  run("${CMAKE_COMMAND}" --install "${BUILD}" --prefix "${PREFIX}")
  foreach(f include/fq/kernels/engine.h include/fq/common/version.h include/fq/wire/fq.pb.h
            include/fq/clients/common/frame_sender.h include/fq/clients/common/result_receiver.h
            share/fq/fq.proto)
    if(NOT EXISTS "${PREFIX}/${f}")
      message(FATAL_ERROR "${f} not installed")
    endif()
  endforeach()
  if(EXISTS "${PREFIX}/include/fq/clients/common/mesh_source.h")
    message(FATAL_ERROR "the tools' own mesh_source.h is installed with the client library")
  endif()
  if(PYTHON)
    run("${CMAKE_COMMAND}" -E env "PYTHONPATH=${PREFIX}/${PYTHON_DIR}" "${PYTHON}" -c
        "import fq, os; assert fq.__file__.startswith(os.environ['PYTHONPATH']), fq.__file__; print(fq.__version__)")
  endif()
elseif(STEP STREQUAL "cmake")
  file(REMOVE_RECURSE "${work}")
  run("${CMAKE_COMMAND}" -S "${SOURCE}/tests/package/consumer" -B "${work}" -G "${GENERATOR}"
      -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${PREFIX}" "-DCMAKE_CXX_COMPILER=${CXX}")
  run("${CMAKE_COMMAND}" --build "${work}")
  check_consumer("${work}/fq_consumer")
elseif(STEP STREQUAL "pkgconfig")
  file(REMOVE_RECURSE "${work}")
  file(MAKE_DIRECTORY "${work}")
  use_installed_pc_files()
  run(pkg-config --cflags --libs fq)
  separate_arguments(flags UNIX_COMMAND "${out}")
  run("${CXX}" "${SOURCE}/tests/package/consumer/main.cpp" -o "${work}/fq_consumer" ${flags})
  check_consumer("${work}/fq_consumer")
elseif(STEP STREQUAL "producer_cmake")
  build_wire_only("${SOURCE}/tests/package/producer" fq_producer fq_wire)
  check_producer("${work}/fq_producer")
elseif(STEP STREQUAL "producer_pkgconfig")
  compile_wire_only(fq-wire "${SOURCE}/tests/package/producer/main.cpp" fq_producer)
  check_producer("${work}/fq_producer")
elseif(STEP STREQUAL "client_cmake")
  build_wire_only("${SOURCE}/clients/examples" producer fq_client)
elseif(STEP STREQUAL "client_pkgconfig")
  compile_wire_only(fq-client "${SOURCE}/clients/examples/consumer.cpp" consumer)
elseif(STEP STREQUAL "no_component")
  file(REMOVE_RECURSE "${work}")
  file(WRITE "${work}/src/CMakeLists.txt" "cmake_minimum_required(VERSION 3.25)\nproject(p LANGUAGES CXX)\n"
             "find_package(fq CONFIG REQUIRED COMPONENTS client nosuch)\n")
  execute_process(COMMAND "${CMAKE_COMMAND}" -S "${work}/src" -B "${work}/build"
                          "-DCMAKE_PREFIX_PATH=${PREFIX}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0 OR NOT err MATCHES "fq has no component 'nosuch'")
    message(FATAL_ERROR "find_package(fq COMPONENTS nosuch) gave ${rc}:\n${out}\n${err}")
  endif()
else()
  message(FATAL_ERROR "unknown STEP '${STEP}'")
endif()
