# Finds what the Python module needs: a Python 3 interpreter with its development headers,
# numpy for that interpreter, and pybind11's CMake package. Sets SPHRAY_PYTHON_DEPS_FOUND and,
# when something is missing, SPHRAY_PYTHON_MISSING (what, for the message).
#
# The interpreter is /usr/bin/python3 unless Python_EXECUTABLE says otherwise: Debian's numpy,
# pybind11 and pytest belong to the system Python, and a python3 earlier on PATH (pyenv, a
# virtualenv) would lack them.
if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "The Python the sphray module is built for")
endif()
set(SPHRAY_PYTHON_MISSING "")
find_package(Python 3.8 COMPONENTS Interpreter Development.Module QUIET)
if(NOT Python_FOUND)
  list(APPEND SPHRAY_PYTHON_MISSING "Python 3 headers (python3-dev)")
else()
  execute_process(COMMAND ${Python_EXECUTABLE} -c "import numpy"
                  RESULT_VARIABLE sphray_no_numpy OUTPUT_QUIET ERROR_QUIET)
  if(sphray_no_numpy)
    list(APPEND SPHRAY_PYTHON_MISSING "numpy for ${Python_EXECUTABLE} (python3-numpy)")
  endif()
  set(PYBIND11_FINDPYTHON ON)
  find_package(pybind11 2.6 CONFIG QUIET)
  if(NOT pybind11_FOUND)
    list(APPEND SPHRAY_PYTHON_MISSING "pybind11 (pybind11-dev)")
  endif()
endif()
if(SPHRAY_PYTHON_MISSING)
  set(SPHRAY_PYTHON_DEPS_FOUND OFF)
else()
  set(SPHRAY_PYTHON_DEPS_FOUND ON)
endif()
