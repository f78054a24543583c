# cmake -P script (the python_package test): acuity as a user installs it with pip. A fresh venv
# (Debian's python3-venv; --system-site-packages for numpy and dask) in WORK_DIR, then
# `pip install --no-index --no-build-isolation PACKAGE_DIR` (nothing from an index), then
# tests/python_package/check_installed.py run by the venv's python from WORK_DIR, PYTHONPATH unset.
#   PYTHON  Debian's python3   PACKAGE_DIR  <build>/python   CHECK  check_installed.py
#   TESTS_PYTHON  tests/python (helpers)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
function(run)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=PYTHONPATH ${ARGN} WORKING_DIRECTORY ${WORK_DIR}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  message("${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}")
  endif()
endfunction()
run(${PYTHON} -m venv --system-site-packages ${WORK_DIR}/venv)
run(${WORK_DIR}/venv/bin/python -m pip install --no-index --no-build-isolation --no-cache-dir ${PACKAGE_DIR})
run(${WORK_DIR}/venv/bin/python -m pip show acuity)
run(${WORK_DIR}/venv/bin/python ${CHECK} ${TESTS_PYTHON} ${WORK_DIR})
