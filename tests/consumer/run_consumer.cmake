# Installs the build tree into a scratch prefix, then uses the installed package three ways:
# the CMake consumer project (tests/consumer: a C++ and a C program), the same two programs built
# with plain compiler commands through pkg-config, and the installed `rtdenoise` command; no
# LD_LIBRARY_PATH anywhere.
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(rc)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}")
  endif()
  message(STATUS "${what}: ${out}")
endfunction()
# Nothing may come from the build tree or the environment's library path.
set(ENV{LD_LIBRARY_PATH} "")
run("install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

run("configure of the consumer" ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/build -G ${GENERATOR}
    -DCMAKE_PREFIX_PATH=${prefix})
run("build of the consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run("consumer" ${WORK_DIR}/build/consumer)
run("C consumer" ${WORK_DIR}/build/c_consumer)

# pkg-config: the .pc files of the scratch prefix only. The C++ API needs -std=c++20 (the
# .pc file's cxx_standard variable says so); the C program needs nothing.
set(ENV{PKG_CONFIG_PATH} "")
set(ENV{PKG_CONFIG_LIBDIR} ${prefix}/lib/pkgconfig)
foreach(var cxx_standard vulkan libdir)
  execute_process(COMMAND pkg-config --variable=${var} rtdenoise OUTPUT_VARIABLE value RESULT_VARIABLE rc
                  OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(rc)
    message(FATAL_ERROR "pkg-config --variable=${var} rtdenoise failed")
  endif()
  set(pc_${var} ${value})
endforeach()
if(NOT pc_cxx_standard STREQUAL "20")
  message(FATAL_ERROR "rtdenoise.pc: cxx_standard is '${pc_cxx_standard}'")
endif()
if(NOT pc_vulkan STREQUAL EXPECT_VULKAN)
  message(FATAL_ERROR "rtdenoise.pc: vulkan is '${pc_vulkan}', the build says '${EXPECT_VULKAN}'")
endif()
run("pkg-config C++ consumer" sh -c
    "${CXX} -std=c++${pc_cxx_standard} -DCONSUMER_PACKAGE_VULKAN=${EXPECT_VULKAN_01} ${SOURCE_DIR}/main.cpp -o ${WORK_DIR}/pc_consumer \$(pkg-config --cflags --libs rtdenoise rtdenoise-eval ${EXTRA_PC}) -Wl,-rpath,${pc_libdir} && ${WORK_DIR}/pc_consumer")

run("pkg-config C consumer" sh -c
    "${CC} -std=c99 ${SOURCE_DIR}/consumer.c -o ${WORK_DIR}/pc_c_consumer \$(pkg-config --cflags --libs rtdenoise) -lm -Wl,-rpath,${pc_libdir} && ${WORK_DIR}/pc_c_consumer")

run("installed rtdenoise --version" ${prefix}/bin/rtdenoise --version)
run("installed rtdenoise methods" ${prefix}/bin/rtdenoise methods)
