# Finds what the Python module needs, before the STICKSLIP_BUILD_PYTHON option takes its default:
# pybind11 (Debian python3-pybind11) and an interpreter with development files that imports
# numpy. Without -DPython_EXECUTABLE, the first `python3` on PATH that imports numpy is taken, so
# that a private interpreter earlier on PATH (pyenv, conda) without numpy does not hide Debian's.
set(STICKSLIP_PYTHON_FOUND OFF)
if(NOT Python_EXECUTABLE)
  find_program(_stickslip_path_python python3 NO_CACHE)
  foreach(_candidate IN ITEMS ${_stickslip_path_python} /usr/bin/python3)
    if(EXISTS "${_candidate}")
      execute_process(COMMAND "${_candidate}" -c "import numpy" RESULT_VARIABLE _numpy_status
                      OUTPUT_QUIET ERROR_QUIET)
      if(_numpy_status EQUAL 0)
        set(Python_EXECUTABLE "${_candidate}" CACHE FILEPATH "Python interpreter for the module")
        break()
      endif()
    endif()
  endforeach()
endif()
find_package(Python 3.7 QUIET COMPONENTS Interpreter Development.Module)
if(Python_FOUND)
  # pybind11's own CMake files: Debian installs them where the interpreter's pybind11 says.
  execute_process(COMMAND "${Python_EXECUTABLE}" -c "import pybind11; print(pybind11.get_cmake_dir())"
                  OUTPUT_VARIABLE _pybind11_dir OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  set(PYBIND11_FINDPYTHON ON)
  find_package(pybind11 2.6 CONFIG QUIET HINTS "${_pybind11_dir}")
  execute_process(COMMAND "${Python_EXECUTABLE}" -c "import numpy" RESULT_VARIABLE _numpy_status
                  OUTPUT_QUIET ERROR_QUIET)
  if(pybind11_FOUND AND _numpy_status EQUAL 0)
    set(STICKSLIP_PYTHON_FOUND ON)
  endif()
endif()
