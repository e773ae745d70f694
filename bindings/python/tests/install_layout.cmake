# The package as a wheel lays it out (cmake --install --component python): rtdenoise/ with the
# module and the libraries beside it. It must import and denoise with nothing on LD_LIBRARY_PATH.
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --component python --prefix ${WORK_DIR}
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "install of component python failed")
endif()
set(ENV{LD_LIBRARY_PATH} "")
set(ENV{PYTHONPATH} ${WORK_DIR})
execute_process(COMMAND ${PYTHON} -c
  "import numpy as np, rtdenoise, os; assert os.path.dirname(rtdenoise.__file__) == '${WORK_DIR}/rtdenoise', rtdenoise.__file__; c = np.full((4, 8, 3), 0.5, np.float32); out = rtdenoise.Device('cpu').create_denoiser('accumulate').denoise(color=c); assert np.allclose(out, 0.5); print('installed package ok', rtdenoise.__version__)"
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(rc)
  message(FATAL_ERROR "the installed package does not work:\n${out}")
endif()
message(STATUS "${out}")
