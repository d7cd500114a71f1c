# Finds what the Python module (python/) builds with: Python 3's interpreter and development
# files, and pybind11 (Debian's pybind11-dev, or PyPI's in a pip build). Sets IGI_PYTHON_MODULE
# to whether the module is built; without them the module and its test are skipped, saying why.
# A pip build (scikit-build-core sets SKBUILD) is nothing but the module, so there they are required.
set(IGI_PYTHON_MODULE OFF)
# The tests run with the interpreter found here: Debian's, for which scripts/deps.sh installs numpy
# and pytest, unless one is named (-DPython3_EXECUTABLE=...) or pip builds the module for its own.
if(NOT DEFINED Python3_EXECUTABLE AND NOT SKBUILD AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3)
endif()
find_package(Python3 3.9 COMPONENTS Interpreter Development.Module)
if(Python3_FOUND)
  find_package(pybind11 2.6 CONFIG QUIET)
endif()
if(Python3_FOUND AND pybind11_FOUND)
  set(IGI_PYTHON_MODULE ON)
elseif(SKBUILD)
  message(FATAL_ERROR "igi: the Python module needs Python 3's development files and pybind11")
else()
  set(IGI_PYTHON_MISSING "Python 3 development files (python3-dev) or pybind11 (pybind11-dev) not found")
  message(STATUS "igi: ${IGI_PYTHON_MISSING} - skipping the Python module (bash scripts/deps.sh installs them)")
endif()
